//! The linear-actuator axis (`hw::LinearAxis`) on the simulated LINAK LA12
//! (`sim::linear_actuator`, `ActuatorSpec::LA12_L1_12V`: 100 mm stroke,
//! 26 mm/s free and 14 mm/s at rated load, 1 mm per Hall pulse, 0.5–4.5 V
//! potentiometer, built-in end switches), polled every millisecond.
//!
//! Geometry (as `drivers/tests/linear_actuator.rs`, whose hand-worked
//! values are repeated here): a = 300 mm, b = 150 mm, offset 75°, 245 mm
//! retracted (assumed: the manual's dimension drawing was not available),
//! 100 mm stroke. By the law of cosines the stroke spans −20.666° (L = 245)
//! to +19.158° (L = 345); axis +15° is γ = 90°, L = √(300² + 150²) =
//! 335.4102 mm, 90.41 mm extended.
//!
//! The ports are `sim::linear_drive`'s: the Hall counter counts each pulse
//! edge up or down by the bridge's last commanded direction, as a board's
//! interrupt does; the potentiometer is read by a 10-bit ADC at 5 V
//! (0.5 V → 102 counts, 4.5 V → 921) with one count rms of noise.

/// A fixed seed of the ADC noise.
const SEED: u64 = 7;

fn plant(extension_mm: f64) -> Shared {
    ActuatorHardware::shared(
        LinearActuator::new(ActuatorSpec::LA12_L1_12V, extension_mm),
        1.0,
        SEED,
    )
}

use std::cell::Cell;
use std::rc::Rc;

use drivers::dc_motor::{Config as MotorConfig, DcMotor, Output, RestMode};
use drivers::linear::{ActuatorGeometry, LinearError, PotCalibration, PulseScale};
use embedded_hal::digital::InputPin;
use sim::linear_actuator::{ActuatorSpec, LinearActuator};
use sim::linear_drive::{
    adc_counts, ActuatorBridge, ActuatorHardware, AdcFailed, PotAdc, PulseCounter, RetractedSwitch,
    SharedActuator as Shared, LA12_HALL_LOOP, LA12_POT_LOOP, LA12_POT_READING,
};
use suntracker::config::AxisConfig;
use suntracker::hw::{
    DcAxisConfig, HallFeedback, LinearAxis, LinearAxisConfig, LinearAxisConfigError,
    LinearAxisError, NoCurrentSense, NoEndSwitch, PotConfig, PotError, PotFeedback,
};
use suntracker::motion::{AxisDrive, DriveFault};

const GEOMETRY: ActuatorGeometry = ActuatorGeometry::LA12_EXAMPLE;

/// Hand-worked: L = 245 → cos γ = 52 475 / 90 000, γ = 54.334°, −20.666°.
const RETRACTED_DEG: f32 = -20.666;

/// Hand-worked: L = 246 → cos γ = (112 500 − 60 516) / 90 000 = 0.5776,
/// γ = 54.718°, −20.282°: the Hall axis's home, the first pulse edge
/// (1 mm) above the switch at the retracted end.
const FIRST_EDGE_DEG: f32 = -20.282;

/// The controller's scale: 100 counts a degree; home at the retracted end.
fn axis_config() -> AxisConfig {
    AxisConfig {
        counts_per_motor_rev: 36_000,
        microsteps: 1,
        gear_ratio: 1.0,
        min_deg: RETRACTED_DEG,
        max_deg: 19.0,
        home_deg: RETRACTED_DEG,
        backlash_deg: 0.0,
        max_speed_deg_s: 10.0,
        deadband_deg: 0.05,
        continuous: 0,
        drive: suntracker::config::DriveKind::LinearPot as u8,
        ..suntracker::config::Config::DEFAULT.axes[0]
    }
}

fn motor(plant: &Shared) -> DcMotor<ActuatorBridge> {
    DcMotor::new(
        ActuatorBridge(Rc::clone(plant)),
        MotorConfig {
            ramp_permille_per_ms: 5,
            rest: RestMode::Brake,
        },
    )
    .unwrap()
}

