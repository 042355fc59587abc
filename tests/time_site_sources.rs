//! Time and site fallbacks (GPS, then RTC; GPS, then stored site, then a
//! postal code) over the real DS3231 driver on an
//! I2C mock (transaction-exact) and the real GPS reader on an in-memory
//! serial port.

mod common;

use common::*;
use drivers::gps::{Coordinate, FixQuality, GpsFix};
use drivers::rtc::Ds3231;
use drivers::time::DateTime;
use embedded_hal::i2c::{ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};
use sun_algos::{Site, UtcTime};
use suntracker::config::SiteConfig;
use suntracker::hw::{GpsPort, RtcClock};
use suntracker::ports::Clock;
use suntracker::site::PostalError;
use suntracker::site::{follow_gps_site, resolve_site, SiteError, SiteOrigin};
use suntracker::time::{gps_time, GpsTime, TimeConfig, TimeKeeper, TimeOrigin};

fn nack() -> ErrorKind {
    ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
}

fn at(secs: u32) -> DayTime {
    DayTime { secs }
}

fn utc(secs: u32) -> UtcTime {
    let (h, m, s) = at(secs).hms();
    UtcTime::from_ymd_hms(2026, 3, 20, h as u8, m as u8, s as u8).unwrap()
}

/// A GPS fix at Kano, 2026-03-20 `secs` after midnight.
fn kano_fix(secs: u32) -> GpsFix {
    let (h, m, s) = at(secs).hms();
    GpsFix {
        utc: Some(DateTime::new(2026, 3, 20, h as u8, m as u8, s as u8).unwrap()),
        latitude_deg: Coordinate::from_deg(11.9683),
        longitude_deg: Coordinate::from_deg(8.4261),
        altitude_m: Some(480.0),
        quality: FixQuality::Gps,
        satellites: Some(8),
        // Received in the same second, on a monotonic clock that counts
        // from midnight here.
        utc_received_ms: Some(ms(secs)),
    }
}

/// The monotonic clock (ms) at `secs` after midnight.
fn ms(secs: u32) -> u32 {
    suntracker::time::monotonic::from_board_ms(u64::from(secs) * 1000)
}

const T0: u32 = 6 * 3600 + 30 * 60; // 06:30:00

#[test]
fn rtc_that_lost_power_waits_for_gps_then_gps_sets_it() {
    let mut tx = vec![
        // 1. No GPS; OSF set: the time registers are not even read.
        read_status(STATUS_OSF),
        // 2. A first GPS epoch: one alone is not trusted.
        read_status(STATUS_OSF),
        // 3. The next, agreeing with it: OSF still set -> the RTC is set
        //    to GPS time.
        read_status(STATUS_OSF),
    ];
    tx.extend(set_time(at(T0 + 60), STATUS_OSF));
    // 4. GPS gone: the RTC, now running, gives the time.
    tx.push(read_status(STATUS_RUNNING));
    tx.push(read_time(at(T0 + 120)));
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), TimeConfig::default());

    let s = keeper.update(&GpsFix::NONE, 0);
    assert!(!s.time_valid(), "an RTC that lost power is not trusted");
    assert!(s.rtc_lost_power && !s.gps_fix && !s.rtc_set && !s.rtc_error);
    assert_eq!(s.rtc_raw, None);

    let s = keeper.update(&kano_fix(T0 + 59), ms(T0 + 59));
    assert!(!s.time_valid() && !s.rtc_set);
    let s = keeper.update(&kano_fix(T0 + 60), ms(T0 + 60));
    assert_eq!(s.now, Some(utc(T0 + 60)));
    assert_eq!(s.origin, Some(TimeOrigin::Gps));
    assert!(s.rtc_set && s.gps_fix && s.rtc_lost_power);

    let s = keeper.update(&GpsFix::NONE, 0);
    assert_eq!(s.now, Some(utc(T0 + 120)));
    assert_eq!(s.origin, Some(TimeOrigin::Rtc));
    assert!(!s.gps_fix && !s.rtc_set);
    assert_eq!(keeper.rtc_sets(), 1);
    keeper.destroy().destroy().done();
}

