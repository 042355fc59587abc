//! GPS receivers that lie about the time, against the time keeper and a
//! modelled RTC. The rules (`suntracker::time::keeper`): GPS time is
//! adopted when two consecutive epochs agree with the monotonic time
//! between them (or one agrees with a running RTC within the drift limit);
//! a step beyond the margin from a running RTC waits for the confirm time
//! of consistent epochs; a stream that keeps disagreeing is reported
//! unstable and never adopted; reports are held so that a fault raised by
//! every epoch is raised once.
//!
//! Expected values follow from the rules and the stated settings (one
//! epoch a second, `TimeConfig::default()`), not from a run.

use drivers::gps::{Coordinate, FixQuality, GpsFix};
use drivers::time::DateTime;
use sim::rtc::SimRtc;
use sun_algos::UtcTime;
use suntracker::time::{TimeConfig, TimeKeeper, TimeOrigin, UNSTABLE_DISAGREEMENTS};

/// 2026-06-21T10:00:00Z, the true time at monotonic 0.
fn t0() -> UtcTime {
    UtcTime::from_ymd_hms(2026, 6, 21, 10, 0, 0).unwrap()
}

fn at(s: i64) -> UtcTime {
    t0().add_millis(s * 1000).unwrap()
}

/// A Kano fix saying `said`, arriving at monotonic `arrived_ms`.
fn fix(said: UtcTime, arrived_ms: u32) -> GpsFix {
    let (y, mo, d) = said.ymd();
    let s = said.ms_of_day() / 1000;
    GpsFix {
        utc: Some(
            DateTime::new(
                y as u16,
                mo,
                d,
                (s / 3600) as u8,
                (s / 60 % 60) as u8,
                (s % 60) as u8,
            )
            .unwrap(),
        ),
        latitude_deg: Coordinate::from_deg(11.9683),
        longitude_deg: Coordinate::from_deg(8.4261),
        altitude_m: Some(480.0),
        quality: FixQuality::Gps,
        satellites: Some(8),
        utc_received_ms: Some(arrived_ms),
    }
}

/// One tick's time in force, its origin and the unstable report.
type Tick = (Option<UtcTime>, Option<TimeOrigin>, bool);

/// Runs `seconds` one-second ticks with a running RTC that reads the true
/// time, a GPS epoch every second saying `gps(s)` (arriving with the
/// tick); returns, per tick, (time in force, origin, unstable report) and
/// the RTC's writes.
fn run(seconds: i64, rtc_lost_power: bool, gps: impl Fn(i64) -> UtcTime) -> (Vec<Tick>, u32) {
    let mut rtc = SimRtc::new(t0());
    if rtc_lost_power {
        rtc.power_loss();
    }
    let mut keeper = TimeKeeper::new(rtc, TimeConfig::default());
    let mut out = Vec::new();
    for s in 0..seconds {
        keeper.rtc_mut().advance(at(s));
        let now_ms = (s * 1000) as u32;
        let st = keeper.update(&fix(gps(s), now_ms), now_ms);
        out.push((st.now, st.origin, st.gps_time_unstable));
    }
    let sets = keeper.rtc_mut().sets;
    (out, sets)
}

#[test]
fn a_good_receiver_is_adopted_at_once_beside_a_good_rtc() {
    let (ticks, sets) = run(60, false, at);
    for (s, (now, origin, unstable)) in ticks.iter().enumerate() {
        assert_eq!(*now, Some(at(s as i64)));
        assert_eq!(*origin, Some(TimeOrigin::Gps), "{s}");
        assert!(!unstable);
    }
    assert_eq!(sets, 0);
}

#[test]
fn an_hour_behind_a_running_rtc_waits_for_the_confirm_time_then_steps_once() {
    let confirm_s = i64::from(TimeConfig::default().confirm_ms / 1000);
    let (ticks, sets) = run(1200, false, |s| at(s - 3600));
    for (s, (now, origin, unstable)) in ticks.iter().enumerate() {
        let s = s as i64;
        assert!(!unstable, "a consistent receiver is not unstable");
        // Consistent from the first epoch: the agreement counts from it,
        // so the step comes confirm_s after it.
        if s < confirm_s {
            assert_eq!((*now, *origin), (Some(at(s)), Some(TimeOrigin::Rtc)), "{s}");
        } else {
            assert_eq!(
                (*now, *origin),
                (Some(at(s - 3600)), Some(TimeOrigin::Gps)),
                "{s}"
            );
        }
    }
    assert_eq!(sets, 1, "one write to the RTC: the step");
}