/// The loops and the reading of the LA12 in `sim::linear_drive` (their
/// documentation gives each value's reason; `simulate`'s Hall axis runs
/// the dual-Hall loop, the same in its finer counts): on the single Hall's
/// pulses done on the target's edge,
/// stall after 1 s without a pulse; on the potentiometer done within
/// 0.1 mm, sixteen conversions a poll and a hysteresis of 0.1 mm.
const HALL_LOOP: DcAxisConfig = LA12_HALL_LOOP;
const POT_LOOP: DcAxisConfig = LA12_POT_LOOP;
const POT: PotConfig = LA12_POT_READING;

type HallAxis =
    LinearAxis<ActuatorBridge, HallFeedback<PulseCounter>, RetractedSwitch, NoCurrentSense>;
type PotAxis = LinearAxis<ActuatorBridge, PotFeedback<PotAdc>, NoEndSwitch, NoCurrentSense>;

fn hall_axis_config() -> AxisConfig {
    AxisConfig {
        home_deg: FIRST_EDGE_DEG,
        drive: suntracker::config::DriveKind::LinearHall as u8,
        ..axis_config()
    }
}

fn hall_axis(plant: &Shared) -> HallAxis {
    let feedback = HallFeedback::new(
        PulseCounter(Rc::clone(plant)),
        PulseScale::new(1.0).unwrap(),
    );
    LinearAxis::new(
        motor(plant),
        feedback,
        RetractedSwitch(Rc::clone(plant)),
        false,
        None,
        LinearAxisConfig {
            geometry: GEOMETRY,
            switch_extension_mm: 1.0,
            end_tolerance_mm: 0.0,
            loop_config: HALL_LOOP,
        },
        &hall_axis_config(),
    )
    .unwrap()
}

/// 0.5 V and 4.5 V on a 10-bit ADC at 5 V: 102.3 → 102, 920.7 → 921.
fn pot_calibration() -> PotCalibration {
    assert_eq!((adc_counts(0.5), adc_counts(4.5)), (102, 921));
    PotCalibration::new(102, 921, 100.0).unwrap()
}

fn pot_axis(plant: &Shared) -> PotAxis {
    let pot = PotFeedback::new(PotAdc(Rc::clone(plant)), pot_calibration(), 100.0, POT).unwrap();
    LinearAxis::new(
        motor(plant),
        pot,
        NoEndSwitch,
        false,
        None,
        LinearAxisConfig {
            geometry: GEOMETRY,
            switch_extension_mm: 0.0,
            // An ADC count is 0.12 mm, the hysteresis 0.1 mm.
            end_tolerance_mm: 0.3,
            loop_config: POT_LOOP,
        },
        &axis_config(),
    )
    .unwrap()
}

/// Polls every ms until the axis has nothing pending and rests (at most
/// `max_ms`); returns the time.
fn run<F: suntracker::hw::LinearFeedback, H: InputPin>(
    plant: &Shared,
    axis: &mut LinearAxis<ActuatorBridge, F, H, NoCurrentSense>,
    now: &Cell<u32>,
    max_ms: u32,
) where
    F::Error: core::fmt::Debug,
{
    for _ in 0..max_ms {
        let t = now.get();
        axis.poll(t).unwrap();
        plant.borrow_mut().step(1.0e-3);
        now.set(t + 1);
        let braked = matches!(axis.inner().output(), Output::Brake | Output::Coast);
        let idle = matches!(axis.inner().state(), suntracker::hw::DcState::Idle { .. });
        if axis.pending() == 0 && braked && idle {
            return;
        }
    }
}

/// Homes as the controller does: moves down until the switch closes.
fn home<F: suntracker::hw::LinearFeedback, H: InputPin>(
    plant: &Shared,
    axis: &mut LinearAxis<ActuatorBridge, F, H, NoCurrentSense>,
    now: &Cell<u32>,
) where
    F::Error: core::fmt::Debug,
{
    axis.move_counts(-10_000).unwrap();
    for _ in 0..20_000 {
        if axis.at_limit().unwrap() {
            break;
        }
        let t = now.get();
        axis.poll(t).unwrap();
        plant.borrow_mut().step(1.0e-3);
        now.set(t + 1);
    }
    assert!(axis.at_limit().unwrap());
    axis.stop().unwrap();
    run(plant, axis, now, 2_000);
}

