//! The timed axis (`hw::TimedAxis`: a DC motor run for the time a move
//! takes at a calibrated speed, no feedback) on the simulated gear motor
//! (`sim::dc_motor`, Pololu 37D 131.25:1 at 12 V, through a further 60:1
//! worm of 40 %: 7,875:1, 7.62 °/s at no load), polled every millisecond by
//! `sim::dc_drive`.
//!
//! The expected angles come from the motor model's own no-load speed
//! (`MotorSpec::no_load_motor_rad_s`, from the data-sheet figures) times the
//! run time, not from the axis's arithmetic: the model's motor is linear
//! (viscous friction only) with one mechanical time constant driven and
//! braked, so the angle of a run of T is the speed times T whatever its
//! start-up lag.

use sim::dc_drive::{worm_slew_axis_config, worm_slew_motor, DcDrive, DcDriveSpec, SimTimedAxis};
use sim::dc_motor::MotorSpec;
use sim::plant::{Injected, SimAxis};
use suntracker::config::AxisConfig;
use suntracker::hw::{TimedAxisConfig, TimedAxisConfigError};
use suntracker::motion::{AxisController, AxisDrive, DriveFault, FeedbackMode, HomeState};

fn spec() -> MotorSpec {
    worm_slew_motor()
}

/// The axis's no-load speed at 12 V, °/s.
fn speed_deg_s() -> f64 {
    let s = spec();
    (s.no_load_motor_rad_s() / s.gear_ratio).to_degrees()
}

/// 1,400 counts per degree, switch at −90°.
fn axis_config() -> AxisConfig {
    worm_slew_axis_config(-90.0, 90.0)
}

fn drive(config: TimedAxisConfig, start_deg: f64) -> DcDrive<SimTimedAxis> {
    DcDrive::new(
        DcDriveSpec {
            motor: spec(),
            bridge: drivers::dc_motor::Config {
                ramp_permille_per_ms: 0,
                rest: drivers::dc_motor::RestMode::Brake,
            },
            firmware: config,
        },
        &axis_config(),
        -90.0,
        90.0,
        start_deg,
    )
    .unwrap()
}

fn calibrated() -> TimedAxisConfig {
    let v = speed_deg_s() as f32;
    TimedAxisConfig {
        forward_deg_s: v,
        backward_deg_s: v,
        duty_permille: 1_000,
        calibration_supply_mv: 12_000,
        max_current_ma: 3_000,
        overcurrent_ms: 100,
        lag_ms: 120,
    }
}

#[test]
fn runs_land_on_the_speed_times_the_time() {
    assert!((speed_deg_s() - 7.619).abs() < 0.001, "{}", speed_deg_s());
    let mut d = drive(calibrated(), 0.0);
    let mut expected = 0.0f64;
    let mut worst = 0.0f64;
    // Tracker steps, slews both ways, a nudge of a few milliseconds.
    for deg in [0.25, 0.25, 0.25, 45.0, -60.0, 0.1, -0.1, 30.0, 0.02, -15.0] {
        d.begin_tick(120.0);
        d.move_counts((deg * 1_400.0) as i32).unwrap();
        assert_eq!(d.pending(), 0, "not done within the tick");
        expected += deg;
        let err = (d.output_deg() - expected).abs();
        worst = worst.max(err);
        // Run times are whole milliseconds: ±0.5 ms at 7.62 °/s is
        // ±0.0038°, plus the rounding of the counts (1/1400°).
        assert!(err < 0.01, "{deg}°: at {} for {expected}", d.output_deg());
    }
    println!("worst {worst:.4}° over the moves");
}

/// A day of tracker steps of 0.25° (32.8 ms each at 7.62 °/s): each run's
/// rounding to whole milliseconds is carried into the next, so 400 of them
/// end within a millisecond's travel of 100°, not 400 roundings of 0.2 ms
/// (0.6°) away.
#[test]
fn the_rounding_of_many_short_runs_does_not_add_up() {
    let mut d = drive(calibrated(), -80.0);
    for _ in 0..400 {
        d.begin_tick(60.0);
        d.move_counts(350).unwrap();
    }
    let err = d.output_deg() - 20.0;
    println!("400 steps of 0.25°: {err:+.4}°");
    assert!(err.abs() < 0.008, "{err}");
}

