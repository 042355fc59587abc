//! Servo axes on the real drivers: `drivers::servo::ContinuousServo` (PWM),
//! `drivers::encoder::SharedEncoder` (the Gray-code decoder an interrupt
//! would feed) and `drivers::servo::PositionController`, through
//! `hw::ServoAxis`, closed loop in the whole controller over a Kano day.
//!
//! The PWM channel and the encoder lines are the servo model of
//! `common::servo`: the pulse
//! width sets the motor speed (FS5106R class, Chowdhury et al. 2019: 1.5 ms
//! stop, ±0.5 ms full speed, taken here as 400°/s at the motor, ±8 µs
//! dead zone), the motor turns a 300-line encoder (YMT22 class; ×4 = 1200
//! edges per revolution, each fed to the decoder as its A/B levels) and a
//! 100:1 gear to the axis. Pointing is checked against NREL SPA as in
//! `hw_stepper_day`.

mod common;

use std::cell::RefCell;
use std::rc::Rc;

use common::motor::{
    angle_deg, below_reach_deg, calm_tick, next_tick, normal_xyz, spa_kano, sun_xyz, TOL_DEG,
};
use common::servo::{Pwm, ServoModel, ServoSpec, Switch};
use drivers::encoder::SharedEncoder;
use drivers::servo::{ContinuousServo, PositionController, ServoConfig};
use sim::sensors::MountSensors;
use sim::servo::{ServoSpec as SpeedLaw, FRAME_S};
use sun_algos::{Algorithm, Options, Site};
use suntracker::config::{AxisConfig, Config};
use suntracker::controller::{Controller, ControllerOptions};
use suntracker::hw::ServoAxis;
use suntracker::motion::{AxisController, AxisDrive, FeedbackMode, HomeState};
use suntracker::plan::Phase;
use suntracker::safety::Mode;
use suntracker::sun::AlgorithmSource;

const EDGES_PER_MOTOR_REV: u32 = 1200;
const GEAR: f64 = 100.0;
const MOTOR_DEG_PER_EDGE: f64 = 360.0 / EDGES_PER_MOTOR_REV as f64;

/// An FS5106R-class servo as these tests take it: ±0.5 ms full speed,
/// 400°/s at the motor, ±8 µs dead zone, a 300-line encoder on the motor
/// and a 100:1 gear; the pulse acts at once; 1 µs per duty step.
const SPEC: ServoSpec = ServoSpec {
    law: SpeedLaw {
        neutral_us: 1_500.0,
        dead_band_us: 8.0,
        min_pulse_us: 1_000.0,
        max_pulse_us: 2_000.0,
        // 400 °/s at the motor.
        no_load_rpm: 400.0 / 6.0,
        signal_timeout_s: 3.0 * FRAME_S,
    },
    gear: GEAR,
    edges_per_rev: EDGES_PER_MOTOR_REV,
    frame_s: None,
    duty_per_us: 1.0,
};

type Axis<'a> = ServoAxis<'a, Pwm, SharedEncoder, Switch>;

fn control() -> PositionController {
    PositionController {
        kp_per_count: 0.01,
        deadband_counts: 1,
        max_speed: 1.0,
        min_speed: 0.03,
    }
}

fn axis_config(min_deg: f32, max_deg: f32) -> AxisConfig {
    AxisConfig {
        counts_per_motor_rev: EDGES_PER_MOTOR_REV,
        microsteps: 1,
        gear_ratio: GEAR as f32,
        min_deg,
        max_deg,
        home_deg: min_deg,
        backlash_deg: 0.0,
        max_speed_deg_s: 4.0,
        deadband_deg: 0.05,
        continuous: 0,
        drive: suntracker::config::DriveKind::ServoEncoder as u8,
        ..suntracker::config::Config::DEFAULT.axes[0]
    }
}

fn servo_axis<'a>(
    model: &Rc<RefCell<ServoModel>>,
    encoder: &'a SharedEncoder,
    cfg: &AxisConfig,
) -> Axis<'a> {
    let servo = ContinuousServo::new(Pwm(Rc::clone(model)), ServoConfig::STANDARD_50HZ).unwrap();
    let switch = Switch {
        model: Rc::clone(model),
        active_low: false,
    };
    ServoAxis::new(servo, encoder, switch, false, control(), cfg)
}

/// Polls every millisecond until the axis is on target (speed 0, nothing
/// pending) or `max_s` elapsed; returns the seconds used.
fn run(axis: &mut Axis, model: &Rc<RefCell<ServoModel>>, enc: &SharedEncoder, max_s: f64) -> f64 {
    let mut t = 0.0;
    while t < max_s {
        let speed = axis.poll().unwrap();
        model.borrow_mut().advance(0.001, enc);
        t += 0.001;
        if speed == 0.0 && axis.pending() == 0 {
            break;
        }
    }
    t
}

#[test]
fn a_move_settles_within_one_count() {
    let model = ServoModel::new(SPEC, 0.0, -180.0);
    let enc = SharedEncoder::new();
    let cfg = axis_config(-180.0, 180.0);
    let mut axis = servo_axis(&model, &enc, &cfg);
    // 10° of axis = 10 × 1200 × 100 / 360 = 3333 counts.
    axis.move_counts(3333).unwrap();
    assert_eq!(axis.pending(), 3333);
    let used = run(&mut axis, &model, &enc, 30.0);
    assert!(
        (i64::from(axis.count()) - 3333).abs() <= 1,
        "{}",
        axis.count()
    );
    assert_eq!(axis.pending(), 0);
    assert_eq!(axis.pulse_us(), 1500, "stopped at neutral");
    // 1000° of motor at ≤ 400°/s: at least 2.5 s.
    assert!((2.5..30.0).contains(&used), "{used}");
    assert_eq!(enc.errors(), 0);
    let m = model.borrow();
    assert!((m.output_deg() - 10.0).abs() <= 2.0 * MOTOR_DEG_PER_EDGE / GEAR);
    assert!(m.min_pulse_us >= 1000.0 && m.max_pulse_us <= 2000.0);
}