#[test]
fn hall_axis_homes_then_reaches_15_degrees_at_90_pulses() {
    let plant = plant(20.0);
    let mut axis = hall_axis(&plant);
    let now = Cell::new(0);
    // Not referenced: no angle yet.
    assert_eq!(axis.encoder_deg().unwrap(), None);
    home(&plant, &mut axis, &now);
    // Referenced at the first edge above the switch.
    let at_home = axis.encoder_deg().unwrap().unwrap();
    assert!((at_home - FIRST_EDGE_DEG).abs() < 0.001, "{at_home}");
    assert_eq!(plant.borrow().actuator.extension_mm(), 0.0);
    // To +15°: 35.666° · 100 counts.
    let counts = ((15.0 - at_home) * 100.0).round() as i32;
    axis.move_counts(counts).unwrap();
    assert!(axis.pending() > 0);
    run(&plant, &mut axis, &now, 20_000);
    assert_eq!(axis.pending(), 0);
    // 90.41 mm: the rod stops on the 90 mm edge (braked within a poll at
    // the slow band's 40 % duty, about 10 mm/s: 0.01 mm).
    let ext = plant.borrow().actuator.extension_mm();
    assert!((90.0..90.05).contains(&ext), "{ext} mm");
    // L = 335: cos γ = (112 500 − 112 225) / 90 000 = 0.003 056,
    // γ = 89.825°, axis 14.825°.
    let deg = axis.encoder_deg().unwrap().unwrap();
    assert!((deg - 14.825).abs() < 0.001, "{deg}");
    // Back to 0°: γ = 75°, L² = 112 500 − 90 000 · cos 75° = 89 206.3,
    // L = 298.674 mm, 53.67 mm extended. Retracting, the rod stops just
    // below the 54 mm edge (the last edge crossed): L = 299,
    // cos γ = (112 500 − 89 401) / 90 000 = 0.256 66, γ = 75.128°.
    axis.move_counts((-deg * 100.0).round() as i32).unwrap();
    run(&plant, &mut axis, &now, 20_000);
    let ext = plant.borrow().actuator.extension_mm();
    assert!((53.95..54.0).contains(&ext), "{ext} mm");
    let deg = axis.encoder_deg().unwrap().unwrap();
    assert!((deg - 0.128).abs() < 0.001, "{deg}");
    assert_eq!(axis.take_fault(), None);
}

#[test]
fn a_correction_at_rest_on_an_edge_is_taken_from_that_edge() {
    let plant = plant(20.0);
    let mut axis = hall_axis(&plant);
    let now = Cell::new(0);
    home(&plant, &mut axis, &now);
    let at_home = axis.encoder_deg().unwrap().unwrap();
    axis.move_counts(((15.0 - at_home) * 100.0).round() as i32)
        .unwrap();
    run(&plant, &mut axis, &now, 20_000);
    // On the 90 mm edge, 14.825° (hand-worked above): 0.175° short of 15°,
    // more than the controller's 0.05° deadband, so it corrects by +18
    // counts at its next tick, as `AxisController::update` does.
    let deg = axis.encoder_deg().unwrap().unwrap();
    assert!((deg - 14.825).abs() < 0.001, "{deg}");
    axis.rebase_at_rest();
    axis.move_counts(18).unwrap();
    run(&plant, &mut axis, &now, 20_000);
    // From the edge: 15.005°, L = 335.42 mm, 90.42 mm, still nearest the
    // 90 mm edge: the rod stays. (Added to the 15° target it was 15.18°,
    // 90.83 mm: the 91 mm edge, and the next correction back.)
    let ext = plant.borrow().actuator.extension_mm();
    assert!((90.0..90.05).contains(&ext), "{ext} mm");
}