/// A run whose end comes in a long pass of the main loop (30 ms from
/// 20 ms into a 32.8 ms step: its end served 17 ms late) turns the motor
/// 0.13° on; the next step is that much shorter, so the axis is back within
/// a millisecond's travel of its count, not 0.13° off until its homing.
#[test]
fn a_run_ended_late_is_made_up_by_the_next() {
    let mut d = drive(calibrated(), 0.0);
    d.begin_tick(60.0);
    d.long_pass(20, 30);
    d.move_counts(350).unwrap();
    let over = d.output_deg() - 0.25;
    // 17 ms at 7.62 °/s is 0.13°.
    assert!(over > 0.1, "ran on {over:+.4}°");
    d.begin_tick(60.0);
    d.move_counts(350).unwrap();
    let err = d.output_deg() - 0.5;
    println!("ran on {over:+.4}° in the long pass, {err:+.4}° after the next step");
    assert!(err.abs() < 0.008, "{err}");
}

#[test]
fn a_miscalibrated_speed_errs_in_proportion() {
    // Calibrated 5 % slow: every run is 5 % long.
    let v = (speed_deg_s() * 0.95) as f32;
    let mut d = drive(
        TimedAxisConfig {
            forward_deg_s: v,
            backward_deg_s: v,
            duty_permille: 1_000,
            calibration_supply_mv: 0,
            ..calibrated()
        },
        0.0,
    );
    d.begin_tick(120.0);
    d.move_counts(40 * 1_400).unwrap();
    let want = 40.0 / 0.95;
    assert!((d.output_deg() - want).abs() < 0.02, "{}", d.output_deg());
}

/// On a battery at 11.9 V the motor turns at 11.9/12 of its calibrated
/// speed; told the supply (as a board's ADC reads it), the axis lengthens
/// its runs to match.
#[test]
fn runs_follow_the_measured_supply() {
    let run = |measured: bool| {
        let mut d = drive(calibrated(), 0.0);
        if measured {
            d.set_supply_v(11.9);
        } else {
            // The motor slows, the firmware is not told.
            let mut bare = drive(
                TimedAxisConfig {
                    calibration_supply_mv: 0,
                    ..calibrated()
                },
                0.0,
            );
            bare.set_supply_v(11.9);
            d = bare;
        }
        d.begin_tick(120.0);
        d.move_counts(90 * 1_400).unwrap();
        d.output_deg()
    };
    // Uncompensated: 90° × 11.9/12 = 89.25°.
    let bare = run(false);
    assert!((bare - 90.0 * 11.9 / 12.0).abs() < 0.01, "{bare}");
    // Compensated: within the ADC's 19.6 mV step (0.16 %, 0.15°).
    let fixed = run(true);
    assert!((fixed - 90.0).abs() < 0.15, "{fixed}");
}

/// A slew of 40° meets an obstacle at 5°: the jammed motor draws its
/// stall current, 5.5 A at full duty, above the 3 A limit: an obstruction
/// 100 ms later, reported once, the motor braked, moves refused. Once the
/// obstacle is gone the retry (clearing the fault) runs the part of the
/// run not done, and the axis ends at 40°.
#[test]
fn an_obstruction_stops_the_run_and_the_retry_finishes_it() {
    let mut d = drive(calibrated(), 0.0);
    // Jam the output once it passes 5°: ticks of 10 ms until then.
    d.begin_tick(0.0);
    d.move_counts(40 * 1_400).unwrap();
    let mut t = 0;
    while d.output_deg() < 5.0 {
        d.begin_tick(0.01);
        t += 10;
        assert!(t < 2_000, "never reached 5°");
    }
    d.inject(Injected {
        obstructed: true,
        ..Injected::default()
    });
    d.begin_tick(1.0);
    assert_eq!(d.take_fault(), Some(DriveFault::Obstruction));
    assert_eq!(d.take_fault(), None, "reported once");
    assert!(d.fault_latched());
    assert_eq!(d.pending(), 0);
    assert!(d.move_counts(100).is_err(), "moves refused while latched");
    let held_at = d.output_deg();
    assert!((5.0..5.2).contains(&held_at), "{held_at}");
    d.inject(Injected::default());
    d.clear_fault();
    d.begin_tick(10.0);
    let end = d.output_deg();
    println!("held at {held_at:.3}°, retried to {end:.3}°");
    assert!((end - 40.0).abs() < 0.1, "{end}");
}

