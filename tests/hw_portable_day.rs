//! A whole Kano day (2026-03-20) of a portable, tilted mount (α0 = 4°,
//! β0 = −6°, γ0 = 25°) whose attitude the controller measures every tick
//! through the real ADXL345 and QMC5883L drivers on a mocked I2C bus
//! (transaction-exact, bytes from the datasheets: `common::mount`),
//! with the axes on the real H-bridge stepper driver (motor model of
//! `common::motor`).
//!
//! Independent check: the panel normal in the horizontal frame is
//! `T·n(γ, α)` with `T` and `n` written out in the test helpers and the
//! motor models' angles, compared with NREL SPA; the controller works with
//! PSA+ and its own kinematics. The bound is set by the sensors: the
//! ADXL345's 3.9 mg steps give the tilt to ≈ 0.1°, which moves the
//! pointing by up to about twice that.

mod common;

use common::motor::*;
use common::mount::*;
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};
use sun_algos::{Algorithm, Options, Site};
use suntracker::controller::{AttitudeSource, Controller};
use suntracker::plan::Phase;
use suntracker::safety::Mode;
use suntracker::sun::AlgorithmSource;

const SAMPLES: u8 = 4;
/// Pointing bound of the measured attitude, degrees (measured: 0.086°).
const TOL_PORTABLE_DEG: f64 = 0.2;

/// `m·v`: tracker → horizontal.
fn to_horizontal(m: &Mat, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| (0..3).map(|j| m[i][j] * v[j]).sum())
}

/// Pointing error of the tilted mount's panel, less what the mount cannot
/// reach (the sun below the mount's own plane, where A = ±90° stops).
fn portable_error_deg(gamma_deg: f64, alpha_deg: f64, zenith_deg: f64, azimuth_deg: f64) -> f64 {
    let t = t_matrix();
    let n = to_horizontal(&t, normal_xyz(gamma_deg, alpha_deg));
    let sun = sun_xyz(90.0 - zenith_deg, azimuth_deg);
    let sun_t = to_tracker(&t, sun);
    let below_plane_deg = (-sun_t[2].clamp(-1.0, 1.0).asin().to_degrees()).max(0.0);
    angle_deg(n, sun) - below_plane_deg
}

#[test]
fn portable_mount_day_with_measured_attitude() {
    let c_motor = Motor::new(60.0, -180.0);
    let a_motor = Motor::new(-20.0, -90.0);
    let mut bus = I2cMock::new(&init());
    let sensors = sensors(&bus);
    let (config, mut options) = tracker_config();
    options.attitude = AttitudeSource::Sensors;
    options.sensor_samples = SAMPLES;
    let site = Site::with_elevation(11.9683, 8.4261, 480.0).unwrap();
    let source = AlgorithmSource {
        algorithm: Algorithm::Psa2020,
        site,
        options: Options::default(),
    };
    let axes = [stepper_axis(&c_motor), stepper_axis(&a_motor)];
    let mut ctrl: Controller<f64, _, Axis, Sensors, 360> =
        Controller::new(config, options, source, axes, Some(sensors)).unwrap();
    // Boot at midnight: homing and waiting need no stow (see hw_stepper_day).
    let tick_tx: Vec<I2c> = (0..SAMPLES)
        .flat_map(|_| {
            let mut v = vec![acc_read()];
            v.extend(mag_read());
            v
        })
        .collect();

    let mut t: u32 = 60;
    let mut last_set_point = None;
    let (mut applied, mut max_err_deg, mut first) = (0usize, 0.0f64, None);
    while t < 23 * 3600 {
        bus.update_expectations(&tick_tx);
        let report = ctrl.tick(&calm_tick(t));
        let next = next_tick(t, report.homing);
        pump(&mut ctrl, [&c_motor, &a_motor], t, next);
        let tracking = matches!(ctrl.scheduler().phase(), Phase::Tracking { .. });
        if report.mode == Mode::Tracking && tracking {
            if report.set_point != last_set_point && t % 240 < 30 {
                let sun = spa_kano(t - t % 240);
                let err = portable_error_deg(
                    c_motor.borrow().angle_deg(),
                    a_motor.borrow().angle_deg(),
                    sun.zenith_deg,
                    sun.azimuth_deg,
                );
                assert!(err <= TOL_PORTABLE_DEG, "pointing error {err}° at t={t}");
                max_err_deg = max_err_deg.max(err);
                applied += 1;
                first.get_or_insert(t - t % 240);
            }
            last_set_point = report.set_point;
        }
        t = next;
    }
    bus.done();

    let m = ctrl.attitude();
    println!(
        "portable day: entries={} applied={applied} max_err_deg={max_err_deg:.3} \
         attitude=({:.3}, {:.3}, {:.3})",
        ctrl.scheduler().table().len(),
        m.alpha0_deg,
        m.beta0_deg,
        m.gamma0_deg
    );
    assert_eq!(applied, ctrl.scheduler().table().len());
    assert!((m.alpha0_deg - ALPHA0).abs() < 0.3);
    assert!((m.beta0_deg - BETA0).abs() < 0.3);
    assert!((m.gamma0_deg - GAMMA0).abs() < 0.3);
    // Home at night: facing the day's first entry again.
    let sun = spa_kano(first.expect("tracked"));
    let err = portable_error_deg(
        c_motor.borrow().angle_deg(),
        a_motor.borrow().angle_deg(),
        sun.zenith_deg,
        sun.azimuth_deg,
    );
    assert!(err <= TOL_PORTABLE_DEG, "home pose off by {err}°");
    assert_eq!(ctrl.faults().active_count(), 0);
}
