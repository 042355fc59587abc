//! A linear actuator's keys (`axis.X.pivot_a_mm` … `pot_extended_counts`,
//! the core's `linear` feature): the rules between them and the drive
//! kind, their stored layout, and the mounting and loop `mechanics`
//! builds from them. The stroke's angles are worked here by the law of
//! cosines in `f64`, apart from the firmware's `f32` geometry; the loop's
//! figures are the simulator's LA12 loops (`sim::linear_drive`, which
//! explain them).

use sim::linear_actuator::ActuatorSpec;
use sim::linear_drive::{
    la12_tilt_axis_config, FeedbackKind, LA12_DUAL_HALL_LOOP, LA12_POT_LOOP, LA12_POT_READING,
    LA12_TILT_MOUNT,
};
use suntracker::config::{Config, DriveKind, Field, LinearMount, Reason, PAYLOAD_LEN};
use suntracker::mechanics::{linear_loop, linear_mount, LINEAR_POT_READING};

/// The simulator's LA12 tilt mount (`sim::linear_drive::LA12_TILT_MOUNT`):
/// pivots 237 mm and 110 mm from the hinge, γ = 172.9° at the axis's zero,
/// 245 mm retracted, 100 mm of stroke.
const A_MM: f64 = 237.0;
const B_MM: f64 = 110.0;
const OFFSET_DEG: f64 = 172.9;
const RETRACTED_MM: f64 = 245.0;
const STROKE_MM: f64 = 100.0;

/// The axis angle at pivot-to-pivot length `l_mm`: `L² = a² + b² −
/// 2ab·cos γ`, axis = γ − offset.
fn axis_deg(l_mm: f64) -> f64 {
    ((A_MM * A_MM + B_MM * B_MM - l_mm * l_mm) / (2.0 * A_MM * B_MM))
        .acos()
        .to_degrees()
        - OFFSET_DEG
}

/// The configuration with its A axis the LA12 of `kind` (3 Hall, 4
/// potentiometer) on the tilt mount, the soft limits the stroke's ends
/// (rounded inward to the hundredth), home where `home_deg` says.
fn linear_config(kind: DriveKind, home_deg: f64) -> Config {
    let mut c = Config::default();
    let a = &mut c.axes[1];
    a.linear = LinearMount {
        pivot_a_mm: A_MM as f32,
        pivot_b_mm: B_MM as f32,
        pivot_offset_deg: OFFSET_DEG as f32,
        retracted_mm: RETRACTED_MM as f32,
        stroke_mm: STROKE_MM as f32,
        pulses_per_mm: (1.0 / 0.1875) as f32,
        pot_retracted_counts: 102,
        pot_extended_counts: 920,
    };
    a.counts_per_motor_rev = 36_000;
    a.microsteps = 1;
    a.gear_ratio = 1.0;
    a.min_deg = ((axis_deg(RETRACTED_MM) * 100.0).ceil() / 100.0) as f32;
    a.max_deg = ((axis_deg(RETRACTED_MM + STROKE_MM) * 100.0).floor() / 100.0) as f32;
    a.home_deg = home_deg as f32;
    a.drive = kind as u8;
    c
}

fn error_of(c: &Config) -> Option<(String, Reason)> {
    c.validate()
        .err()
        .map(|e| (e.field.name().to_string(), e.reason))
}

#[test]
fn the_stroke_angles_worked_by_hand() {
    // acos((237² + 110² − 245²) / (2 · 237 · 110)) = acos(8,244 / 52,140)
    // = 80.9026°, less 172.9°; at 345 mm acos(−0.97346) = 166.7692°: the
    // stroke spans −91.997° to −6.131°.
    assert!((axis_deg(245.0) - -91.9974).abs() < 1e-3);
    assert!((axis_deg(345.0) - -6.1308).abs() < 1e-3);
}

#[test]
fn the_default_mount_is_the_simulators_la12_tilt_mount() {
    // As `LinearMount`'s docs say; the core cannot name the simulator's
    // constant, so this keeps the two the same.
    assert_eq!(LinearMount::DEFAULT.geometry(), LA12_TILT_MOUNT);
}

#[test]
fn a_linear_axis_within_its_stroke_is_taken() {
    let pot = linear_config(DriveKind::LinearPot, axis_deg(RETRACTED_MM));
    assert_eq!(pot.validate(), Ok(()));
    // On Hall pulses the home switch's edge is the first state shift
    // above the switch (0.1875 mm out).
    let hall = linear_config(DriveKind::LinearHall, axis_deg(RETRACTED_MM + 0.1875));
    assert_eq!(hall.validate(), Ok(()));
    // Stored and read back whole.
    let mut buf = [0u8; PAYLOAD_LEN];
    let n = hall.encode(&mut buf).unwrap();
    assert_eq!(Config::decode(&buf[..n]), Some(hall));
}

#[test]
fn limits_outside_the_stroke_are_refused_naming_the_limit() {
    // The default A axis turns −90…+90°: +90 is far beyond the extended
    // end (−6.13°).
    let mut c = Config::default();
    c.axes[1].drive = DriveKind::LinearPot as u8;
    assert_eq!(
        error_of(&c),
        Some(("axis.a.max_deg".into(), Reason::WithinStroke))
    );
    // The low limit 0.02° below the retracted end's angle.
    let mut c = linear_config(DriveKind::LinearHall, axis_deg(RETRACTED_MM + 0.1875));
    c.axes[1].min_deg = (axis_deg(RETRACTED_MM) - 0.02) as f32;
    c.axes[1].home_deg = c.axes[1].min_deg + 0.1;
    assert_eq!(
        error_of(&c),
        Some(("axis.a.min_deg".into(), Reason::WithinStroke))
    );
    // The home switch below the retracted end (where the rod never is),
    // though within the 5° below the low limit any axis's may be.
    let c = linear_config(DriveKind::LinearHall, axis_deg(RETRACTED_MM) - 0.05);
    assert_eq!(
        error_of(&c),
        Some(("axis.a.home_deg".into(), Reason::WithinStroke))
    );
}

