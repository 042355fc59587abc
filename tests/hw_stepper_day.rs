//! One whole simulated day of the controller on the real drivers with mocked
//! buses: Kano (11.9683° N, 8.4261° E), 2026-03-20, one tick a minute.
//!
//! - RTC: the real DS3231 driver on an embedded-hal-mock
//!   I2C bus; every tick's transactions are set exactly from the datasheet
//!   register layout (status read, time burst read; once, the setting from
//!   GPS because the RTC starts 7 s slow).
//! - GPS: the real NMEA reader on an in-memory UART fed one RMC + GGA epoch
//!   per tick.
//! - Axes: the real H-bridge stepper driver (half-step, ramps, min limit
//!   switch, coil release) through `hw::StepperAxis`. The step pins are too
//!   busy for a transaction list (≈10⁵ steps a day), so they drive a small
//!   recording motor model instead: it turns the four bridge inputs into the
//!   coil current vector and the rotor follows it (half-step phases at 45°),
//!   so the axis angle comes from what the driver really put on its pins.
//!
//! Independent check: the panel normal the *motor model* reached (from the
//! decoded coil phases, `n = Rz(γ)·Rx(α)·ẑ` written out below) against NREL
//! SPA (Reda & Andreas 2004, `sun_algos::Algorithm::Spa`), while the
//! controller computes its table with PSA+ (Blanco et al. 2020,
//! `Algorithm::Psa2020`): a different algorithm and a different code path
//! for the kinematics.

mod common;

use std::cell::Cell;

use common::motor::*;
use common::*;
use drivers::rtc::Ds3231;
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};
use sim::sensors::MountSensors;
use sun_algos::{Algorithm, Options};
use suntracker::config::Config;
use suntracker::controller::{Controller, TickInputs};
use suntracker::hw::GpsPort;
use suntracker::plan::Phase;
use suntracker::safety::Mode;
use suntracker::site::{resolve_site, SiteOrigin};
use suntracker::sun::SharedSiteSource;
use suntracker::time::{TimeConfig, TimeKeeper};

// ---------------------------------------------------------------- the day

