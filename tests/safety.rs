//! Faults, recoveries, wind stow and mode selection.

use suntracker::config::{Config, WindConfig};
use suntracker::safety::{
    clear_sky_ghi_w_m2, retry_backoff_ms, select_mode, AxisId, Fault, FaultManager, Mode,
    ModeInputs, OvercastMonitor, Reading, Recovery, Sensor, StowInputs, WeatherModes, WeatherStow,
    WindMonitor, RECURRENCE_WINDOW_MS,
};

/// Monotonic milliseconds (the firmware's 32-bit clock) at `s` seconds
/// after boot.
fn at(s: u32) -> u32 {
    s * 1000
}

/// The 32-bit clock `s` seconds after `start_ms`, wrapping as a board's.
fn after(start_ms: u32, s: u32) -> u32 {
    start_ms.wrapping_add(s * 1000)
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
    // A motor that does not move, meets an obstacle, is moved by one or
    // runs too slowly:
    // retried, then that axis is left alone.
    for ax in [AxisId::C, AxisId::A] {
        for st in [
            Fault::MotorStalled(ax),
            Fault::Obstruction(ax),
            Fault::UnexpectedMotion(ax),
            Fault::MoveTimeout(ax),
        ] {
            assert_eq!(st.recovery(1, r), Recovery::Retry);
            assert_eq!(st.recovery(3, r), Recovery::Retry);
            assert_eq!(st.recovery(4, r), Recovery::DegradeOneAxis(ax));
        }
    }
    let dev = Fault::SetPointDeviation(AxisId::A);
    assert_eq!(dev.recovery(1, r), Recovery::Rehome(AxisId::A));
    assert_eq!(dev.recovery(4, r), Recovery::DegradeOneAxis(AxisId::A));
    let lim = Fault::LimitSwitchHit(AxisId::C);
    assert_eq!(lim.recovery(1, r), Recovery::Rehome(AxisId::C));
    assert_eq!(lim.recovery(4, r), Recovery::StopSafely);
}

/// Every fault's log name by the scheme docs/src/reliability.md gives
/// (`timeout_*`, `bus_*`, `motor_stalled_c/a`, `deviation_c/a`,
/// `limit_switch_c/a`, the others as listed there), built here from the
/// parts, and every mode's name as the log documents it (src/log.rs).
#[test]
fn every_fault_and_mode_has_its_documented_name() {
    let sensors = [
        (Sensor::Inclinometer, "inclinometer"),
        (Sensor::Compass, "compass"),
        (Sensor::Encoder(AxisId::C), "encoder_c"),
        (Sensor::Encoder(AxisId::A), "encoder_a"),
        (Sensor::Rtc, "rtc"),
        (Sensor::Gps, "gps"),
    ];
    let mut expected: Vec<(Fault, String)> = Vec::new();
    for (s, word) in sensors {
        expected.push((Fault::SensorTimeout(s), format!("timeout_{word}")));
        expected.push((Fault::I2cError(s), format!("bus_{word}")));
    }
    for (a, letter) in [(AxisId::C, "c"), (AxisId::A, "a")] {
        expected.push((Fault::MotorStalled(a), format!("motor_stalled_{letter}")));
        expected.push((Fault::SetPointDeviation(a), format!("deviation_{letter}")));
        expected.push((Fault::LimitSwitchHit(a), format!("limit_switch_{letter}")));
        expected.push((Fault::Obstruction(a), format!("obstruction_{letter}")));
        expected.push((
            Fault::UnexpectedMotion(a),
            format!("unexpected_motion_{letter}"),
        ));
        expected.push((Fault::MoveTimeout(a), format!("move_timeout_{letter}")));
    }
    for (f, name) in [
        (Fault::GpsLost, "gps_lost"),
        (Fault::RtcInvalid, "rtc_invalid"),
        (Fault::GpsTimeImplausible, "gps_time_implausible"),
        (Fault::GpsTimeUnstable, "gps_time_unstable"),
        (Fault::GpsPositionUnstable, "gps_position_unstable"),
        (Fault::TimeOutOfRange, "time_out_of_range"),
        (Fault::ScheduleFailed, "schedule_failed"),
        (Fault::SupplyReading, "supply_reading"),
        (Fault::IrradianceReading, "irradiance_reading"),
    ] {
        expected.push((f, name.to_string()));
    }
    assert_eq!(expected.len(), 33);
    for (f, name) in &expected {
        assert_eq!(f.name(), name.as_str(), "{f:?}");
    }
    for (m, name) in [
        (Mode::Service, "service"),
        (Mode::SafeStop, "safe_stop"),
        (Mode::WindStow, "wind_stow"),
        (Mode::HailStow, "hail_stow"),
        (Mode::ExternalStow, "external_stow"),
        (Mode::SnowStow, "snow_stow"),
        (Mode::LowSupplyStow, "low_supply_stow"),
        (Mode::CommandStow, "command_stow"),
        (Mode::Manual, "manual"),
        (Mode::WaitForTime, "wait_for_time"),
        (Mode::Night, "night"),
        (Mode::Homing, "homing"),
        (Mode::Overcast, "overcast"),
        (Mode::Unwind, "unwind"),
        (Mode::Tracking, "tracking"),
    ] {
        assert_eq!(m.name(), name, "{m:?}");
    }
}