#[test]
fn gps_disciplines_the_rtc_only_past_the_drift_limit() {
    let mut tx = vec![
        // RTC 2 s slow, limit 2 s: left alone.
        read_status(STATUS_RUNNING),
        read_time(at(T0 - 2)),
        // RTC 3 s fast: set.
        read_status(STATUS_RUNNING),
        read_time(at(T0 + 60 + 3)),
    ];
    tx.extend(set_time(at(T0 + 60), STATUS_RUNNING));
    let mut keeper = TimeKeeper::new(
        Ds3231::new(I2cMock::new(&tx)),
        TimeConfig {
            max_drift_s: 2,
            ..TimeConfig::default()
        },
    );
    let s = keeper.update(&kano_fix(T0), ms(T0));
    assert_eq!((s.now, s.rtc_set), (Some(utc(T0)), false));
    assert_eq!(s.rtc_raw, Some(utc(T0 - 2)));
    let s = keeper.update(&kano_fix(T0 + 60), ms(T0 + 60));
    assert_eq!((s.now, s.rtc_set), (Some(utc(T0 + 60)), true));
    keeper.destroy().destroy().done();
}

#[test]
fn gps_time_without_a_fix_is_not_trusted() {
    // RMC status V still carries the receiver's time: not used, so an RTC
    // that lost power stays untrusted and is not written.
    let no_fix = GpsFix {
        latitude_deg: None,
        longitude_deg: None,
        altitude_m: None,
        quality: FixQuality::Invalid,
        satellites: Some(0),
        ..kano_fix(T0)
    };
    assert_eq!(
        gps_time(&no_fix, ms(T0), &TimeConfig::default()),
        GpsTime::NoFix
    );
    let tx = [read_status(STATUS_OSF)];
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), TimeConfig::default());
    let s = keeper.update(&no_fix, ms(T0));
    assert!(!s.time_valid() && !s.gps_fix && !s.rtc_set);
    keeper.destroy().destroy().done();
}

#[test]
fn rtc_nack_falls_back_to_gps_and_without_gps_the_time_is_unknown() {
    let tx = [
        // 1. NACK on the status read, GPS has a fix: one epoch alone is
        //    not trusted.
        I2c::write_read(RTC_ADDR, vec![REG_STATUS], vec![0]).with_error(nack()),
        // 2. The next epoch agrees with it: GPS time, no write.
        I2c::write_read(RTC_ADDR, vec![REG_STATUS], vec![0]).with_error(nack()),
        // 3. NACK again, no GPS: time unknown.
        I2c::write_read(RTC_ADDR, vec![REG_STATUS], vec![0]).with_error(nack()),
        // 4. Status fine, time read NACKed, no GPS: unknown.
        read_status(STATUS_RUNNING),
        I2c::write_read(RTC_ADDR, vec![REG_SECONDS], vec![0; 7]).with_error(nack()),
        // 5. Bus back: RTC time.
        read_status(STATUS_RUNNING),
        read_time(at(T0 + 180)),
    ];
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), TimeConfig::default());
    let s = keeper.update(&kano_fix(T0 - 1), ms(T0 - 1));
    assert!(!s.time_valid() && s.rtc_error);
    let s = keeper.update(&kano_fix(T0), ms(T0));
    assert_eq!((s.now, s.origin), (Some(utc(T0)), Some(TimeOrigin::Gps)));
    assert!(s.rtc_error && !s.rtc_set);
    let s = keeper.update(&GpsFix::NONE, 0);
    assert!(!s.time_valid() && s.rtc_error);
    // The controller still gets an instant for its timers: the last good one.
    assert_eq!(s.tick_time(keeper.last_valid().unwrap()), utc(T0));
    let s = keeper.update(&GpsFix::NONE, 0);
    assert!(!s.time_valid() && s.rtc_error);
    let s = keeper.update(&GpsFix::NONE, 0);
    assert_eq!((s.now, s.rtc_error), (Some(utc(T0 + 180)), false));
    keeper.destroy().destroy().done();
}

#[test]
fn garbage_time_registers_are_replaced_by_gps_time() {
    // OSF clear but the date register holds 0 (no such date): the RTC is
    // rewritten from GPS at the second epoch (one alone is not trusted).
    let mut tx = vec![
        read_status(STATUS_RUNNING),
        I2c::write_read(RTC_ADDR, vec![REG_SECONDS], vec![0; 7]),
        read_status(STATUS_RUNNING),
        I2c::write_read(RTC_ADDR, vec![REG_SECONDS], vec![0; 7]),
    ];
    tx.extend(set_time(at(T0), STATUS_RUNNING));
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), TimeConfig::default());
    let s = keeper.update(&kano_fix(T0 - 1), ms(T0 - 1));
    assert!(s.rtc_error && !s.rtc_set && !s.time_valid());
    let s = keeper.update(&kano_fix(T0), ms(T0));
    assert!(s.rtc_error && s.rtc_set);
    assert_eq!(s.now, Some(utc(T0)));
    keeper.destroy().destroy().done();
}