#[test]
fn kano_equinox_day_on_real_drivers() {
    // Devices.
    let c_motor = Motor::new(20.0, -180.0);
    let a_motor = Motor::new(10.0, -90.0);
    let mut i2c = I2cMock::new(&[]);
    let mut keeper = TimeKeeper::new(
        Ds3231::new(i2c.clone()),
        TimeConfig {
            max_drift_s: 2,
            ..TimeConfig::default()
        },
    );
    let uart = MemSerial::default();
    let mut gps = GpsPort::new(uart.clone(), 3_000);

    // Power-on: the first GPS epoch gives the site (GPS first, then the stored site).
    let mut t: u32 = 60; // seconds after 2026-03-20 00:00 UTC
    uart.push(&gps_epoch(DayTime { secs: t }, true));
    let fix = gps.service(t * 1_000).unwrap();
    let stored = Config::default().site;
    let (site, origin) = resolve_site(&fix, Some(&stored), None).unwrap();
    assert_eq!(origin, SiteOrigin::Gps);
    assert_eq!(
        (
            site.latitude_deg(),
            site.longitude_deg(),
            site.elevation_m()
        ),
        (11.9683, 8.4261, 480.0)
    );
    let site_cell = Cell::new(site);
    let source = SharedSiteSource {
        algorithm: Algorithm::Psa2020,
        site: &site_cell,
        options: Options::default(),
    };

    // The tracker: level mount, open loop on counted half-steps (Li et al.'s
    // (2022) H-bridge steppers have no encoders), re-homed every night.
    let (config, options) = tracker_config();
    let axes = [stepper_axis(&c_motor), stepper_axis(&a_motor)];
    let mut ctrl: Controller<f64, _, Axis, MountSensors, 360> =
        Controller::new(config, options, source, axes, None).unwrap();
    // Boot at midnight: the non-blocking drives home during the night
    // (the controller never stops an axis that is still homing unless a
    // fault asks for a safe stop) and wait facing the coming sunrise.

    let mut rtc_offset_s: i64 = -7; // the RTC starts 7 s slow
    let mut last_set_point = None;
    let mut applied = 0usize;
    let mut max_err_deg: f64 = 0.0;
    let mut ticks = 0u32;
    let mut homing_ticks = 0u32;
    let mut first_track_s = None;
    let mut go_home_s = None;
    let end_s = 23 * 3600;
    while t < end_s {
        ticks += 1;
        // The monotonic clock runs with UTC here (t < 23 h: no overflow).
        let now_ms = t * 1_000;
        // GPS epoch of this second, then the exact RTC traffic of the tick.
        if ticks > 1 {
            uart.push(&gps_epoch(DayTime { secs: t }, true));
        }
        let fix = gps.service(now_ms).unwrap();
        let rtc_reads = DayTime {
            secs: (i64::from(t) + rtc_offset_s) as u32,
        };
        let mut tx: Vec<I2c> = vec![read_status(STATUS_RUNNING), read_time(rtc_reads)];
        // GPS time is adopted from the second epoch, the first that agrees
        // with the one before it (the RTC, 7 s off, does not confirm the
        // first): until then the RTC's time is in force.
        let gps_adopted = ticks > 1;
        let rtc_was_off_s = rtc_offset_s;
        if rtc_offset_s.abs() > 2 && gps_adopted {
            tx.extend(set_time(DayTime { secs: t }, STATUS_RUNNING));
            rtc_offset_s = 0;
        }
        i2c.update_expectations(&tx);
        let status = keeper.update(&fix, now_ms);
        if gps_adopted {
            assert_eq!(status.now, Some(utc_at(t)), "GPS time at t={t}");
        } else {
            let rtc_s = (i64::from(t) + rtc_was_off_s) as u32;
            assert_eq!(status.now, Some(utc_at(rtc_s)), "RTC time at t={t}");
        }

        let report = ctrl.tick(&TickInputs {
            now_ms,
            now: status.tick_time(utc_at(t)),
            time_valid: status.time_valid(),
            gps_fix: status.gps_fix,
            gps_time_implausible: status.gps_time_implausible,
            gps_time_unstable: status.gps_time_unstable,
            gps_position_unstable: false,
            wind_pulses: 0,
            wind_interval_ms: 60_000,
            stow_inputs: Default::default(),
        });
        if report.homing {
            homing_ticks += 1;
        }

        // The main loop runs the drivers until the motion (and the coil
        // settle time) is over, at most until the next minute.
        let next = next_tick(t, report.homing);
        pump(&mut ctrl, [&c_motor, &a_motor], t, next);

        // A new table entry applied: where does the panel point now?
        let tracking = matches!(ctrl.scheduler().phase(), Phase::Tracking { .. });
        if report.mode == Mode::Tracking && tracking && report.set_point != last_set_point {
            let late = t % 240;
            assert!(late < 30, "entry applied {late} s after its time");
            let entry_s = t - late;
            let sun = spa_kano(entry_s);
            let err = pointing_error_deg(&c_motor, &a_motor, sun.zenith_deg, sun.azimuth_deg)
                - below_reach_deg(sun.zenith_deg);
            assert!(err <= TOL_DEG, "pointing error {err}° at t={t}");
            max_err_deg = max_err_deg.max(err);
            applied += 1;
            first_track_s.get_or_insert(t);
        }
        if report.mode == Mode::Tracking && tracking {
            last_set_point = report.set_point;
        }
        if first_track_s.is_some() && go_home_s.is_none() && report.mode == Mode::Night {
            go_home_s = Some(t);
        }
        t = next;
    }
    i2c.done();

    let first = first_track_s.expect("tracked");
    let home_at = go_home_s.expect("went home");
    let table = ctrl.scheduler().table();
    println!(
        "ticks={ticks} homing_ticks={homing_ticks} entries={} applied={applied} \
         first={first} s go_home={home_at} s max_err_deg={max_err_deg:.4} \
         c_writes={} a_writes={}",
        table.len(),
        c_motor.borrow().pin_writes,
        a_motor.borrow().pin_writes
    );
    // Every table entry was applied, once.
    assert_eq!(applied, table.len());
    // The daylight span against SPA (geometric): the first and last entries
    // lie between rise/set of the upper limb with refraction (−0.833°) and
    // of the centre, the entries just outside have the sun down.
    let elev = |s: u32| 90.0 - spa_kano(s).zenith_deg;
    let last_entry_s = first + 240 * (table.len() as u32 - 1);
    assert!(elev(first) > -0.9 && elev(first - 240) < 0.0, "{first}");
    assert!(elev(last_entry_s) > -0.9 && elev(last_entry_s + 240) < 0.0);
    assert!(home_at > last_entry_s && home_at <= last_entry_s + 300);

    // Home at day end: the panel faces the day's first entry again (Li et
    // al. 2022), checked against SPA at that entry's time.
    let home_sun = spa_kano(first);
    let err = pointing_error_deg(
        &c_motor,
        &a_motor,
        home_sun.zenith_deg,
        home_sun.azimuth_deg,
    ) - below_reach_deg(home_sun.zenith_deg);
    assert!(err <= TOL_DEG, "home pose off by {err}°");

    // Night: coils released, no fault left, nothing went wrong on the pins.
    for (name, m) in [("C", &c_motor), ("A", &a_motor)] {
        let m = m.borrow();
        assert!(!m.energised(), "{name} coils still powered at night");
        assert_eq!(
            (m.shoot_through, m.lost_sync, m.hit_stop),
            (0, 0, 0),
            "{name} axis pin faults"
        );
    }
    // Homed twice each (boot and night): the fast approach of each homing
    // ends with the driver refusing to step past the closed switch.
    for ax in ctrl.axes().iter() {
        assert!(
            ax.drive().limit_stops() >= 2,
            "{}",
            ax.drive().limit_stops()
        );
    }
    assert_eq!(ctrl.faults().active_count(), 0);
    assert_eq!(keeper.rtc_sets(), 1);
    let stats = gps.stats();
    assert_eq!(stats.sentences, stats.accepted);
}
