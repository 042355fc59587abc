//! `sim::rtc::SimRtc`: a DS3231-like clock that follows the true time with
//! an offset, and its injected faults (step, power loss, bus error).

use drivers::rtc::{sync_from_gps, Clock};
use drivers::time::DateTime;
use sim::rtc::{SimRtc, SimRtcError, POWER_LOSS_RESET_UNIX_S};
use sun_algos::UtcTime;

fn utc(y: i32, mo: u8, d: u8, h: u8, mi: u8, s: u8) -> UtcTime {
    UtcTime::from_ymd_hms(y, mo, d, h, mi, s).unwrap()
}

fn dt(y: u16, mo: u8, d: u8, h: u8, mi: u8, s: u8) -> DateTime {
    DateTime::new(y, mo, d, h, mi, s).unwrap()
}

#[test]
fn follows_true_time_in_whole_seconds() {
    let mut rtc = SimRtc::new(utc(2026, 3, 20, 12, 0, 0));
    assert_eq!(rtc.datetime(), Ok(dt(2026, 3, 20, 12, 0, 0)));
    assert_eq!(rtc.lost_power(), Ok(false));
    // Milliseconds of the true time are dropped, as the chip has none.
    let t = UtcTime::from_ymd_hms_milli(2026, 3, 20, 23, 59, 59, 999).unwrap();
    rtc.advance(t);
    assert_eq!(rtc.datetime(), Ok(dt(2026, 3, 20, 23, 59, 59)));
    rtc.advance(utc(2026, 3, 21, 0, 1, 0));
    assert_eq!(rtc.datetime(), Ok(dt(2026, 3, 21, 0, 1, 0)));
    assert_eq!(rtc.offset_s(), 0);
    assert_eq!(rtc.sets, 0);
}

#[test]
fn step_moves_the_reading_and_the_offset_stays() {
    let mut rtc = SimRtc::new(utc(2026, 3, 20, 12, 0, 0));
    rtc.step_s(3600);
    assert_eq!(rtc.datetime(), Ok(dt(2026, 3, 20, 13, 0, 0)));
    rtc.step_s(-7200);
    assert_eq!(rtc.offset_s(), -3600);
    rtc.advance(utc(2026, 3, 21, 0, 30, 0));
    assert_eq!(rtc.datetime(), Ok(dt(2026, 3, 20, 23, 30, 0)));
    // A step does not set the lost-power flag.
    assert_eq!(rtc.lost_power(), Ok(false));
}

#[test]
fn set_datetime_makes_it_read_the_given_time_and_counts() {
    let mut rtc = SimRtc::new(utc(2026, 6, 1, 10, 0, 0));
    rtc.set_datetime(&dt(2026, 6, 1, 9, 59, 30)).unwrap();
    assert_eq!(rtc.offset_s(), -30);
    assert_eq!(rtc.datetime(), Ok(dt(2026, 6, 1, 9, 59, 30)));
    rtc.advance(utc(2026, 6, 1, 10, 1, 0));
    assert_eq!(rtc.datetime(), Ok(dt(2026, 6, 1, 10, 0, 30)));
    // Milliseconds given to set_datetime are dropped.
    let with_ms = dt(2026, 6, 1, 10, 1, 0).with_millis(750).unwrap();
    rtc.set_datetime(&with_ms).unwrap();
    assert_eq!(rtc.offset_s(), 0);
    assert_eq!(rtc.sets, 2);
}

#[test]
fn power_loss_reads_2000_and_counts_on_until_set() {
    let mut rtc = SimRtc::new(utc(2026, 6, 1, 10, 0, 0));
    rtc.power_loss();
    assert_eq!(rtc.lost_power(), Ok(true));
    assert!(rtc.oscillator_stopped());
    assert_eq!(rtc.datetime(), Ok(dt(2000, 1, 1, 0, 0, 0)));
    assert_eq!(
        rtc.reading_unix_s(),
        Some(POWER_LOSS_RESET_UNIX_S),
        "2000-01-01T00:00:00Z"
    );
    rtc.advance(utc(2026, 6, 1, 10, 5, 0));
    assert_eq!(rtc.datetime(), Ok(dt(2000, 1, 1, 0, 5, 0)));
    assert_eq!(rtc.lost_power(), Ok(true), "still lost until set");
    // The GPS sync path sets it, which clears the flag.
    let gps = dt(2026, 6, 1, 10, 5, 0);
    assert_eq!(sync_from_gps(&mut rtc, &gps, 2), Ok(true));
    assert_eq!(rtc.lost_power(), Ok(false));
    assert_eq!(rtc.datetime(), Ok(gps));
    assert_eq!(rtc.sets, 1);
    // In sync now: nothing to do.
    assert_eq!(sync_from_gps(&mut rtc, &gps, 2), Ok(false));
    assert_eq!(rtc.sets, 1);
}

#[test]
fn bus_error_fails_every_call_and_changes_nothing() {
    let mut rtc = SimRtc::new(utc(2026, 6, 1, 10, 0, 0));
    rtc.bus_error = true;
    assert_eq!(rtc.datetime(), Err(SimRtcError::Bus));
    assert_eq!(rtc.lost_power(), Err(SimRtcError::Bus));
    assert_eq!(
        rtc.set_datetime(&dt(2020, 1, 1, 0, 0, 0)),
        Err(SimRtcError::Bus)
    );
    assert_eq!(rtc.sets, 0);
    assert_eq!(rtc.offset_s(), 0);
    assert_eq!(
        sync_from_gps(&mut rtc, &dt(2026, 6, 1, 10, 0, 0), 2),
        Err(SimRtcError::Bus)
    );
    rtc.bus_error = false;
    assert_eq!(rtc.datetime(), Ok(dt(2026, 6, 1, 10, 0, 0)));
    assert_eq!(SimRtcError::Bus.to_string(), "RTC bus error");
}

#[test]
fn extreme_steps_are_errors_not_panics() {
    let mut rtc = SimRtc::new(utc(2026, 6, 1, 10, 0, 0));
    rtc.step_s(i64::MAX);
    rtc.step_s(i64::MAX);
    assert_eq!(rtc.offset_s(), i64::MAX, "saturates");
    assert_eq!(rtc.reading_unix_s(), None);
    assert_eq!(rtc.datetime(), Err(SimRtcError::OutOfRange));
    rtc.step_s(i64::MIN);
    rtc.step_s(i64::MIN);
    assert_eq!(rtc.datetime(), Err(SimRtcError::OutOfRange));
    // Past year 9999 but without overflow: still OutOfRange.
    let mut rtc = SimRtc::new(utc(2026, 6, 1, 10, 0, 0));
    rtc.step_s(10_000 * 366 * 86_400);
    assert_eq!(rtc.datetime(), Err(SimRtcError::OutOfRange));
    // Setting it repairs it.
    rtc.set_datetime(&dt(2026, 6, 1, 10, 0, 0)).unwrap();
    assert_eq!(rtc.datetime(), Ok(dt(2026, 6, 1, 10, 0, 0)));
}
