//! Axis control over the simulated plants.

use suntracker::axis::{AxisController, AxisDrive, FeedbackMode, HomeState};
use suntracker::config::{AxisConfig, Config};
use suntracker::sim::plant::MotorPlant;

fn cfg() -> AxisConfig {
    // 1.8° stepper, 16 microsteps, 100:1 → 200·16·100/360 = 888.9 counts/°;
    // the plants below have no backlash unless a test says so.
    AxisConfig {
        backlash_deg: 0.0,
        ..Config::default().axes[1]
    }
}

fn home(ax: &mut AxisController<MotorPlant>) {
    for _ in 0..1_000_000 {
        ax.drive_mut().begin_tick(1.0);
        if ax.home_step(1.0).unwrap() == HomeState::Done {
            return;
        }
    }
    panic!("homing did not finish");
}

#[test]
fn counts_per_degree_from_configuration() {
    assert!((cfg().counts_per_deg() - 200.0 * 16.0 * 100.0 / 360.0).abs() < 1e-3);
}

#[test]
fn homing_finds_the_switch_and_soft_limits_clamp() {
    let c = cfg();
    // The switch sits at the home angle −90°; the axis starts at +30°.
    let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.0, 5.0, None, -90.0, 90.0, 30.0);
    let mut ax = AxisController::new(plant, c);
    assert!(ax.update(10.0, FeedbackMode::OpenLoop, None).is_err());
    home(&mut ax);
    // Within the fine approach step (1°/50) of the switch.
    assert!((ax.drive().output_deg() - -90.0).abs() <= 0.02 + 1e-9);
    ax.drive_mut().begin_tick(1000.0);
    let r = ax.update(45.0, FeedbackMode::OpenLoop, None).unwrap();
    assert!(!r.clamped);
    assert!((ax.drive().output_deg() - 45.0).abs() < 0.03);
    // Beyond the soft limit: clamped to +90°.
    ax.drive_mut().begin_tick(1000.0);
    let r = ax.update(120.0, FeedbackMode::OpenLoop, None).unwrap();
    assert!(r.clamped);
    assert_eq!(r.target_deg, 90.0);
    assert!((ax.drive().output_deg() - 90.0).abs() < 0.03);
    // NaN targets are errors, not motion.
    assert!(ax.update(f32::NAN, FeedbackMode::OpenLoop, None).is_err());
}

#[test]
fn stuck_switch_is_backed_off_or_reported() {
    let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.0, 5.0, None, -90.0, 90.0, 0.0);
    let mut ax = AxisController::new(plant, cfg());
    ax.drive_mut().switch_stuck = true;
    let mut err = false;
    for _ in 0..10_000 {
        ax.drive_mut().begin_tick(1.0);
        match ax.home_step(1.0) {
            Ok(HomeState::Done) => panic!("homed on a stuck switch"),
            Ok(_) => {}
            Err(_) => {
                err = true;
                break;
            }
        }
    }
    assert!(err);
}

#[test]
fn backlash_compensation_on_reversal() {
    let mut c = cfg();
    c.backlash_deg = 0.5;
    let run = |c: AxisConfig| {
        let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.5, 5.0, None, -90.0, 90.0, 0.0);
        let mut ax = AxisController::new(plant, c);
        home(&mut ax);
        let mut worst = 0.0f64;
        for target in [10.0, 20.0, 5.0, 15.0, -30.0, 40.0, 39.0] {
            ax.drive_mut().begin_tick(1000.0);
            ax.update(target, FeedbackMode::OpenLoop, None).unwrap();
            worst = worst.max((ax.drive().output_deg() - f64::from(target)).abs());
        }
        worst
    };
    let with = run(c);
    c.backlash_deg = 0.0;
    let without = run(c);
    // Uncompensated, a reversal leaves the whole 0.5° of slack.
    assert!(without > 0.45, "{without}");
    assert!(with < 0.03, "{with}");
}

#[test]
fn closed_loop_corrects_lost_steps_pseudo_closed_only_reports() {
    for mode in [FeedbackMode::ClosedLoop, FeedbackMode::PseudoClosed] {
        let plant = MotorPlant::stepper(1.8, 16, 100.0, 0.0, 5.0, Some(1 << 16), -90.0, 90.0, 0.0);
        let mut ax = AxisController::new(plant, cfg());
        home(&mut ax);
        ax.drive_mut().begin_tick(1000.0);
        ax.update(20.0, mode, None).unwrap();
        // The motor slips 2° (lost steps).
        ax.drive_mut().slip(-2.0);
        let fb = ax.drive_mut().encoder_deg().unwrap().unwrap();
        ax.drive_mut().begin_tick(1000.0);
        let r = ax.update(20.0, mode, Some(fb)).unwrap();
        let dev = r.deviation_deg.unwrap();
        assert!((dev + 2.0).abs() < 0.03, "{dev}");
        let out = ax.drive().output_deg();
        match mode {
            FeedbackMode::ClosedLoop => assert!((out - 20.0).abs() < 0.03, "{out}"),
            _ => assert!((out - 18.0).abs() < 0.03, "{out}"),
        }
        // Inside the deadband nothing moves.
        let before = ax.travel_counts;
        let fb = ax.drive_mut().encoder_deg().unwrap().unwrap();
        ax.drive_mut().begin_tick(1000.0);
        ax.update(fb + 0.01, FeedbackMode::ClosedLoop, Some(fb))
            .unwrap();
        assert_eq!(ax.travel_counts, before);
    }
}

#[test]
fn servo_lands_on_encoder_counts_and_speed_limits_a_tick() {
    let mut c = cfg();
    c.counts_per_motor_rev = 4096;
    c.microsteps = 1;
    c.gear_ratio = 1.0;
    c.backlash_deg = 0.0;
    let plant = MotorPlant::servo(4096, 3.0, -90.0, 90.0, 0.0);
    let mut ax = AxisController::new(plant, c);
    home(&mut ax);
    // 3°/s for 10 s: at most 30° this tick.
    ax.drive_mut().begin_tick(10.0);
    ax.update(0.0, FeedbackMode::OpenLoop, None).unwrap();
    let moved = ax.drive().output_deg() - -90.0;
    assert!((moved - 30.0).abs() < 0.2, "{moved}");
    ax.drive_mut().begin_tick(100.0);
    let out = ax.drive().output_deg();
    // 360/4096 = 0.088° resolution.
    assert!(out.abs() < 0.09, "{out}");
}
