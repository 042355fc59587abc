//! A C axis that turns without end (`axis.c.continuous`: a slip ring or an
//! unlimited slewing drive) over the simulator's plant with no end stops,
//! its home switch an index cam passed once a turn.
//!
//! The expected angles are the plant's true output angle taken modulo 360°
//! (the physical pose repeats every turn) against the targets commanded;
//! the counts per turn are 200 full steps × 16 microsteps × a 100:1 gear =
//! 320,000, an integer, so rebasing by whole turns loses nothing.

use sim::plant::MotorPlant;
use suntracker::config::{AxisConfig, Config, Field, Reason};
use suntracker::motion::{AxisController, AxisDrive, AxisError, FeedbackMode, HomeState};

/// 1.8° stepper, 16 microsteps, 100:1; home switch (index) at −180°.
fn cfg() -> AxisConfig {
    AxisConfig {
        backlash_deg: 0.0,
        continuous: 1,
        ..Config::default().axes[0]
    }
}

fn plant(start_deg: f64, encoder: Option<u32>) -> MotorPlant {
    let mut p = MotorPlant::stepper(1.8, 16, 100.0, 0.0, 5.0, encoder, -180.0, 180.0, start_deg);
    p.make_continuous();
    p
}

fn home(ax: &mut AxisController<MotorPlant>) {
    for _ in 0..1_000_000 {
        ax.drive_mut().begin_tick(1.0);
        match ax.home_step(1.0, 0) {
            Ok(HomeState::Done) => return,
            Ok(_) => {}
            Err(e) => panic!("homing failed: {e:?}"),
        }
    }
    panic!("homing did not finish");
}

/// `a − b` reduced to −180…180°.
fn wrapped(a: f64, b: f64) -> f64 {
    (a - b + 540.0).rem_euclid(360.0) - 180.0
}

#[test]
fn turns_fifty_times_one_way_with_the_count_within_a_turn() {
    let c = cfg();
    let mut ax = AxisController::new(plant(10.0, None), c);
    assert!(ax.is_continuous());
    home(&mut ax);
    assert!((ax.drive().output_deg() - -180.0).abs() <= 0.02 + 1e-9);
    let turn_counts = 320_000;
    // 7° a step, 2,572 steps: just over 50 turns (18,004°).
    // The angles are counted from where homing left the plant (within
    // the fine approach of the index).
    let start_deg = ax.drive().output_deg();
    for step in 1..=2_572 {
        let commanded_deg = start_deg + 7.0 * f64::from(step);
        // The target in the count's frame, as the controller's pose is.
        let counted = f64::from(ax.counted_deg());
        let target = (counted + wrapped(commanded_deg, counted)) as f32;
        ax.drive_mut().begin_tick(10.0);
        let r = ax.update(target, FeedbackMode::OpenLoop, None).unwrap();
        // Never clamped: no soft limit holds it.
        assert!(!r.clamped, "step {step}");
        let turns = ax.rebase();
        assert!((0..=1).contains(&turns), "step {step}: {turns}");
        // The count stays within the turn above the switch.
        let p = ax.position_counts();
        assert!((0..turn_counts).contains(&p), "step {step}: {p}");
        // The plant is where the targets say, modulo whole turns, to a
        // count (1/889°), and its count never drifts.
        let err = wrapped(ax.drive().output_deg(), commanded_deg);
        assert!(err.abs() < 2e-3, "step {step}: {err}");
    }
    // Fifty turns and more in the same direction, through the index each
    // time without stopping at it.
    assert!(ax.drive().output_deg() > -180.0 + 50.0 * 360.0);
    assert!(ax.drive().travel_deg > 50.0 * 360.0);
}

#[test]
fn index_stops_only_while_homing() {
    let c = cfg();
    let mut ax = AxisController::new(plant(-150.0, None), c);
    home(&mut ax);
    // Down through the index (at −180°) to −200° (that is 160°), then on.
    for target in [-170.0, -190.0, -200.0, -260.0] {
        ax.drive_mut().begin_tick(100.0);
        ax.update(target, FeedbackMode::OpenLoop, None).unwrap();
        assert!(
            wrapped(ax.drive().output_deg(), f64::from(target)).abs() < 2e-3,
            "{target}: at {}",
            ax.drive().output_deg()
        );
        ax.rebase();
    }
    // Homing again: the index stops the seek, and the count is 0 there.
    ax.unhome();
    home(&mut ax);
    assert_eq!(ax.position_counts(), 0);
    assert!(wrapped(ax.drive().output_deg(), -180.0).abs() <= 0.02 + 1e-9);
}