#[test]
fn pot_axis_reaches_15_degrees_within_an_adc_count() {
    let plant = plant(20.0);
    let mut axis = pot_axis(&plant);
    let now = Cell::new(0);
    // Absolute: an angle from the start. 20 mm: L = 265,
    // cos γ = (112 500 − 70 225) / 90 000 = 0.469 72, γ = 61.985°, −13.015°.
    let start = axis.encoder_deg().unwrap().unwrap();
    assert!((start - -13.015).abs() < 0.05, "{start}");
    home(&plant, &mut axis, &now);
    // Home within the 0.3 mm end tolerance of the retracted end (about
    // 0.6°/mm there: dγ/dL = L / (ab · sin γ) = 245 / (45 000 · 0.8125)).
    let at_home = axis.encoder_deg().unwrap().unwrap();
    let truth = plant.borrow().actuator.axis_deg(&GEOMETRY).unwrap();
    assert!((at_home - RETRACTED_DEG).abs() < 0.2, "{at_home}");
    assert!((at_home - truth).abs() < 0.1, "{at_home} vs {truth}");
    let counts = ((15.0 - at_home) * 100.0).round() as i32;
    axis.move_counts(counts).unwrap();
    run(&plant, &mut axis, &now, 20_000);
    // 90.41 mm; the ADC resolves 100 / 819 = 0.12 mm, the loop's deadband
    // is 0.1 mm and the hysteresis 0.1 mm.
    let ext = plant.borrow().actuator.extension_mm();
    assert!((ext - 90.41).abs() < 0.4, "{ext} mm");
    let truth = plant.borrow().actuator.axis_deg(&GEOMETRY).unwrap();
    let deg = axis.encoder_deg().unwrap().unwrap();
    // dγ/dL ≈ 0.43°/mm near 90° (L / (ab · sin γ) = 335 / 45 000 rad/mm).
    assert!((truth - 15.0).abs() < 0.2, "{truth}");
    assert!((deg - truth).abs() < 0.1, "{deg} vs {truth}");
    // At rest with the noise: no unexpected motion.
    run(&plant, &mut axis, &now, 5_000);
    assert_eq!(axis.take_fault(), None);
}

#[test]
fn a_target_beyond_the_stroke_stops_at_the_extended_end_and_back_from_it() {
    let plant = plant(95.0);
    let mut axis = pot_axis(&plant);
    let now = Cell::new(0);
    // +30° is past +19.158° (L = 345): clamped to the end.
    let from = axis.encoder_deg().unwrap().unwrap();
    axis.move_counts(((30.0 - from) * 100.0) as i32).unwrap();
    run(&plant, &mut axis, &now, 10_000);
    let ext = plant.borrow().actuator.extension_mm();
    assert!(ext > 99.6, "{ext}");
    assert_eq!(axis.pending(), 0);
    assert!(matches!(
        axis.inner().output(),
        Output::Brake | Output::Coast
    ));
    // Then 5° back: the rod leaves the end at once for 14.158°; the target
    // did not stay 10.8° out of reach.
    axis.move_counts(-500).unwrap();
    run(&plant, &mut axis, &now, 10_000);
    let truth = plant.borrow().actuator.axis_deg(&GEOMETRY).unwrap();
    // Within the 0.1 mm deadband at 0.43°/mm and the 0.3 mm end tolerance.
    assert!((truth - 14.158).abs() < 0.2, "{truth}");
    assert_eq!(axis.take_fault(), None);
}

#[test]
fn a_switch_closed_far_from_home_does_not_hold_the_next_homing_short() {
    let plant = plant(20.0);
    let mut axis = hall_axis(&plant);
    let now = Cell::new(0);
    home(&plant, &mut axis, &now);
    axis.move_counts(2_000).unwrap();
    run(&plant, &mut axis, &now, 20_000);
    let out = plant.borrow().actuator.extension_mm();
    assert!(out > 30.0, "{out} mm");
    // The controller reads the switch every tick: open out there. Then it
    // sticks closed for a reading: that closing edge moves the reference
    // (as any closing edge does), 53 mm up.
    assert!(!axis.at_limit().unwrap());
    plant.borrow_mut().switch_stuck = Some(true);
    assert!(axis.at_limit().unwrap());
    plant.borrow_mut().switch_stuck = None;
    assert!(!axis.at_limit().unwrap());
    assert_eq!(axis.extension_mm(), Some(1.0));
    // The next homing run goes on past where that reference put the
    // retracted end, to the real switch, and is referenced there again.
    home(&plant, &mut axis, &now);
    assert_eq!(plant.borrow().actuator.extension_mm(), 0.0);
    let at_home = axis.encoder_deg().unwrap().unwrap();
    assert!((at_home - FIRST_EDGE_DEG).abs() < 0.001, "{at_home}");
}