#[test]
fn rtc_clock_adapter_refuses_a_clock_that_lost_power() {
    let tx = [
        read_status(STATUS_OSF),
        read_status(STATUS_RUNNING),
        read_time(at(12 * 3600 + 34 * 60 + 56)),
        I2c::write_read(RTC_ADDR, vec![REG_STATUS], vec![0]).with_error(nack()),
    ];
    let mut clock = RtcClock::new(Ds3231::new(I2cMock::new(&tx)));
    assert_eq!(clock.now(), Err(suntracker::hw::ClockError::LostPower));
    assert_eq!(clock.now(), Ok(utc(12 * 3600 + 34 * 60 + 56)));
    assert!(matches!(
        clock.now(),
        Err(suntracker::hw::ClockError::Rtc(_))
    ));
    clock.destroy().destroy().done();
}

#[test]
fn nmea_on_the_serial_port_sets_a_stopped_rtc() {
    // The whole path: NMEA bytes -> GpsPort (real assembler, nmea parser,
    // fusion) -> TimeKeeper -> DS3231 writes.
    let serial = MemSerial::default();
    let mut gps = GpsPort::new(serial.clone(), 3_000);
    let mut tx = vec![
        read_status(STATUS_OSF),
        read_status(STATUS_OSF),
        read_status(STATUS_OSF),
    ];
    tx.extend(set_time(at(T0 + 2), STATUS_OSF));
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), TimeConfig::default());

    // No fix yet: the receiver reports time without position.
    serial.push(&gps_epoch(at(T0), false));
    let fix = gps.service(1_000).unwrap();
    assert_eq!(fix.quality, FixQuality::Invalid);
    assert!(!keeper.update(&fix, 1_000).time_valid());

    // The first fix: one epoch alone does not set the clock.
    serial.push(&gps_epoch(at(T0 + 1), true));
    let fix = gps.service(2_000).unwrap();
    assert!(fix.has_position());
    assert!(!keeper.update(&fix, 2_000).time_valid());

    // The next agrees with it over the second between them.
    serial.push(&gps_epoch(at(T0 + 2), true));
    let fix = gps.service(3_000).unwrap();
    let s = keeper.update(&fix, 3_000);
    assert_eq!(s.now, Some(utc(T0 + 2)));
    assert!(s.rtc_set);
    assert_eq!(gps.fixes(), 3);
    assert_eq!(gps.stats().accepted, 6);

    // Silence beyond the stale limit: the fix is gone.
    assert_eq!(gps.service(11_000).unwrap(), GpsFix::NONE);
    keeper.destroy().destroy().done();
}

#[test]
fn site_from_gps_then_stored_then_postal_code() {
    let stored = SiteConfig {
        latitude_deg: 36.75,
        longitude_deg: 3.06,
        elevation_m: 10.0,
        utc_offset_h: 0.0,
    };
    let (s, o) = resolve_site::<f64>(&kano_fix(T0), Some(&stored), Some("DZ:16000")).unwrap();
    assert_eq!(o, SiteOrigin::Gps);
    assert_eq!((s.latitude_deg(), s.longitude_deg()), (11.9683, 8.4261));
    assert_eq!(s.elevation_m(), 480.0);

    let (s, o) = resolve_site::<f64>(&GpsFix::NONE, Some(&stored), Some("DZ:16000")).unwrap();
    assert_eq!(o, SiteOrigin::Stored);
    assert!((s.latitude_deg() - 36.75).abs() < 1e-6);

    // DZ:16000 is "Alger Gare" (36.779443, 3.061738) in data/postal_codes.csv.
    let (s, o) = resolve_site::<f64>(&GpsFix::NONE, None, Some("DZ:16000")).unwrap();
    assert_eq!(o, SiteOrigin::PostalCode);
    let entry = suntracker::site::lookup_str("DZ:16000").unwrap();
    assert_eq!(s.latitude_deg(), entry.latitude_deg::<f64>());
    assert_eq!(s.longitude_deg(), entry.longitude_deg::<f64>());

    assert_eq!(
        resolve_site::<f64>(&GpsFix::NONE, None, Some("DZ:99999")),
        Err(SiteError::Postal(PostalError::UnknownPostalCode))
    );
    assert_eq!(
        resolve_site::<f64>(&GpsFix::NONE, None, None),
        Err(SiteError::NoSource)
    );
    // A stored site that is out of range is an error, never applied.
    let bad = SiteConfig {
        latitude_deg: 95.0,
        ..stored
    };
    assert!(matches!(
        resolve_site::<f64>(&GpsFix::NONE, Some(&bad), None),
        Err(SiteError::Invalid(_))
    ));
}