#[test]
fn homing_gives_the_encoder_its_reference() {
    let model = ServoModel::new(SPEC, -150.0, -180.0);
    let enc = SharedEncoder::new();
    let cfg = axis_config(-180.0, 180.0);
    let mut ax = AxisController::new(servo_axis(&model, &enc, &cfg), cfg);
    assert_eq!(ax.drive_mut().encoder_deg(), Ok(None));
    let mut steps = 0;
    loop {
        steps += 1;
        assert!(steps < 10_000, "homing did not finish");
        match ax.home_step(1.0, 0).unwrap() {
            HomeState::Done => break,
            _ => {
                let m = Rc::clone(&model);
                run(ax.drive_mut(), &m, &enc, 5.0);
            }
        }
    }
    let truth = model.borrow().output_deg();
    let fb = f64::from(ax.drive_mut().encoder_deg().unwrap().unwrap());
    // The switch closes at −180°: found within the slow approach's step.
    assert!((truth + 180.0).abs() < 0.03, "{truth}");
    assert!((fb - truth).abs() < 0.03, "{fb} vs {truth}");
    // Closed loop to 12.5°.
    for _ in 0..3 {
        let fb = ax.drive_mut().encoder_deg().unwrap();
        ax.update(12.5, FeedbackMode::ClosedLoop, fb).unwrap();
        let m = Rc::clone(&model);
        run(ax.drive_mut(), &m, &enc, 120.0);
    }
    let truth = model.borrow().output_deg();
    assert!((truth - 12.5).abs() < 0.05, "{truth}");
}

#[test]
fn closed_loop_day_on_servo_axes() {
    let c_model = ServoModel::new(SPEC, 0.0, -180.0);
    let a_model = ServoModel::new(SPEC, 30.0, -90.0);
    let (c_enc, a_enc) = (SharedEncoder::new(), SharedEncoder::new());
    let config = Config {
        axes: [axis_config(-180.0, 180.0), axis_config(-90.0, 90.0)],
        ..Config::default()
    };
    let options = ControllerOptions {
        feedback: FeedbackMode::ClosedLoop,
        ..ControllerOptions::default()
    };
    let site = Site::with_elevation(11.9683, 8.4261, 480.0).unwrap();
    let source = AlgorithmSource {
        algorithm: Algorithm::Psa2020,
        site,
        options: Options::default(),
    };
    let axes = [
        servo_axis(&c_model, &c_enc, &config.axes[0]),
        servo_axis(&a_model, &a_enc, &config.axes[1]),
    ];
    let mut ctrl: Controller<f64, _, Axis, MountSensors, 360> =
        Controller::new(config, options, source, axes, None).unwrap();
    // Boot at midnight: homing and waiting need no stow (see hw_stepper_day).

    let mut t: u32 = 5 * 3600;
    let end = 19 * 3600 + 30 * 60;
    let mut last_set_point = None;
    let (mut applied, mut max_err_deg) = (0u32, 0.0f64);
    while t < end {
        let report = ctrl.tick(&calm_tick(t));
        let next = next_tick(t, report.homing);
        // The main loop: both axes every millisecond until on target.
        let mut s = 0.0;
        while s < f64::from(next - t) {
            let mut busy = false;
            for (ax, (m, e)) in ctrl
                .axes_mut()
                .iter_mut()
                .zip([(&c_model, &c_enc), (&a_model, &a_enc)])
            {
                let d = ax.drive_mut();
                let sp = d.poll().unwrap();
                busy |= sp != 0.0 || d.pending() != 0;
                m.borrow_mut().advance(0.001, e);
            }
            s += 0.001;
            if !busy {
                break;
            }
        }
        let tracking = matches!(ctrl.scheduler().phase(), Phase::Tracking { .. });
        if report.mode == Mode::Tracking && tracking {
            if report.set_point != last_set_point && t % 240 < 30 {
                let sun = spa_kano(t - t % 240);
                let n = normal_xyz(c_model.borrow().output_deg(), a_model.borrow().output_deg());
                let err = angle_deg(n, sun_xyz(90.0 - sun.zenith_deg, sun.azimuth_deg))
                    - below_reach_deg(sun.zenith_deg);
                assert!(err <= TOL_DEG, "pointing error {err}° at t={t}");
                max_err_deg = max_err_deg.max(err);
                applied += 1;
            }
            last_set_point = report.set_point;
        }
        t = next;
    }
    let table = ctrl.scheduler().table();
    println!(
        "servo day: entries={} applied={applied} max_err_deg={max_err_deg:.4} raised={}",
        table.len(),
        ctrl.faults().raised
    );
    assert_eq!(applied as usize, table.len());
    // Home at night: facing the day's first entry again.
    let first = table.get(0).unwrap().time;
    let (h, m, _, _) = first.hms_milli();
    let sun = spa_kano(u32::from(h) * 3600 + u32::from(m) * 60);
    let n = normal_xyz(c_model.borrow().output_deg(), a_model.borrow().output_deg());
    let err = angle_deg(n, sun_xyz(90.0 - sun.zenith_deg, sun.azimuth_deg))
        - below_reach_deg(sun.zenith_deg);
    assert!(err <= TOL_DEG, "home pose off by {err}°");
    assert_eq!(ctrl.faults().active_count(), 0);
    assert_eq!((c_enc.errors(), a_enc.errors()), (0, 0));
}