#[test]
fn a_dual_hall_pair_counts_a_rod_pushed_back_as_going_back() {
    // While driven out the rod is pushed back from 50 mm to 45 mm. A
    // single output counts the 5 pulses up (by the commanded direction);
    // a quadrature pair (0.1875 mm a shift) counts ⌊45 / 0.1875⌋ −
    // ⌊50 / 0.1875⌋ = 240 − 266 = −26.
    for (spec, counted) in [
        (ActuatorSpec::LA12_L1_12V, 5),
        (ActuatorSpec::LA12_DUAL_HALL_12V, -26),
    ] {
        use drivers::dc_motor::Bridge;
        use suntracker::hw::EncoderCount;
        let hw = ActuatorHardware::shared(LinearActuator::new(spec, 50.0), 0.0, SEED);
        ActuatorBridge(Rc::clone(&hw))
            .apply(&mut (), Output::Forward(1_000))
            .unwrap();
        hw.borrow_mut().slip_to(45.0);
        assert_eq!(PulseCounter(Rc::clone(&hw)).count(), counted);
    }
}

#[test]
fn a_pot_reading_at_a_rail_is_a_fault_not_a_panic() {
    let plant = plant(50.0);
    let mut axis = pot_axis(&plant);
    let now = Cell::new(0);
    // A broken wiper reads 1023: 102 counts beyond 921 + 8.
    plant.borrow_mut().adc_stuck = Some(1_023);
    assert_eq!(
        axis.poll(now.get()),
        Err(LinearAxisError::Feedback(PotError::Reading(
            LinearError::OutsideStroke
        )))
    );
    assert!(axis.fault_latched());
    assert_eq!(axis.take_fault(), Some(DriveFault::Stall));
    assert_eq!(axis.take_fault(), None);
    assert_eq!(axis.move_counts(100), Err(LinearAxisError::FeedbackLost));
    // Repaired and cleared: moves again.
    plant.borrow_mut().adc_stuck = None;
    AxisDrive::clear_fault(&mut axis);
    assert!(!axis.fault_latched());
    axis.move_counts(100).unwrap();
    run(&plant, &mut axis, &now, 5_000);
    assert_eq!(axis.take_fault(), None);
}

#[test]
fn the_loop_takes_a_failed_reading_as_a_motor_fault_not_a_drive_error() {
    // Through the firmware loop's `Motion`: the pass goes on (true), and
    // the controller learns of the fault through `take_fault`.
    let plant = plant(50.0);
    let mut axis = pot_axis(&plant);
    plant.borrow_mut().adc_fails = true;
    assert!(suntracker::firmware::Motion::service(&mut axis, 1_000));
    assert_eq!(axis.take_fault(), Some(DriveFault::Stall));
    // Refused moves stay refused until cleared, and the loop still runs.
    assert!(suntracker::firmware::Motion::service(&mut axis, 1_001));
    assert_eq!(axis.move_counts(10), Err(LinearAxisError::FeedbackLost));
}

#[test]
fn an_adc_error_is_a_fault() {
    let plant = plant(50.0);
    let mut axis = pot_axis(&plant);
    plant.borrow_mut().adc_fails = true;
    assert_eq!(
        axis.poll(0),
        Err(LinearAxisError::Feedback(PotError::Adc(AdcFailed)))
    );
    assert!(axis.fault_latched());
}

#[test]
fn readings_just_outside_the_span_are_the_end() {
    let plant = plant(0.0);
    // 0.5 V reads 102 ± 1; 96 is within the 8-count margin: fully retracted.
    plant.borrow_mut().adc_stuck = Some(96);
    let mut axis = pot_axis(&plant);
    axis.poll(0).unwrap();
    assert!(axis.at_limit().unwrap());
    let deg = axis.encoder_deg().unwrap().unwrap();
    assert!((deg - RETRACTED_DEG).abs() < 0.001, "{deg}");
}