#[test]
fn homes_from_just_below_the_index() {
    // Resting within the index cam's 5° below the switch (the switch reads
    // closed), the count a turn above it after a rebase: the back-off is
    // not held to max_deg, and homing ends on the index.
    let c = cfg();
    let mut ax = AxisController::new(plant(-100.0, None), c);
    home(&mut ax);
    ax.drive_mut().begin_tick(100.0);
    ax.update(-183.0, FeedbackMode::OpenLoop, None).unwrap();
    assert_eq!(ax.rebase(), -1);
    assert!((ax.counted_deg() - 177.0).abs() < 2e-3);
    // Within the cam: at the switch, not above it.
    assert!((ax.above_home_deg() - -3.0).abs() < 2e-3);
    ax.unhome();
    home(&mut ax);
    assert!(wrapped(ax.drive().output_deg(), -180.0).abs() <= 0.02 + 1e-9);
}

#[test]
fn an_absolute_encoder_is_read_in_the_count_turn() {
    let c = cfg();
    // A 16-bit single-turn encoder on the output.
    let mut ax = AxisController::new(plant(0.0, Some(1 << 16)), c);
    home(&mut ax);
    ax.drive_mut().begin_tick(100.0);
    ax.update(170.0, FeedbackMode::OpenLoop, None).unwrap();
    // The encoder says 170° (0…360°); the count 170° too (−180…180°
    // above the switch): as read, and in the count's turn.
    assert!((ax.near_count(170.0) - 170.0).abs() < 1e-4);
    assert!((ax.near_count(170.0 + 360.0) - 170.0).abs() < 1e-3);
    assert!((ax.near_count(170.0 - 720.0) - 170.0).abs() < 1e-3);
    // On through the index, to 190°: the count is taken a turn back...
    ax.drive_mut().begin_tick(100.0);
    ax.update(190.0, FeedbackMode::OpenLoop, None).unwrap();
    assert_eq!(ax.rebase(), 1);
    // ... to −170°, and the encoder, which reads 190° (0…360°), is read
    // there.
    assert!((ax.counted_deg() - -170.0).abs() < 2e-3);
    let read = ax.drive_mut().encoder_deg().unwrap().unwrap();
    assert!((read - 190.0).abs() < 0.03, "{read}");
    assert!((ax.near_count(read) - -170.0).abs() < 0.03);
    // A closed loop on that reading corrects nothing (it is in the deadband).
    ax.drive_mut().begin_tick(100.0);
    let fb = ax.near_count(read);
    let r = ax
        .update(fb + 0.01, FeedbackMode::ClosedLoop, Some(fb))
        .unwrap();
    assert_eq!(r.commanded_counts, 0);
    // Not finite stays not finite (the update refuses it).
    assert!(ax.near_count(f32::NAN).is_nan());
    assert!(matches!(
        ax.update(0.0, FeedbackMode::ClosedLoop, Some(f32::INFINITY)),
        Err(AxisError::NotFinite)
    ));
}

#[test]
fn a_limited_axis_is_unchanged() {
    // `continuous` off: the limits clamp, nothing is rebased, feedback is
    // taken as read.
    let c = AxisConfig {
        continuous: 0,
        ..cfg()
    };
    let p = MotorPlant::stepper(1.8, 16, 100.0, 0.0, 5.0, None, -180.0, 180.0, 0.0);
    let mut ax = AxisController::new(p, c);
    assert!(!ax.is_continuous());
    home(&mut ax);
    ax.drive_mut().begin_tick(1000.0);
    let r = ax.update(200.0, FeedbackMode::OpenLoop, None).unwrap();
    assert!(r.clamped);
    assert_eq!(ax.rebase(), 0);
    assert_eq!(ax.near_count(530.0), 530.0);
    assert!((ax.above_home_deg() - 360.0).abs() < 2e-3);
}

#[test]
fn continuous_needs_a_whole_number_of_counts_per_turn() {
    let mut config = Config::default();
    config.axes[0].continuous = 1;
    assert!(config.validate().is_ok());
    // 62.5:1 (a worm and a 2.5:1 belt): 200 × 16 × 62.5 = 200,000 counts a
    // turn, a whole number, but the rule asks for a whole gear ratio: the
    // fraction of a count per turn of most such ratios would drift.
    config.axes[0].gear_ratio = 62.5;
    let e = config.validate().unwrap_err();
    assert_eq!(e.field, Field::AxisCContinuous);
    assert_eq!(e.reason, Reason::WholeCountsPerTurn);
    config.axes[0].continuous = 0;
    assert!(config.validate().is_ok());
    // Out of its 0…1 range.
    config.axes[0].continuous = 2;
    assert_eq!(config.validate().unwrap_err().field, Field::AxisCContinuous);
}