#[test]
fn shared_site_follows_a_moved_gps_only() {
    let cell = std::cell::Cell::new(Site::new(36.75, 3.06).unwrap());
    assert!(follow_gps_site(&cell, &kano_fix(T0), 0.01));
    assert_eq!(cell.get().latitude_deg(), 11.9683);
    // 0.00005° of fix noise: no change.
    let mut noisy = kano_fix(T0);
    noisy.latitude_deg = Coordinate::from_deg(11.96835);
    assert!(!follow_gps_site(&cell, &noisy, 0.01));
    assert!(!follow_gps_site(&cell, &GpsFix::NONE, 0.01));
}

#[test]
fn wmm_declination_for_the_site_matches_noaa_test_values() {
    // NOAA's WMM2025 test values (report table; pygeomag 1.1.0 to 6
    // decimals): 2027.5 at 80° N 0° E, 0 km: D = 2.59° (2.594134°);
    // 2025.0 at 0° N 120° E: D = −0.16° (−0.158274°). 2027.5 is
    // 2027-07-02 12:00 UTC (182.5 days into a 365-day year).
    // In f64 (hosts) and in f32 (the 8-bit board's site and synthesis).
    use suntracker::site::wmm_declination_deg as wmm;
    let t = UtcTime::from_ymd_hms(2027, 7, 2, 12, 0, 0).unwrap();
    for d in [
        wmm(&Site::<f64>::new(80.0, 0.0).unwrap(), &t).unwrap(),
        wmm(&Site::<f32>::new(80.0, 0.0).unwrap(), &t).unwrap(),
    ] {
        assert!((f64::from(d) - 2.594134).abs() < 0.005, "{d}");
    }
    let (site, site32) = (
        Site::new(0.0, 120.0).unwrap(),
        Site::<f32>::new(0.0, 120.0).unwrap(),
    );
    let t = UtcTime::from_ymd_hms(2025, 1, 1, 0, 0, 0).unwrap();
    for d in [wmm::<f64>(&site, &t).unwrap(), wmm(&site32, &t).unwrap()] {
        assert!((f64::from(d) + 0.158274).abs() < 0.005, "{d}");
    }
    // Outside the model's life span: an error, not a guess.
    let t = UtcTime::from_ymd_hms(2031, 1, 1, 0, 0, 0).unwrap();
    assert!(wmm::<f64>(&site, &t).is_err());
    assert!(wmm(&site32, &t).is_err());
}

#[test]
fn an_old_fix_does_not_set_a_correct_rtc_back() {
    // The RTC is right (T0 + 3 s); the fix says T0 but arrived 2.9 s ago.
    // Before the age was accounted for, the 3 s "drift" set the RTC back
    // by 2.9 s. Now: older than 1.5 s is stale, the RTC is kept.
    let old = kano_fix(T0);
    let tx = [read_status(STATUS_RUNNING), read_time(at(T0 + 3))];
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), TimeConfig::default());
    let now_ms = ms(T0) + 2_900;
    assert_eq!(
        gps_time(&old, now_ms, &TimeConfig::default()),
        GpsTime::Stale
    );
    let s = keeper.update(&old, now_ms);
    assert!(!s.rtc_set && !s.gps_fix);
    assert_eq!(
        (s.now, s.origin),
        (Some(utc(T0 + 3)), Some(TimeOrigin::Rtc))
    );
    keeper.destroy().destroy().done();

    // A fresh fix 0.9 s old is advanced by its age: T0 + 0.9 s, within
    // the drift limit of an RTC reading T0 + 1 s, so nothing is written.
    let now_ms = ms(T0) + 900;
    let want = utc(T0).add_seconds(0).unwrap();
    match gps_time(&old, now_ms, &TimeConfig::default()) {
        GpsTime::Trusted(t) => {
            assert_eq!(t.days_since_2000(), want.days_since_2000());
            assert_eq!(t.ms_of_day(), want.ms_of_day() + 900);
        }
        other => panic!("{other:?}"),
    }
    let tx = [read_status(STATUS_RUNNING), read_time(at(T0 + 1))];
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), TimeConfig::default());
    let s = keeper.update(&old, now_ms);
    assert!(s.gps_fix && !s.rtc_set);
    keeper.destroy().destroy().done();
}

