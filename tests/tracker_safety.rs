//! Faults, recoveries, wind stow and mode selection.

use sun_algos::UtcTime;
use suntracker::config::{Config, WindConfig};
use suntracker::safety::{
    select_mode, AxisId, Fault, FaultManager, Mode, ModeInputs, Recovery, Sensor, WindMonitor,
};

fn t0() -> UtcTime {
    "2026-03-01T10:00:00Z".parse().unwrap()
}
fn at(s: i64) -> UtcTime {
    t0().add_seconds(s).unwrap()
}

#[test]
fn every_fault_has_its_recovery() {
    let r = 3;
    // Transient sensor faults: retry, then open loop.
    for f in [
        Fault::SensorTimeout(Sensor::Inclinometer),
        Fault::I2cError(Sensor::Compass),
        Fault::SensorTimeout(Sensor::Encoder(AxisId::A)),
    ] {
        assert_eq!(f.recovery(1, r), Recovery::Retry);
        assert_eq!(f.recovery(3, r), Recovery::Retry);
        assert_eq!(f.recovery(4, r), Recovery::DegradeOpenLoop);
    }
    assert_eq!(Fault::GpsLost.recovery(1, r), Recovery::UseRtcAndStoredSite);
    assert_eq!(Fault::RtcInvalid.recovery(1, r), Recovery::WaitForGps);
    let st = Fault::MotorStalled(AxisId::C);
    assert_eq!(st.recovery(1, r), Recovery::Retry);
    assert_eq!(st.recovery(4, r), Recovery::DegradeOneAxis(AxisId::C));
    let dev = Fault::SetPointDeviation(AxisId::A);
    assert_eq!(dev.recovery(1, r), Recovery::Rehome(AxisId::A));
    assert_eq!(dev.recovery(4, r), Recovery::DegradeOneAxis(AxisId::A));
    let lim = Fault::LimitSwitchHit(AxisId::C);
    assert_eq!(lim.recovery(1, r), Recovery::Rehome(AxisId::C));
    assert_eq!(lim.recovery(4, r), Recovery::StopSafely);
}

#[test]
fn manager_counts_raised_and_recovered() {
    let mut m = FaultManager::new(Config::default().safety);
    let f = Fault::MotorStalled(AxisId::A);
    for k in 1..=3 {
        assert_eq!(m.raise(f, at(k)), Recovery::Retry);
    }
    assert_eq!(m.raise(f, at(4)), Recovery::DegradeOneAxis(AxisId::A));
    assert!(m.axis_disabled(AxisId::A));
    assert!(!m.axis_disabled(AxisId::C));
    assert_eq!(m.raised, 1);
    assert!(m.clear(f));
    assert!(!m.clear(f));
    assert_eq!(m.recovered, 1);
    assert_eq!(m.active_count(), 0);
    // A limit switch hit over and over ends in a safe stop until reset.
    let l = Fault::LimitSwitchHit(AxisId::C);
    for k in 0..4 {
        m.raise(l, at(10 + k));
    }
    assert!(m.must_stop());
    assert_eq!(
        select_mode(&ModeInputs {
            must_stop: m.must_stop(),
            ..Default::default()
        }),
        Mode::SafeStop
    );
    m.reset();
    assert!(!m.must_stop());
    assert_eq!(m.raised, 2);
    assert_eq!(m.recovered, 2);
    // RTC invalid: time unknown.
    m.raise(Fault::RtcInvalid, at(20));
    assert!(m.time_unknown());
    // Full list: still answered, counted as dropped.
    for s in [
        Sensor::Inclinometer,
        Sensor::Compass,
        Sensor::Gps,
        Sensor::Rtc,
    ] {
        m.raise(Fault::SensorTimeout(s), at(21));
        m.raise(Fault::I2cError(s), at(21));
    }
    assert!(m.dropped > 0);
    assert_eq!(m.active_count(), suntracker::safety::MAX_ACTIVE);
}

fn wind() -> WindConfig {
    WindConfig {
        threshold_hz: 25.0,
        hold_s: 3,
        release_s: 600,
    }
}

#[test]
fn wind_stow_needs_the_hold_time() {
    let mut w = WindMonitor::new(wind());
    // A 2-second gust above the threshold does not stow.
    assert!(!w.update_pulses(at(0), 30, 1.0));
    assert!(!w.update_pulses(at(1), 30, 1.0));
    assert!(!w.update_pulses(at(2), 10, 1.0));
    // Sustained: stows once 3 s have passed above the threshold.
    assert!(!w.update_pulses(at(3), 30, 1.0));
    assert!(!w.update_pulses(at(4), 30, 1.0));
    assert!(!w.update_pulses(at(5), 30, 1.0));
    assert!(w.update_pulses(at(6), 30, 1.0));
    assert_eq!(w.stow_count, 1);
    // Exactly at the threshold counts as calm.
    assert!(w.update_pulses(at(7), 25, 1.0));
    // Calm, but a gust inside the release time restarts the count.
    assert!(w.update_pulses(at(300), 5, 1.0));
    assert!(w.update_pulses(at(400), 40, 1.0));
    assert!(w.update_pulses(at(401), 5, 1.0));
    assert!(w.update_pulses(at(1000), 5, 1.0));
    assert!(!w.update_pulses(at(1001), 5, 1.0));
    assert_eq!(w.stow_count, 1);
}

#[test]
fn wind_bad_inputs_fail_safe() {
    let mut w = WindMonitor::new(wind());
    // A zero interval is ignored.
    assert!(!w.update_pulses(at(0), 1000, 0.0));
    // A NaN rate counts as windy.
    w.update_rate(at(0), f32::NAN);
    assert!(w.update_rate(at(5), f32::NAN));
}

#[test]
fn mode_priorities() {
    let all = ModeInputs {
        must_stop: true,
        wind_stow: true,
        command_stow: true,
        manual: true,
        time_unknown: true,
        night: true,
    };
    assert_eq!(select_mode(&all), Mode::SafeStop);
    let i = ModeInputs {
        must_stop: false,
        ..all
    };
    assert_eq!(select_mode(&i), Mode::WindStow);
    let i = ModeInputs {
        wind_stow: false,
        ..i
    };
    assert_eq!(select_mode(&i), Mode::CommandStow);
    let i = ModeInputs {
        command_stow: false,
        ..i
    };
    assert_eq!(select_mode(&i), Mode::Manual);
    let i = ModeInputs { manual: false, ..i };
    assert_eq!(select_mode(&i), Mode::WaitForTime);
    let i = ModeInputs {
        time_unknown: false,
        ..i
    };
    assert_eq!(select_mode(&i), Mode::Night);
    let i = ModeInputs { night: false, ..i };
    assert_eq!(select_mode(&i), Mode::Tracking);
}