#[test]
fn manager_counts_raised_and_recovered() {
    let mut m = FaultManager::new(Config::default().safety);
    let f = Fault::MotorStalled(AxisId::A);
    // Attempts count once per back-off (10 s, 20 s, 40 s): reported every
    // second, the fault stays at its first attempt for 10 s.
    for k in 0..10 {
        assert_eq!(m.raise(f, at(k)), Recovery::Retry);
    }
    assert_eq!(m.get(f).unwrap().attempts, 1);
    for k in [10, 30] {
        assert_eq!(m.raise(f, at(k)), Recovery::Retry);
    }
    assert_eq!(m.raise(f, at(69)), Recovery::Retry);
    assert_eq!(m.raise(f, at(70)), Recovery::DegradeOneAxis(AxisId::A));
    assert!(m.axis_disabled(AxisId::A));
    assert!(!m.axis_disabled(AxisId::C));
    assert_eq!(m.raised, 1);
    assert!(m.clear(f, at(71)));
    assert!(!m.clear(f, at(71)));
    assert_eq!(m.recovered, 1);
    assert_eq!(m.active_count(), 0);
    // A limit switch hit over and over ends in a safe stop until reset.
    let l = Fault::LimitSwitchHit(AxisId::C);
    for k in [100, 110, 130, 170] {
        m.raise(l, at(k));
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
    m.raise(Fault::RtcInvalid, at(200));
    assert!(m.time_unknown());
    // Full list: still answered, counted as dropped.
    for s in [
        Sensor::Inclinometer,
        Sensor::Compass,
        Sensor::Gps,
        Sensor::Rtc,
    ] {
        m.raise(Fault::SensorTimeout(s), at(201));
        m.raise(Fault::I2cError(s), at(201));
    }
    assert!(m.dropped > 0);
    assert_eq!(m.active_count(), suntracker::safety::MAX_ACTIVE);
}

fn wind() -> WindConfig {
    WindConfig {
        threshold_hz: 25.0,
        hold_s: 3,
        release_s: 600,
        m_s_per_hz: 0.0,
    }
}

#[test]
fn wind_stow_needs_the_hold_time() {
    let mut w = WindMonitor::new(wind());
    // Pulses counted over 1-second intervals ending at each time.
    // A 2-second gust above the threshold (seconds 0..2) does not stow.
    assert!(!w.update_pulses(at(1), 30, 1000));
    assert!(!w.update_pulses(at(2), 30, 1000));
    assert!(!w.update_pulses(at(3), 10, 1000));
    // Sustained from second 3: stows once 3 s have passed above it.
    assert!(!w.update_pulses(at(4), 30, 1000));
    assert!(!w.update_pulses(at(5), 30, 1000));
    assert!(w.update_pulses(at(6), 30, 1000));
    assert_eq!(w.stow_count, 1);
    // Exactly at the threshold counts as calm.
    assert!(w.update_pulses(at(7), 25, 1000));
    // Calm, but a gust inside the release time restarts the count.
    assert!(w.update_pulses(at(300), 5, 1000));
    assert!(w.update_pulses(at(400), 40, 1000));
    // Calm from second 400 (the interval ending at 401): released 600 s
    // later.
    assert!(w.update_pulses(at(401), 5, 1000));
    assert!(w.update_pulses(at(999), 5, 1000));
    assert!(!w.update_pulses(at(1000), 5, 1000));
    assert_eq!(w.stow_count, 1);
}

#[test]
fn wind_bad_inputs_fail_safe() {
    let mut w = WindMonitor::new(wind());
    // A zero interval is ignored.
    assert!(!w.update_pulses(at(0), 1000, 0));
    // A NaN rate counts as windy.
    w.update_rate(at(1), 1000, f32::NAN);
    assert!(w.update_rate(at(5), 1000, f32::NAN));
}

#[test]
fn mode_priorities() {
    let all = ModeInputs {
        service: true,
        must_stop: true,
        wind_stow: true,
        weather: WeatherModes {
            hail: true,
            external: true,
            snow: true,
            low_supply: true,
            supply_fault: false,
        },
        command_stow: true,
        manual: true,
        time_unknown: true,
        night: true,
        unhomed: true,
        overcast: true,
    };
    // The service lock above everything, a gale and a fault stop included.
    assert_eq!(select_mode(&all), Mode::Service);
    let i = ModeInputs {
        service: false,
        ..all
    };
    assert_eq!(select_mode(&i), Mode::SafeStop);
    let i = ModeInputs {
        must_stop: false,
        ..i
    };
    assert_eq!(select_mode(&i), Mode::WindStow);
    // Then hail, the plant's stow contact, snow (the order of the
    // weather stows' danger to the panel), then the operator's stow.
    let i = ModeInputs {
        wind_stow: false,
        ..i
    };
    assert_eq!(select_mode(&i), Mode::HailStow);
    let mut i = i;
    i.weather.hail = false;
    assert_eq!(select_mode(&i), Mode::ExternalStow);
    i.weather.external = false;
    assert_eq!(select_mode(&i), Mode::SnowStow);
    i.weather.snow = false;
    assert_eq!(select_mode(&i), Mode::LowSupplyStow);
    i.weather.low_supply = false;
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
    // An axis homes by night too, and says so.
    assert_eq!(select_mode(&i), Mode::Homing);
    let i = ModeInputs {
        unhomed: false,
        ..i
    };
    assert_eq!(select_mode(&i), Mode::Night);
    let i = ModeInputs { night: false, ..i };
    assert_eq!(select_mode(&i), Mode::Overcast);
    let i = ModeInputs {
        overcast: false,
        ..i
    };
    assert_eq!(select_mode(&i), Mode::Tracking);
}

#[test]
fn backoff_doubles_up_to_its_cap() {
    assert_eq!(retry_backoff_ms(1), 10_000);
    assert_eq!(retry_backoff_ms(2), 20_000);
    assert_eq!(retry_backoff_ms(3), 40_000);
    // 10 000 ms × 2^5 = 320 000 ms, below the cap; × 2^6 = 640 000 ms
    // is above it.
    assert_eq!(retry_backoff_ms(6), 320_000);
    assert_eq!(retry_backoff_ms(7), 600_000);
    assert_eq!(retry_backoff_ms(8), 600_000);
    // Attempt 0 (before the first) waits as the first.
    assert_eq!(retry_backoff_ms(0), 10_000);
    assert_eq!(retry_backoff_ms(u16::MAX), 600_000);
}

#[test]
fn a_fault_that_keeps_coming_back_escalates() {
    // A limit switch hit, cleared by homing, hit again: each return is the
    // next attempt, and the fourth ends in a safe stop (3 retries).
    let mut m = FaultManager::new(Config::default().safety);
    let l = Fault::LimitSwitchHit(AxisId::A);
    let mut t = 0;
    for attempt in 1..=4u16 {
        let r = m.raise(l, at(t));
        assert_eq!(m.get(l).unwrap().attempts, attempt);
        if attempt < 4 {
            assert_eq!(r, Recovery::Rehome(AxisId::A));
            assert!(m.clear(l, at(t + 60)));
        } else {
            assert_eq!(r, Recovery::StopSafely);
        }
        t += 600;
    }
    assert!(m.must_stop());
    // The operator's reset forgets the history: a new hit starts over.
    m.reset();
    assert_eq!(m.raise(l, at(t)), Recovery::Rehome(AxisId::A));
    // A return long after the last one is a new fault, not a recurrence.
    assert!(m.clear(l, at(t)));
    let later = t + RECURRENCE_WINDOW_MS / 1000 + 1;
    m.raise(l, at(later));
    assert_eq!(m.get(l).unwrap().attempts, 1);
}

#[test]
fn attempts_stop_counting_at_the_top() {
    // A fault reported on and on, each report after its back-off (at most
    // ten minutes): the count climbs by one a report and stays at the top
    // of its 16 bits, never back to small (a first attempt again would
    // retry instead of keeping the final recovery).
    let mut m = FaultManager::new(Config::default().safety);
    let f = Fault::GpsLost;
    let step_ms = retry_backoff_ms(u16::MAX);
    let mut now_ms = 0u32;
    for _ in 0..u32::from(u16::MAX) + 10 {
        m.raise(f, now_ms);
        now_ms = now_ms.wrapping_add(step_ms);
        m.catch_up(now_ms);
    }
    assert_eq!(m.get(f).unwrap().attempts, u16::MAX);
}

#[test]
fn wind_hold_and_release_ignore_the_wall_clock() {
    // The monitor never sees UTC: whatever the wall clock does, the hold is
    // counted on the monotonic clock it is given.
    let mut w = WindMonitor::new(wind());
    // 50 Hz over 1-s intervals: stowed after 3 s.
    assert!(!w.update_pulses(at(1), 50, 1000));
    assert!(!w.update_pulses(at(2), 50, 1000));
    assert!(w.update_pulses(at(3), 50, 1000));
    // One interval as long as the hold is enough on its own.
    let mut w = WindMonitor::new(wind());
    assert!(w.update_pulses(at(60), 3000, 60_000));
}

#[test]
fn retries_escalate_across_the_clock_wrap_as_anywhere_else() {
    // The same reports as manager_counts_raised_and_recovered, starting 30 s
    // before the 32-bit monotonic clock wraps (49.7 days after boot).
    let start = u32::MAX - 29_999;
    let mut m = FaultManager::new(Config::default().safety);
    let f = Fault::MotorStalled(AxisId::A);
    for k in 0..10 {
        assert_eq!(m.raise(f, after(start, k)), Recovery::Retry);
    }
    assert_eq!(m.get(f).unwrap().attempts, 1);
    for k in [10, 30] {
        assert_eq!(m.raise(f, after(start, k)), Recovery::Retry);
    }
    assert_eq!(m.raise(f, after(start, 69)), Recovery::Retry);
    assert_eq!(
        m.raise(f, after(start, 70)),
        Recovery::DegradeOneAxis(AxisId::A)
    );
}

#[test]
fn a_due_retry_stays_due_through_a_month_of_silence() {
    // A fault raised once and then not reported for 30 days (longer than the
    // 24.8 days after which a wrapping difference turns negative): the
    // controller catches the manager up every tick (here: hourly), and the
    // next report counts as the next attempt at once.
    let mut m = FaultManager::new(Config::default().safety);
    let f = Fault::LimitSwitchHit(AxisId::C);
    m.raise(f, at(0));
    let mut now = 0u32;
    for _ in 0..30 * 24 {
        now = now.wrapping_add(3_600_000);
        m.catch_up(now);
    }
    assert!(m.get(f).unwrap().retry_due(now));
    m.raise(f, now);
    assert_eq!(m.get(f).unwrap().attempts, 2);
}

#[test]
fn a_cleared_fault_does_not_recur_after_the_clock_comes_round() {
    // Cleared at 0, raised again 2^32 ms later (the clock reads 1 s):
    // without the hourly catch-up it would look 1 s old and count as a
    // recurrence.
    let mut m = FaultManager::new(Config::default().safety);
    let f = Fault::LimitSwitchHit(AxisId::A);
    m.raise(f, at(0));
    assert!(m.clear(f, at(0)));
    let mut now = 0u32;
    for _ in 0..=(u32::MAX / 3_600_000) {
        now = now.wrapping_add(3_600_000);
        m.catch_up(now);
    }
    m.raise(f, at(1));
    assert_eq!(m.get(f).unwrap().attempts, 1);
}

#[test]
fn wind_stow_holds_across_the_clock_wrap() {
    let mut w = WindMonitor::new(wind());
    let start = u32::MAX - 1_499;
    // 1.5 s before the wrap a gale starts: stowed 3 s after it began.
    assert!(!w.update_pulses(after(start, 1), 30, 1000));
    assert!(!w.update_pulses(after(start, 2), 30, 1000));
    assert!(w.update_pulses(after(start, 3), 30, 1000));
    // Then a gale for 60 days, read every minute: stays stowed; calm for
    // 600 s releases it.
    let mut now = after(start, 3);
    for _ in 0..60 * 1440 {
        now = now.wrapping_add(60_000);
        assert!(w.update_pulses(now, 1800, 60_000));
    }
    for _ in 0..9 {
        now = now.wrapping_add(60_000);
        assert!(w.update_pulses(now, 0, 60_000));
    }
    now = now.wrapping_add(60_000);
    assert!(!w.update_pulses(now, 0, 60_000));
}

#[test]
fn operator_hold_bits_round_trip_and_unknown_bits_are_refused() {
    use suntracker::safety::OperatorHold;
    for b in 0u8..8 {
        let h = OperatorHold::from_bits(b).expect("three known bits");
        assert_eq!(h.to_bits(), b);
    }
    assert_eq!(
        OperatorHold::from_bits(4),
        Some(OperatorHold {
            stow: false,
            manual: false,
            service: true
        })
    );
    for b in 8u8..=255 {
        assert_eq!(OperatorHold::from_bits(b), None, "{b:#x}");
    }
}

#[test]
fn a_full_list_of_cleared_faults_forgets_the_oldest() {
    // Nine different faults raised and cleared one after another, a
    // minute apart: the list of cleared faults holds eight
    // (`MAX_ACTIVE`), so the ninth takes the place of the first, the
    // oldest. The first coming back is then a new fault; the second, still
    // remembered, a recurrence.
    let faults = [
        Fault::GpsLost,
        Fault::RtcInvalid,
        Fault::SensorTimeout(Sensor::Inclinometer),
        Fault::SensorTimeout(Sensor::Compass),
        Fault::MotorStalled(AxisId::C),
        Fault::MotorStalled(AxisId::A),
        Fault::LimitSwitchHit(AxisId::C),
        Fault::LimitSwitchHit(AxisId::A),
        Fault::TimeOutOfRange,
    ];
    let mut m = FaultManager::new(Config::default().safety);
    for (i, &f) in (0u32..).zip(faults.iter()) {
        m.raise(f, at(60 * i));
        assert!(m.clear(f, at(60 * i + 30)));
    }
    let now = at(600);
    m.raise(faults[0], now);
    assert_eq!(m.get(faults[0]).unwrap().attempts, 1);
    m.raise(faults[1], now);
    assert_eq!(m.get(faults[1]).unwrap().attempts, 2);
    // A fault cleared again takes its own earlier place: the other
    // remembered ones stay.
    assert!(m.clear(faults[1], now));
    m.raise(faults[2], now);
    assert_eq!(m.get(faults[2]).unwrap().attempts, 2);
}

#[test]
fn faults_are_equal_only_to_themselves() {
    // Every fault, each variant with each of its sensors or axes (the
    // enums' own lists): equality, ordering and hashing agree, and no two
    // different faults are equal.
    use std::collections::hash_map::DefaultHasher;
    use std::hash::{Hash, Hasher};
    let sensors = [
        Sensor::Inclinometer,
        Sensor::Compass,
        Sensor::Encoder(AxisId::C),
        Sensor::Encoder(AxisId::A),
        Sensor::Rtc,
        Sensor::Gps,
    ];
    let mut all = Vec::new();
    for s in sensors {
        all.push(Fault::SensorTimeout(s));
        all.push(Fault::I2cError(s));
    }
    for a in [AxisId::C, AxisId::A] {
        all.push(Fault::MotorStalled(a));
        all.push(Fault::SetPointDeviation(a));
        all.push(Fault::LimitSwitchHit(a));
        all.push(Fault::Obstruction(a));
        all.push(Fault::UnexpectedMotion(a));
        all.push(Fault::MoveTimeout(a));
    }
    all.extend([
        Fault::GpsLost,
        Fault::RtcInvalid,
        Fault::GpsTimeImplausible,
        Fault::GpsTimeUnstable,
        Fault::GpsPositionUnstable,
        Fault::TimeOutOfRange,
        Fault::ScheduleFailed,
    ]);
    assert_eq!(all.len(), 31);
    let hash = |f: &Fault| {
        let mut h = DefaultHasher::new();
        f.hash(&mut h);
        h.finish()
    };
    for (i, a) in all.iter().enumerate() {
        for (j, b) in all.iter().enumerate() {
            assert_eq!(a == b, i == j, "{a:?} {b:?}");
            assert_eq!(a.cmp(b) == std::cmp::Ordering::Equal, i == j);
        }
        let copy = *a;
        assert_eq!(hash(a), hash(&copy));
        // The names are distinct too (one per fault).
        assert_eq!(all.iter().filter(|b| b.name() == a.name()).count(), 1);
    }
}

/// The weather stows on the monotonic clock: hail and snow latched until
/// their inputs have been clear for their release times, the plant's
/// contact only while at its active level; an unwired input never stows.
#[test]
fn weather_stows_latch_and_release_on_the_monotonic_clock() {
    let mut config = Config::default().stow;
    let supply = Config::default().supply;
    config.snow_release_s = 600;
    config.hail_release_s = 60;
    let mut w = WeatherStow::default();
    let none = StowInputs::default();
    assert_eq!(
        w.update(&none, 0, &config, &supply),
        WeatherModes::default()
    );
    let snowing = StowInputs {
        snow: Some(true),
        hail: Some(false),
        external_high: Some(true),
        supply_mv: None,
        irradiance_w_m2: None,
    };
    // The contact reads high: not its active level (low by default).
    let m = w.update(&snowing, 1_000, &config, &supply);
    assert!(m.snow && !m.hail && !m.external);
    let clear = StowInputs {
        snow: Some(false),
        hail: Some(false),
        external_high: Some(false),
        supply_mv: None,
        irradiance_w_m2: None,
    };
    // Clear from 2 s: the contact (low) is active at once; snow stays
    // until 600 s of clear input, counted from the first clear tick.
    let m = w.update(&clear, 2_000, &config, &supply);
    assert!(m.snow && m.external);
    assert!(w.update(&clear, 601_999, &config, &supply).snow);
    assert!(!w.update(&clear, 602_000, &config, &supply).snow);
    // Snow again in the release time starts it over.
    assert!(w.update(&snowing, 603_000, &config, &supply).snow);
    assert!(w.update(&clear, 604_000, &config, &supply).snow);
    assert!(w.update(&snowing, 700_000, &config, &supply).snow);
    assert!(w.update(&clear, 701_000, &config, &supply).snow);
    assert!(w.update(&clear, 1_300_999, &config, &supply).snow);
    assert!(!w.update(&clear, 1_301_000, &config, &supply).snow);
    // Hail over the wrap of the 32-bit clock: released 60 s after clear.
    let hail = StowInputs {
        hail: Some(true),
        ..clear
    };
    let t0 = u32::MAX - 10_000;
    assert!(w.update(&hail, t0, &config, &supply).hail);
    assert!(
        w.update(&clear, t0.wrapping_add(1_000), &config, &supply)
            .hail
    );
    assert!(
        w.update(&clear, t0.wrapping_add(60_999), &config, &supply)
            .hail
    );
    assert!(
        !w.update(&clear, t0.wrapping_add(61_000), &config, &supply)
            .hail
    );
    // Active high: the contact stows while the pin reads high.
    config.external_active = 1;
    assert!(!w.update(&clear, 5, &config, &supply).external);
    assert!(w.update(&snowing, 6, &config, &supply).external);
    // Unwired inputs never stow, whatever the configuration.
    assert!(!w.update(&none, 7, &config, &supply).external);
}

/// The supply watch: low below `supply.stow_mv`, back from
/// `supply.resume_mv` (hysteresis), off at 0; an impossible reading is a
/// fault that keeps the state, or stows with `stow.on_sensor_fault`.
#[test]
fn low_supply_stows_with_hysteresis_and_sensor_faults() {
    let mut stow = Config::default().stow;
    let mut supply = Config::default().supply;
    let mut w = WeatherStow::default();
    let at = |mv: u16| StowInputs {
        supply_mv: Some(Reading::Value(mv)),
        ..StowInputs::default()
    };
    let rail = StowInputs {
        supply_mv: Some(Reading::Impossible),
        ..StowInputs::default()
    };
    // Off by default, whatever the reading, and no fault.
    assert!(!w.update(&at(1_000), 0, &stow, &supply).low_supply);
    assert!(!w.update(&rail, 0, &stow, &supply).supply_fault);
    supply.stow_mv = 11_500;
    supply.resume_mv = 12_200;
    assert!(!w.update(&at(12_000), 1, &stow, &supply).low_supply);
    assert!(!w.update(&at(11_500), 2, &stow, &supply).low_supply);
    assert!(w.update(&at(11_499), 3, &stow, &supply).low_supply);
    // Between the levels it stays low; from the resume level it is not.
    assert!(w.update(&at(12_199), 4, &stow, &supply).low_supply);
    assert!(!w.update(&at(12_200), 5, &stow, &supply).low_supply);
    assert!(!w.update(&at(11_800), 6, &stow, &supply).low_supply);
    // An impossible reading: a fault, the state kept (not low here).
    let m = w.update(&rail, 7, &stow, &supply);
    assert!(m.supply_fault && !m.low_supply);
    assert!(w.update(&at(11_000), 8, &stow, &supply).low_supply);
    let m = w.update(&rail, 9, &stow, &supply);
    assert!(m.supply_fault && m.low_supply);
    assert!(!w.update(&at(12_500), 10, &stow, &supply).low_supply);
    // ... or a stow of its own when configured.
    stow.on_sensor_fault = 1;
    assert!(w.update(&rail, 11, &stow, &supply).low_supply);
    // No input wired: never.
    assert!(
        !w.update(&StowInputs::default(), 12, &stow, &supply)
            .low_supply
    );
}

/// The clear sky of B. Haurwitz (1945), `1098 · cos z · exp(−0.059 / cos
/// z)` W/m², written out here from the formula, and pvlib 0.11's
/// `clearsky.haurwitz` at 0°, 30° and 60° (1,035.092, 888.271 and 487.894
/// W/m²); none at and below the horizon.
#[test]
fn clear_sky_is_haurwitz() {
    let f = |z: f64| 1098.0 * z.to_radians().cos() * (-0.059 / z.to_radians().cos()).exp();
    for z in [0.0f32, 30.0, 60.0, 80.0, 89.0] {
        let want = f(f64::from(z));
        assert!(
            (f64::from(clear_sky_ghi_w_m2(z)) - want).abs() < 0.01 * want.max(1.0),
            "{z}"
        );
    }
    for (z, pvlib) in [(0.0f32, 1035.092), (30.0, 888.271), (60.0, 487.894)] {
        assert!(
            (f64::from(clear_sky_ghi_w_m2(z)) - pvlib).abs() < 0.05,
            "{z}"
        );
    }
    assert_eq!(clear_sky_ghi_w_m2(90.0), 0.0);
    assert_eq!(clear_sky_ghi_w_m2(120.0), 0.0);
    assert_eq!(clear_sky_ghi_w_m2(f32::NAN), 0.0);
}

/// The overcast mode: in after `enter_s` below the ratio of the clear sky,
/// out after `leave_s` at or above it, at most `max_moves_per_hour`
/// changes an hour; off without an input, a sun or a ratio.
#[test]
fn overcast_enters_leaves_and_limits_its_moves() {
    let mut config = Config::default().overcast;
    // Off by default (no pyranometer); an installer's threshold.
    assert_eq!(config.ratio, 0.0);
    config.ratio = 0.3;
    config.enter_s = 60;
    config.leave_s = 120;
    config.max_moves_per_hour = 2;
    let mut o = OvercastMonitor::default();
    // The sun at 30° from the zenith: the clear sky gives 888 W/m², the
    // threshold (0.3) 266.
    let z = Some(30.0f32);
    let w = |v: u16| Some(Reading::Value(v));
    assert!(!o.update(w(900), z, 0, &config));
    assert!(!o.update(w(200), z, 1_000, &config));
    assert!(!o.update(w(200), z, 60_999, &config));
    assert!(o.update(w(200), z, 61_000, &config));
    // A moment of sun does not end it; 120 s of it does.
    assert!(o.update(w(800), z, 70_000, &config));
    assert!(o.update(w(200), z, 80_000, &config));
    assert!(o.update(w(800), z, 90_000, &config));
    assert!(o.update(w(800), z, 209_999, &config));
    assert!(!o.update(w(800), z, 210_000, &config));
    // Two changes this hour: the third waits until the first is an hour
    // old (61 s + 1 h).
    assert!(!o.update(w(100), z, 300_000, &config));
    assert!(!o.update(w(100), z, 3_660_999, &config));
    assert!(o.update(w(100), z, 3_661_000, &config));
    // An impossible reading: a fault, the state kept.
    assert!(o.update(Some(Reading::Impossible), z, 3_700_000, &config));
    assert!(o.fault());
    // Nothing at all with the sun up: a sensor come loose, not a sky.
    assert!(o.update(w(100), z, 3_750_000, &config));
    assert!(!o.fault());
    assert!(o.update(w(2), z, 3_760_000, &config), "the state is kept");
    assert!(o.fault());
    // No sun (night), no input, or off: never overcast.
    assert!(!o.update(w(100), None, 3_800_000, &config));
    assert!(!o.update(None, z, 3_900_000, &config));
    config.ratio = 0.0;
    assert!(!o.update(w(0), z, 4_000_000, &config));
    assert!(!o.fault());
}
