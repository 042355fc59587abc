//! Fault paths of time and site on the real drivers, through the whole
//! controller: Kano, 2026-03-20 09:00–10:40 UTC, one tick a minute (one a
//! second while an axis homes).
//!
//! | from  | RTC (DS3231, I2C mock)        | GPS (NMEA on a UART) | expected |
//! |-------|-------------------------------|----------------------|----------|
//! | 09:00 | lost power (OSF set)          | no fix (status V)    | site from the stored configuration; time unknown → `WaitForTime`, `RtcInvalid` and `GpsLost` active, panel stowed (α = 0) |
//! | 09:10 | OSF set → set from GPS        | fix                  | RTC written once (exact bytes) at the second epoch, the first that agrees with the one before; tracking |
//! | 09:30 | running                       | silent               | `GpsLost` (use RTC and stored site): tracking on RTC time |
//! | 09:50 | NACK for 3 ticks              | silent               | time unknown → `WaitForTime`, `RtcInvalid` |
//! | 09:53 | running                       | silent               | tracking again, `RtcInvalid` recovered |
//! | 10:10 | running, in step with GPS     | fix                  | `GpsLost` recovered; no fault left |
//!
//! At every table entry applied while tracking, the panel (the motor
//! models' decoded pose) points at NREL SPA's sun within the mechanical
//! tolerance, as in `hw_stepper_day`.

mod common;

use std::cell::Cell;

use common::motor::*;
use common::*;
use drivers::rtc::Ds3231;
use embedded_hal::i2c::{ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};
use sim::sensors::MountSensors;
use sun_algos::{Algorithm, Options};
use suntracker::config::Config;
use suntracker::controller::Controller;
use suntracker::hw::GpsPort;
use suntracker::plan::Phase;
use suntracker::safety::{Fault, Mode};
use suntracker::site::{follow_gps_site, resolve_site, SiteOrigin};
use suntracker::sun::SharedSiteSource;
use suntracker::time::{TimeConfig, TimeKeeper};

const H: u32 = 3600;
const M: u32 = 60;
const BOOT: u32 = 9 * H;
const GPS_FIX: u32 = 9 * H + 10 * M;
const GPS_SILENT: u32 = 9 * H + 30 * M;
const RTC_NACK: u32 = 9 * H + 50 * M;
const RTC_BACK: u32 = 9 * H + 53 * M;
const GPS_BACK: u32 = 10 * H + 10 * M;
const END: u32 = 10 * H + 40 * M;

fn nack() -> ErrorKind {
    ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
}