#[test]
fn a_receiver_alternating_an_hour_either_way_is_never_adopted() {
    let (ticks, sets) = run(1200, false, |s| {
        at(s + if s % 2 == 0 { 3600 } else { -3600 })
    });
    for (s, (now, origin, unstable)) in ticks.iter().enumerate() {
        assert_eq!((*now, *origin), (Some(at(s as i64)), Some(TimeOrigin::Rtc)));
        // Every epoch after the first disagrees with the one before.
        assert_eq!(*unstable, s >= usize::from(UNSTABLE_DISAGREEMENTS), "{s}");
    }
    assert_eq!(sets, 0);
}

#[test]
fn time_running_backwards_is_unstable_and_never_adopted() {
    // Each epoch one second earlier than the one before.
    let (ticks, sets) = run(600, false, |s| at(-s));
    for (s, (now, origin, unstable)) in ticks.iter().enumerate() {
        // The first epoch is right (and agrees with the RTC).
        let want = if s == 0 {
            TimeOrigin::Gps
        } else {
            TimeOrigin::Rtc
        };
        assert_eq!((*now, *origin), (Some(at(s as i64)), Some(want)), "{s}");
        assert_eq!(*unstable, s >= usize::from(UNSTABLE_DISAGREEMENTS), "{s}");
    }
    assert_eq!(sets, 0);
    // With no RTC to fall back on, the time stays unknown.
    let (ticks, sets) = run(600, true, |s| at(-s));
    assert!(ticks.iter().all(|(now, _, _)| now.is_none()));
    assert_eq!(sets, 0);
}

#[test]
fn a_lost_rtc_is_set_from_the_second_agreeing_epoch() {
    let (ticks, sets) = run(10, true, at);
    assert_eq!(ticks[0].0, None, "one epoch alone is not trusted");
    for (s, (now, origin, _)) in ticks.iter().enumerate().skip(1) {
        assert_eq!((*now, *origin), (Some(at(s as i64)), Some(TimeOrigin::Gps)));
    }
    assert_eq!(sets, 1);
}

#[test]
fn one_wrong_epoch_is_skipped_without_a_fault() {
    // 10:00:30 says 11:00:30.
    let (ticks, sets) = run(120, false, |s| if s == 30 { at(s + 3600) } else { at(s) });
    for (s, (now, origin, unstable)) in ticks.iter().enumerate() {
        let s = s as i64;
        assert_eq!(*now, Some(at(s)), "{s}");
        // The wrong epoch, and the one after it (which contradicts it:
        // which of the two is right shows only at the next).
        let want = if s == 30 || s == 31 {
            TimeOrigin::Rtc
        } else {
            TimeOrigin::Gps
        };
        assert_eq!(*origin, Some(want), "{s}");
        assert!(!unstable, "{s}");
    }
    assert_eq!(sets, 0);
}

#[test]
fn a_rollover_stream_is_reported_once_and_held() {
    let hold_s = i64::from(TimeConfig::default().fault_hold_ms / 1000);
    let mut keeper = TimeKeeper::new(SimRtc::new(t0()), TimeConfig::default());
    // 1024 weeks back (the GPS week-rollover bug), an epoch every 2 s for
    // 5 minutes, then a good receiver; a tick every second.
    let rollover_days = 1024 * 7;
    let mut reports = Vec::new();
    for s in 0..600i64 {
        keeper.rtc_mut().advance(at(s));
        let now_ms = (s * 1000) as u32;
        let arrived_ms = (s - s % 2) as u32 * 1000;
        let said = if s < 300 {
            at(s - s % 2 - rollover_days * 86_400)
        } else {
            at(s - s % 2)
        };
        let st = keeper.update(&fix(said, arrived_ms), now_ms);
        reports.push(st.gps_time_implausible);
        assert_eq!(st.now, Some(at(s)), "{s}");
    }
    // From the first epoch until the hold after the last one (298 s).
    for (s, r) in reports.iter().enumerate() {
        assert_eq!(*r, (s as i64) <= 298 + hold_s, "{s}");
    }
    assert_eq!(keeper.rejected_epochs(), 150);
}

#[test]
fn old_reports_do_not_come_back_when_the_monotonic_clock_wraps() {
    // One rollover epoch, then a silent receiver, a tick a minute for 50
    // days: the 32-bit millisecond clock wraps after 49.7 days, where the
    // epoch's stamp would look a moment old again.
    let mut keeper = TimeKeeper::new(SimRtc::new(t0()), TimeConfig::default());
    let rollover = at(-1024 * 7 * 86_400);
    let st = keeper.update(&fix(rollover, 0), 0);
    assert!(st.gps_time_implausible);
    let mut raised_after_hold = Vec::new();
    for minute in 1..(50 * 1440i64) {
        let now_ms = (minute * 60_000) as u32;
        keeper.rtc_mut().advance(at(minute * 60));
        let st = keeper.update(&GpsFix::NONE, now_ms);
        if st.gps_time_implausible || st.gps_time_unstable {
            raised_after_hold.push(minute);
        }
    }
    // Held for the minute after it (60 s), then never again.
    assert_eq!(raised_after_hold, [1]);
}