/// A stop while the obstruction is latched (a controller with no target
/// stops its axes at every tick) keeps the part of the run not done: the
/// controller counted the whole move when it commanded it, and once the
/// obstacle goes the retry still brings the axis to the controller's
/// count (0° to 40° through an obstacle at 5°).
#[test]
fn a_stop_while_obstructed_keeps_the_run_for_the_retry() {
    let mut ax = AxisController::new(drive(calibrated(), -70.0), axis_config());
    let mut now = 0u32;
    while ax.home_state() != HomeState::Done {
        ax.drive_mut().begin_tick(1.0);
        now += 1_000;
        ax.home_step(0.45, now).unwrap();
        assert!(now < 200_000, "not homed");
    }
    // Where the axis rests at its home count (the run-on past the switch,
    // as in `homing_stops_on_the_switch_then_moves_by_time`).
    let home_at = ax.drive().output_deg();
    // Each tick's moves run within it (`DcDrive::begin_tick`).
    ax.drive_mut().begin_tick(20.0);
    ax.update(0.0, FeedbackMode::OpenLoop, None).unwrap();
    ax.drive_mut().begin_tick(0.0);
    ax.update(40.0, FeedbackMode::OpenLoop, None).unwrap();
    let mut t = 0;
    while ax.drive().output_deg() < 5.0 {
        ax.drive_mut().begin_tick(0.01);
        t += 10;
        assert!(t < 2_000, "never reached 5°");
    }
    ax.drive_mut().inject(Injected {
        obstructed: true,
        ..Injected::default()
    });
    ax.drive_mut().begin_tick(1.0);
    assert_eq!(ax.drive_mut().take_fault(), Some(DriveFault::Obstruction));
    for _ in 0..3 {
        ax.stop().unwrap();
        ax.drive_mut().begin_tick(1.0);
    }
    assert!(
        (ax.counted_deg() - 40.0).abs() < 1e-3,
        "{}",
        ax.counted_deg()
    );
    ax.drive_mut().inject(Injected::default());
    ax.drive_mut().clear_fault();
    ax.drive_mut().begin_tick(10.0);
    let end = ax.drive().output_deg() - home_at;
    assert!((end - 130.0).abs() < 0.1, "retried to {end} from home");
}

/// The same going backward: jammed on the way from 40° down to 5°, once
/// it passes 30°; the part of the run kept for the retry is negative and
/// the retry ends the axis at 5°.
#[test]
fn an_obstruction_on_a_backward_run_keeps_its_rest_for_the_retry() {
    let mut d = drive(calibrated(), 40.0);
    d.begin_tick(0.0);
    d.move_counts(-35 * 1_400).unwrap();
    let mut t = 0;
    while d.output_deg() > 30.0 {
        d.begin_tick(0.01);
        t += 10;
        assert!(t < 3_000, "never reached 30°");
    }
    d.inject(Injected {
        obstructed: true,
        ..Injected::default()
    });
    d.begin_tick(1.0);
    assert_eq!(d.take_fault(), Some(DriveFault::Obstruction));
    let held_at = d.output_deg();
    assert!((29.8..30.0).contains(&held_at), "{held_at}");
    d.inject(Injected::default());
    d.clear_fault();
    assert!(d.pending() < -30_000, "the rest kept: {}", d.pending());
    d.begin_tick(10.0);
    let end = d.output_deg();
    println!("held at {held_at:.3}°, retried to {end:.3}°");
    assert!((end - 5.0).abs() < 0.1, "{end}");
}

/// A board's timed axis takes its runs from the axis's configuration
/// (`mechanics::timed_runs`): forward at `max_speed_deg_s`, backward at
/// `back_speed_deg_s`, the current watch from `max_current_ma` and
/// `overcurrent_ms`, scaled from the supply `supply.calibration_mv`; at
/// every end of those keys' ranges the runs are valid,
/// so no configuration that passed its checks stops a board at power-on.
#[test]
fn runs_from_every_valid_axis_configuration_are_valid() {
    use suntracker::config::ranges as r;
    use suntracker::mechanics::timed_runs;
    let base = axis_config();
    let (s_lo, s_hi) = r::MAX_SPEED_DEG_S;
    let (i_lo, i_hi) = r::MAX_CURRENT_MA;
    let (o_lo, o_hi) = r::OVERCURRENT_MS;
    let (v_lo, v_hi) = r::SUPPLY_MV;
    for (fwd, back) in [(s_lo, s_hi), (s_hi, s_lo), (s_lo, s_lo), (s_hi, s_hi)] {
        for (ma, ms, mv) in [(i_lo, o_lo, v_lo), (i_hi, o_hi, v_hi)] {
            let axis = AxisConfig {
                max_speed_deg_s: fwd,
                back_speed_deg_s: back,
                max_current_ma: ma,
                overcurrent_ms: ms,
                ..base
            };
            assert_eq!(axis.validate(0), Ok(()));
            let runs = timed_runs(&axis, mv, 10_000);
            assert_eq!(runs.validate(), Ok(()), "{axis:?}");
            assert_eq!((runs.forward_deg_s, runs.backward_deg_s), (fwd, back));
            assert_eq!(runs.calibration_supply_mv, u32::from(mv));
            assert_eq!(
                (runs.max_current_ma, runs.overcurrent_ms, runs.duty_permille),
                (u32::from(ma), u32::from(ms), 1_000)
            );
        }
    }
    // An axis refused by its checks is not given runs that pass either.
    let slow = AxisConfig {
        back_speed_deg_s: 0.0,
        ..base
    };
    assert!(slow.validate(0).is_err());
    assert!(timed_runs(&slow, 0, 120).validate().is_err());
}