#[test]
fn a_week_rollover_date_is_never_written_to_the_rtc() {
    // The receiver reports 2006-08-04 (1024 weeks before 2026-03-20) with
    // a valid fix: outside the firmware's window, reported as implausible;
    // the correct RTC stays as it is and gives the time.
    let (h, m, sec) = at(T0).hms();
    let rolled = GpsFix {
        utc: Some(DateTime::new(2006, 8, 4, h as u8, m as u8, sec as u8).unwrap()),
        ..kano_fix(T0)
    };
    let cfg = TimeConfig::default();
    assert!(matches!(
        gps_time(&rolled, ms(T0), &cfg),
        GpsTime::Implausible(_)
    ));
    // After the window's end (2045-08-18 for a 2026-01-01 floor) too.
    let late = GpsFix {
        utc: Some(DateTime::new(2046, 1, 1, 0, 0, 0).unwrap()),
        ..kano_fix(T0)
    };
    assert!(matches!(
        gps_time(&late, ms(T0), &cfg),
        GpsTime::Implausible(_)
    ));
    let tx = [read_status(STATUS_RUNNING), read_time(at(T0))];
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), cfg);
    let s = keeper.update(&rolled, ms(T0));
    assert!(s.gps_time_implausible && !s.gps_fix && !s.rtc_set);
    assert_eq!((s.now, s.origin), (Some(utc(T0)), Some(TimeOrigin::Rtc)));
    keeper.destroy().destroy().done();
}

#[test]
fn an_rtc_date_outside_the_window_is_not_trusted() {
    // A running RTC that reads 2000-01-01 (never set): not trusted; GPS
    // sets it at its second epoch.
    let never_set = || {
        I2c::write_read(
            RTC_ADDR,
            vec![REG_SECONDS],
            vec![0x00, 0x00, 0x00, 0x07, 0x01, 0x01, 0x00],
        )
    };
    let mut tx = vec![
        read_status(STATUS_RUNNING),
        never_set(),
        read_status(STATUS_RUNNING),
        never_set(),
    ];
    tx.extend(set_time(at(T0), STATUS_RUNNING));
    tx.push(read_status(STATUS_RUNNING));
    tx.push(never_set());
    let mut keeper = TimeKeeper::new(Ds3231::new(I2cMock::new(&tx)), TimeConfig::default());
    let s = keeper.update(&kano_fix(T0 - 1), ms(T0 - 1));
    assert!(s.rtc_implausible && !s.rtc_set && !s.time_valid());
    let s = keeper.update(&kano_fix(T0), ms(T0));
    assert!(s.rtc_implausible && s.rtc_set);
    assert_eq!(s.now, Some(utc(T0)));
    // Without GPS the same reading leaves the time unknown.
    let s = keeper.update(&GpsFix::NONE, ms(T0) + 1_000);
    assert!(s.rtc_implausible && !s.time_valid());
    keeper.destroy().destroy().done();
}

#[test]
fn a_fix_with_an_impossible_position_gives_neither_site_nor_time() {
    // Built directly (the parser already rejects such sentences): the
    // tracker does not rely on the parser alone.
    for (lat, lon) in [(91.0, 8.0), (12.0, 200.0), (f64::NAN, 8.0)] {
        let bad = GpsFix {
            latitude_deg: Coordinate::from_deg(lat),
            longitude_deg: Coordinate::from_deg(lon),
            ..kano_fix(T0)
        };
        assert_eq!(
            gps_time(&bad, ms(T0), &TimeConfig::default()),
            GpsTime::NoFix
        );
        let stored = SiteConfig {
            latitude_deg: 11.9683,
            longitude_deg: 8.4261,
            elevation_m: 480.0,
            utc_offset_h: 0.0,
        };
        let (_, origin) = resolve_site::<f64>(&bad, Some(&stored), None).unwrap();
        assert_eq!(origin, SiteOrigin::Stored);
    }
}