#[test]
fn lost_power_gps_loss_and_rtc_nack_are_raised_and_recovered() {
    let c_motor = Motor::new(-30.0, -180.0);
    let a_motor = Motor::new(40.0, -90.0);
    let mut i2c = I2cMock::new(&[]);
    let mut keeper = TimeKeeper::new(Ds3231::new(i2c.clone()), TimeConfig::default());
    let uart = MemSerial::default();
    let mut gps = GpsPort::new(uart.clone(), 3_000);

    // Boot: GPS without a fix, so the site is the stored one.
    uart.push(&gps_epoch(DayTime { secs: BOOT }, false));
    let fix = gps.service(BOOT * 1_000).unwrap();
    let stored = Config::default().site;
    let (site, origin) = resolve_site(&fix, Some(&stored), Some("DZ:16000")).unwrap();
    assert_eq!(origin, SiteOrigin::Stored);
    let site_cell = Cell::new(site);
    let source = SharedSiteSource {
        algorithm: Algorithm::Psa2020,
        site: &site_cell,
        options: Options::default(),
    };
    let (config, options) = tracker_config();
    let axes = [stepper_axis(&c_motor), stepper_axis(&a_motor)];
    let mut ctrl: Controller<f64, _, Axis, MountSensors, 360> =
        Controller::new(config, options, source, axes, None).unwrap();

    let mut rtc_stopped = true;
    let mut valid_epochs = 0u32;
    let mut t = BOOT;
    let mut ticks = 0u32;
    let mut last_set_point = None;
    let mut applied_on_rtc_only = 0u32;
    let mut applied = 0u32;
    let mut max_err_deg: f64 = 0.0;
    let mut first_tracking = None;
    let mut resumed_after_nack = None;
    while t < END {
        ticks += 1;
        // GPS.
        let gps_talks = !(GPS_SILENT..GPS_BACK).contains(&t);
        if ticks > 1 && gps_talks {
            uart.push(&gps_epoch(DayTime { secs: t }, t >= GPS_FIX));
        }
        // The monotonic clock runs with UTC here (t < a day: no overflow).
        let now_ms = t * 1_000;
        let fix = gps.service(now_ms).unwrap();
        let gps_valid = gps_talks && t >= GPS_FIX;
        assert_eq!(fix.has_position(), gps_valid, "fix at t={t}");
        if gps_valid {
            valid_epochs += 1;
        }
        // Follows a moved receiver; Kano stays Kano.
        assert!(!follow_gps_site(&site_cell, &fix, 0.01));

        // The exact RTC traffic of this tick.
        let nacking = (RTC_NACK..RTC_BACK).contains(&t);
        let tx: Vec<I2c> = if nacking {
            vec![I2c::write_read(RTC_ADDR, vec![REG_STATUS], vec![0]).with_error(nack())]
        } else if rtc_stopped && gps_valid && valid_epochs >= 2 {
            // One epoch alone does not set a clock: the second, agreeing
            // with the first over the monotonic time between them, does.
            rtc_stopped = false;
            let mut v = vec![read_status(STATUS_OSF)];
            v.extend(set_time(DayTime { secs: t }, STATUS_OSF));
            v
        } else if rtc_stopped {
            vec![read_status(STATUS_OSF)]
        } else {
            vec![read_status(STATUS_RUNNING), read_time(DayTime { secs: t })]
        };
        i2c.update_expectations(&tx);
        let status = keeper.update(&fix, now_ms);
        let fallback = keeper.last_valid().unwrap_or(utc_at(t));
        let report = ctrl.tick(&status.tick_inputs(now_ms, fallback, 0, 60_000));
        let next = next_tick(t, report.homing);
        pump(&mut ctrl, [&c_motor, &a_motor], t, next);

        let faults = ctrl.faults();
        let time_unknown = rtc_stopped || nacking;
        if time_unknown {
            assert_eq!(report.mode, Mode::WaitForTime, "t={t}");
            assert!(faults.is_active(Fault::RtcInvalid), "t={t}");
            // Stowed flat (A axis at 0°) once homed.
            if !report.homing {
                assert!(a_motor.borrow().angle_deg().abs() < 0.02, "t={t}");
            }
        } else {
            assert!(!faults.is_active(Fault::RtcInvalid), "t={t}");
            assert_eq!(status.now, Some(utc_at(t)));
        }
        assert_eq!(faults.is_active(Fault::GpsLost), !gps_valid, "t={t}");

        let tracking = matches!(ctrl.scheduler().phase(), Phase::Tracking { .. });
        if report.mode == Mode::Tracking && tracking {
            first_tracking.get_or_insert(t);
            if t >= RTC_BACK {
                resumed_after_nack.get_or_insert(t);
            }
            if report.set_point != last_set_point && t % 240 < 30 {
                let sun = spa_kano(t - t % 240);
                let err = pointing_error_deg(&c_motor, &a_motor, sun.zenith_deg, sun.azimuth_deg);
                assert!(err <= TOL_DEG, "pointing error {err}° at t={t}");
                max_err_deg = max_err_deg.max(err);
                applied += 1;
                if !gps_valid {
                    applied_on_rtc_only += 1;
                }
            }
            last_set_point = report.set_point;
        }
        t = next;
    }
    i2c.done();

    let faults = ctrl.faults();
    println!(
        "ticks={ticks} applied={applied} on_rtc_only={applied_on_rtc_only} \
         max_err_deg={max_err_deg:.4} raised={} recovered={} first_tracking={:?} \
         resumed_after_nack={:?}",
        faults.raised, faults.recovered, first_tracking, resumed_after_nack
    );
    // Tracking began within two ticks of the first fix, and again within
    // two ticks of the RTC's return.
    assert!(first_tracking.is_some_and(|s| s <= GPS_FIX + 2 * M));
    assert!(resumed_after_nack.is_some_and(|s| s <= RTC_BACK + 2 * M));
    // GPS silent 09:30–10:10 minus the 3 minutes of NACK: 37 minutes on
    // RTC time alone, at least 8 four-minute entries.
    assert!(applied_on_rtc_only >= 8);
    // RtcInvalid twice, GpsLost twice, all recovered.
    assert_eq!(faults.active_count(), 0);
    assert_eq!(faults.raised, 4);
    assert_eq!(faults.recovered, faults.raised);
    assert_eq!(keeper.rtc_sets(), 1);
}