#[test]
fn homing_stops_on_the_switch_then_moves_by_time() {
    let mut ax = AxisController::new(drive(calibrated(), -70.0), axis_config());
    let mut now = 0u32;
    for _ in 0..200 {
        ax.drive_mut().begin_tick(1.0);
        now += 1_000;
        if ax.home_step(0.45, now).unwrap() == HomeState::Done {
            break;
        }
    }
    assert_eq!(ax.home_state(), HomeState::Done);
    // Braked where the switch closed (−90°), plus the run-on after the
    // brake: speed × the braked time constant is 0.9°, well short of the
    // hard stop 1° beyond.
    let at = ax.drive().output_deg();
    assert!((-91.0..=-89.9).contains(&at), "{at}");
    ax.drive_mut().begin_tick(60.0);
    ax.update(0.0, FeedbackMode::OpenLoop, None).unwrap();
    let off = ax.drive().output_deg() - at;
    assert!((off - 90.0).abs() < 0.01, "{off}");
}

#[test]
fn pending_counts_down_and_stop_brakes() {
    let mut d = drive(calibrated(), 0.0);
    // A tick of 1 s for a 20° move (2.6 s): two fifths done.
    d.begin_tick(1.0);
    d.move_counts(20 * 1_400).unwrap();
    let left = d.pending();
    assert!((15_000..17_500).contains(&left), "{left}");
    d.stop().unwrap();
    assert_eq!(d.pending(), 0);
    d.begin_tick(5.0);
    let after = d.output_deg();
    d.begin_tick(5.0);
    // The last of the braked run-down, under a Hall count (1/1400°).
    assert!((d.output_deg() - after).abs() < 1e-4, "moved after a stop");
    assert!(after > 7.0 && after < 9.0, "{after}");
}

#[test]
fn absurd_configurations_are_refused() {
    let ok = calibrated();
    for (bad, want) in [
        (
            TimedAxisConfig {
                forward_deg_s: f32::NAN,
                ..ok
            },
            TimedAxisConfigError::Speed,
        ),
        (
            TimedAxisConfig {
                backward_deg_s: 0.0,
                ..ok
            },
            TimedAxisConfigError::Speed,
        ),
        (
            TimedAxisConfig {
                forward_deg_s: 1e9,
                ..ok
            },
            TimedAxisConfigError::Speed,
        ),
        (
            TimedAxisConfig {
                duty_permille: 0,
                ..ok
            },
            TimedAxisConfigError::Duty,
        ),
        (
            TimedAxisConfig {
                duty_permille: 1_001,
                ..ok
            },
            TimedAxisConfigError::Duty,
        ),
        (
            TimedAxisConfig {
                calibration_supply_mv: 100_001,
                ..ok
            },
            TimedAxisConfigError::Supply,
        ),
        (
            TimedAxisConfig {
                max_current_ma: 0,
                ..ok
            },
            TimedAxisConfigError::Current,
        ),
        (
            TimedAxisConfig {
                lag_ms: 10_001,
                ..ok
            },
            TimedAxisConfigError::Lag,
        ),
    ] {
        assert_eq!(bad.validate(), Err(want));
        let d = DcDrive::<SimTimedAxis>::new(
            DcDriveSpec {
                motor: spec(),
                bridge: drivers::dc_motor::Config {
                    ramp_permille_per_ms: 0,
                    rest: drivers::dc_motor::RestMode::Brake,
                },
                firmware: bad,
            },
            &axis_config(),
            -90.0,
            90.0,
            0.0,
        );
        assert_eq!(d.err(), Some(want));
    }
}