#[test]
fn a_potentiometer_is_homed_at_its_retracted_end() {
    let c = linear_config(DriveKind::LinearPot, axis_deg(RETRACTED_MM + 0.1875));
    assert_eq!(
        error_of(&c),
        Some(("axis.a.home_deg".into(), Reason::HomeAtRetracted))
    );
    // The same home is a Hall axis's first edge above its switch.
    let mut hall = c;
    hall.axes[1].drive = DriveKind::LinearHall as u8;
    assert_eq!(hall.validate(), Ok(()));
}

#[test]
fn equal_potentiometer_readings_are_refused() {
    let mut c = linear_config(DriveKind::LinearPot, axis_deg(RETRACTED_MM));
    c.axes[1].linear.pot_extended_counts = 102;
    assert_eq!(
        error_of(&c),
        Some(("axis.a.pot_extended_counts".into(), Reason::PotSpan))
    );
    // A Hall axis reads no potentiometer.
    c.axes[1].drive = DriveKind::LinearHall as u8;
    c.axes[1].home_deg = axis_deg(RETRACTED_MM + 0.1875) as f32;
    assert_eq!(c.validate(), Ok(()));
}

#[test]
fn a_mounting_without_a_triangle_is_refused_for_a_linear_drive_only() {
    // 245 + 110 = 355 mm extended, beyond a + b = 347 mm.
    let mut c = linear_config(DriveKind::LinearHall, axis_deg(RETRACTED_MM + 0.1875));
    c.axes[1].linear.stroke_mm = 110.0;
    assert_eq!(
        error_of(&c),
        Some(("axis.a.stroke_mm".into(), Reason::LinearGeometry))
    );
    // A stepper's configuration keeps whatever mounting it holds.
    c.axes[1] = Config::default().axes[1];
    c.axes[1].linear.stroke_mm = 110.0;
    assert_eq!(c.validate(), Ok(()));
    // Each key has its range on any drive.
    c.axes[1].linear.pivot_b_mm = 9.0;
    assert_eq!(
        error_of(&c),
        Some(("axis.a.pivot_b_mm".into(), Reason::LengthMm))
    );
    assert_eq!(
        Field::AxisCPulsesPerMm.name().to_string(),
        "axis.c.pulses_per_mm"
    );
}

#[test]
fn the_loop_is_the_simulators_la12_loop_in_the_feedbacks_counts() {
    let axis = la12_tilt_axis_config(FeedbackKind::Hall).unwrap();
    // The dual Hall pair: 5.33 shifts a mm, counted in halves (10.67 a mm).
    let hall = linear_loop(&axis, 2.0 * axis.linear.pulses_per_mm);
    assert_eq!(hall, LA12_DUAL_HALL_LOOP);
    // The potentiometer in tenths of a mm.
    let pot = linear_loop(&axis, 10.0);
    assert_eq!(pot, LA12_POT_LOOP);
    assert_eq!(LINEAR_POT_READING, LA12_POT_READING);
    // A reed contact every 10 mm: the stall waits for four of its counts at
    // 10 mm/s (2 s), the bands are at least their floors.
    let reed = linear_loop(&axis, 0.2);
    assert_eq!(reed.stall_ms, 2_000);
    assert_eq!((reed.slow_band_counts, reed.max_idle_counts), (2, 2));
    assert_eq!(reed.min_speed_cps, 1);
}

#[test]
fn the_mount_places_the_hall_switch_edge_at_the_home_angle() {
    let axis = la12_tilt_axis_config(FeedbackKind::Hall).unwrap();
    let m = linear_mount(&axis).unwrap();
    // The simulator's axis is homed at the first state shift, 0.1875 mm
    // out (LINAK's dual Hall: 16 shifts a turn of a 3 mm spindle).
    let shift_mm = ActuatorSpec::LA12_DUAL_HALL_12V.mm_per_pulse as f32;
    assert!((m.switch_extension_mm - shift_mm).abs() < 1e-3, "{m:?}");
    assert_eq!(m.end_tolerance_mm, 0.0);
    assert_eq!(m.loop_config, LA12_DUAL_HALL_LOOP);

    let pot_axis = la12_tilt_axis_config(FeedbackKind::Pot).unwrap();
    let m = linear_mount(&pot_axis).unwrap();
    assert_eq!(m.switch_extension_mm, 0.0);
    // The hysteresis and two of the ADC's counts: 100 mm over 921 − 102
    // counts.
    let span =
        f32::from(pot_axis.linear.pot_extended_counts - pot_axis.linear.pot_retracted_counts);
    assert!((m.end_tolerance_mm - (0.1 + 2.0 * 100.0 / span)).abs() < 1e-6);
    assert_eq!(m.loop_config, LA12_POT_LOOP);
    // The simulator's axis configurations pass the configuration's rules.
    let mut c = Config::default();
    c.axes[1] = pot_axis;
    assert_eq!(c.validate(), Ok(()));
    c.axes[1] = axis;
    assert_eq!(c.validate(), Ok(()));
}