#[test]
fn bad_configurations_are_refused() {
    let plant = plant(0.0);
    let hall = || {
        HallFeedback::new(
            PulseCounter(Rc::clone(&plant)),
            PulseScale::new(1.0).unwrap(),
        )
    };
    let make = |geometry: ActuatorGeometry, axis: AxisConfig| {
        LinearAxis::<_, _, _, NoCurrentSense>::new(
            motor(&plant),
            hall(),
            RetractedSwitch(Rc::clone(&plant)),
            false,
            None,
            LinearAxisConfig {
                geometry,
                switch_extension_mm: 1.0,
                end_tolerance_mm: 0.0,
                loop_config: HALL_LOOP,
            },
            &axis,
        )
        .map(|_| ())
    };
    let nan = ActuatorGeometry {
        b_mm: f32::NAN,
        ..GEOMETRY
    };
    assert_eq!(
        make(nan, hall_axis_config()),
        Err(LinearAxisConfigError::Geometry(LinearError::InvalidConfig))
    );
    // Home at 0° is not the angle of the retracted end.
    let wrong_home = AxisConfig {
        home_deg: 0.0,
        ..axis_config()
    };
    assert_eq!(make(GEOMETRY, wrong_home), Err(LinearAxisConfigError::Home));
    assert_eq!(make(GEOMETRY, hall_axis_config()), Ok(()));
    // A potentiometer calibration that does not cover the stroke.
    let short = PotCalibration::new(102, 921, 50.0).unwrap();
    assert!(matches!(
        PotFeedback::new(PotAdc(Rc::clone(&plant)), short, 100.0, POT),
        Err(PotError::Reading(LinearError::OutsideStroke))
    ));
}

/// The axis follows a day of tilt set-points, one a minute, as the
/// controller sends them: 12 hours from near the retracted end to near
/// the extended end and back, a half sine (the tilt of a tracker's day in
/// shape, over this actuator's 39.8° sweep). Each minute the move is
/// polled to rest; the error is the rod's true angle against the
/// set-point. Returns the p95 and the largest error, degrees.
fn follow_day<F: suntracker::hw::LinearFeedback, H: InputPin>(
    plant: &Shared,
    axis: &mut LinearAxis<ActuatorBridge, F, H, NoCurrentSense>,
) -> (f32, f32)
where
    F::Error: core::fmt::Debug,
{
    let now = Cell::new(0);
    home(plant, axis, &now);
    let mut commanded_deg = axis.encoder_deg().unwrap().unwrap();
    // From 2° above the retracted end (3.5 mm: past the first pulse edge,
    // where the Hall axis is referenced with the rod below it at the
    // switch) to 1° short of the extended end.
    let (lo, hi) = (RETRACTED_DEG + 2.0, 18.158);
    let mut errors = Vec::new();
    for minute in 0..=720 {
        let s = (core::f32::consts::PI * minute as f32 / 720.0).sin();
        let target = lo + (hi - lo) * s;
        let counts = ((target - commanded_deg) * 100.0).round() as i32;
        if counts != 0 {
            axis.move_counts(counts).unwrap();
            commanded_deg += counts as f32 / 100.0;
        }
        run(plant, axis, &now, 60_000);
        let truth = plant.borrow().actuator.axis_deg(&GEOMETRY).unwrap();
        errors.push((truth - target).abs());
    }
    assert_eq!(axis.take_fault(), None);
    errors.sort_by(f32::total_cmp);
    let p95 = errors[errors.len() * 95 / 100];
    (p95, errors[errors.len() - 1])
}

#[test]
fn a_day_of_set_points_on_hall_pulses() {
    let plant = plant(20.0);
    let mut axis = hall_axis(&plant);
    let (p95, max) = follow_day(&plant, &mut axis);
    println!("linear axis, Hall 1 mm/pulse: p95 {p95:.3} deg, max {max:.3} deg");
    // The rod stops on a pulse edge: at most half a pulse (0.5 mm) from
    // the set-point's length, plus the hundredth-degree count. Over this
    // stroke dγ/dL ≤ 0.54°/mm (drivers/tests/linear_actuator.rs): 0.27°.
    assert!(max < 0.28, "{max}");
}

#[test]
fn a_day_of_set_points_on_the_potentiometer() {
    let plant = plant(20.0);
    let mut axis = pot_axis(&plant);
    let (p95, max) = follow_day(&plant, &mut axis);
    println!("linear axis, potentiometer 10-bit: p95 {p95:.3} deg, max {max:.3} deg");
    // Deadband 0.1 mm, hysteresis 0.1 mm, an ADC count 0.12 mm: within
    // about 0.4 mm, 0.22° at 0.54°/mm.
    assert!(max < 0.22, "{max}");
}
