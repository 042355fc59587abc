//! Linear-actuator geometry: round trips over the whole stroke, and a
//! worked example from a real actuator's data sheet.
//!
//! Data sheet: LINAK, *Actuator LA12 User manual* (TECHLINE), page "Actuator
//! with IC and Endstop Signals – I/O specifications": a 100 mm stroke
//! (the longest its potentiometer feedback covers, "Max. 100 mm stroke");
//! single Hall sensor, option L, 2 pulses, 1 mm per pulse on the 12xLxx-1;
//! analogue feedback, option K, 0.5 – 4.5 V. Its retracted (built-in)
//! length is on the manual's dimension drawing, which was not available
//! here: the 245 mm pivot to pivot below is an assumed value for the
//! mounting, not a data-sheet figure. The pivot distances are chosen to fit
//! that stroke: a = 300 mm, b = 150 mm (|a − b| = 150 < 245 and
//! 245 + 100 = 345 < a + b = 450).

use drivers::linear::{ActuatorGeometry, LinearError, PotCalibration, PulseScale};

const GEOMETRY: ActuatorGeometry = ActuatorGeometry::LA12_EXAMPLE;

/// Stated tolerances of the f32 round trips: 0.001° and 0.001 mm. Over this
/// stroke dγ/dL = L / (ab · sin γ) ≤ 345 / (45 000 · sin 54.3°) = 0.0094
/// rad/mm (0.54°/mm), and f32 keeps L to about 3 · 10⁻⁵ mm: the expected
/// error is near 2 · 10⁻⁵°, fifty times inside the tolerance.
const TOL_DEG: f32 = 0.001;
const TOL_MM: f32 = 0.001;

#[test]
fn the_ends_of_the_stroke_by_hand() {
    // L = 245: cos γ = (90 000 + 22 500 − 60 025) / 90 000 = 52 475 / 90 000
    // = 0.583 06, γ = 54.334°, axis = 54.334 − 75 = −20.666°.
    // L = 345: cos γ = (112 500 − 119 025) / 90 000 = −0.072 50,
    // γ = 94.158°, axis = +19.158°.
    let lo = GEOMETRY.axis_deg(245.0).unwrap();
    let hi = GEOMETRY.axis_deg(345.0).unwrap();
    assert!((lo - -20.666).abs() < 0.001, "{lo}");
    assert!((hi - 19.158).abs() < 0.001, "{hi}");
}

#[test]
fn angle_to_length_to_angle_over_the_whole_stroke() {
    // Axis angles from end to end of the stroke (−20.666° … +19.158°,
    // above), 2001 steps including both ends.
    let lo = GEOMETRY.axis_deg(245.0).unwrap();
    let hi = GEOMETRY.axis_deg(345.0).unwrap();
    let n = 2_000;
    for i in 0..=n {
        let axis = lo + (hi - lo) * i as f32 / n as f32;
        let l = GEOMETRY.length_mm(axis).unwrap();
        assert!((245.0..=345.0).contains(&l), "{axis}° → {l} mm");
        let back = GEOMETRY.axis_deg(l).unwrap();
        assert!((back - axis).abs() < TOL_DEG, "{axis}° → {l} mm → {back}°");
    }
}

#[test]
fn length_to_angle_to_length_over_the_whole_stroke() {
    for i in 0..=1_000 {
        let l = 245.0 + 100.0 * i as f32 / 1_000.0;
        let axis = GEOMETRY.axis_deg(l).unwrap();
        let back = GEOMETRY.length_mm(axis).unwrap();
        assert!((back - l).abs() < TOL_MM, "{l} mm → {axis}° → {back} mm");
    }
}

#[test]
fn la12_worked_example() {
    // Axis +15° → γ = 15 + 75 = 90°, cos γ = 0:
    //   L = √(300² + 150²) = √112 500 = 335.4102 mm,
    //   extension = 335.4102 − 245 = 90.4102 mm.
    let l = GEOMETRY.length_mm(15.0).unwrap();
    assert!((l - 335.4102).abs() < 0.001, "{l}");
    let ext = GEOMETRY.extension_mm(l).unwrap();
    assert!((ext - 90.4102).abs() < 0.001, "{ext}");

    // Hall, option L: 1 mm per pulse → 90.41 → 90 pulses from retracted.
    let hall = PulseScale::new(1.0).unwrap();
    assert_eq!(hall.pulses(ext), Ok(90));
    // Back from 90 pulses: 90 mm, L = 335 mm,
    // cos γ = (112 500 − 112 225) / 90 000 = 0.003 056, γ = 89.8249°,
    // axis = 14.8249° (the pulse quantisation: 0.41 mm, 0.18°).
    let l90 = GEOMETRY
        .length_from_extension_mm(hall.extension_mm(90))
        .unwrap();
    assert_eq!(l90, 335.0);
    let axis90 = GEOMETRY.axis_deg(l90).unwrap();
    assert!((axis90 - 14.8249).abs() < 0.001, "{axis90}");

    // Potentiometer, option K, on a 10-bit ADC over 5 V: 0.5 V reads
    // 0.5 / 5 · 1023 = 102.3 → 102 retracted, 4.5 V reads 920.7 → 921
    // extended (calibrated at the end stops: 819 counts over 100 mm).
    let pot = PotCalibration::new(102, 921, 100.0).unwrap();
    // 90.4102 mm → 102 + 819 · 0.904 102 = 842.46 → 842 counts.
    assert_eq!(pot.counts(ext), Ok(842));
    // 842 counts → 740 / 819 · 100 = 90.3541 mm, L = 335.3541 mm,
    // L² = 112 462.37, cos γ = 37.634 / 90 000 = 0.000 418, γ = 89.9760°,
    // axis 14.9760°.
    let e842 = pot.extension_mm(842).unwrap();
    assert!((e842 - 90.3541).abs() < 0.001, "{e842}");
    let axis842 = GEOMETRY
        .axis_deg(GEOMETRY.length_from_extension_mm(e842).unwrap())
        .unwrap();
    assert!((axis842 - 14.9760).abs() < 0.001, "{axis842}");
}

#[test]
fn errors_not_panics() {
    let g = GEOMETRY;
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(g.length_mm(bad), Err(LinearError::NotFinite));
        assert_eq!(g.axis_deg(bad), Err(LinearError::NotFinite));
        assert_eq!(g.extension_mm(bad), Err(LinearError::NotFinite));
        assert_eq!(g.length_from_extension_mm(bad), Err(LinearError::NotFinite));
    }
    // Triangle: 150 ≤ L ≤ 450.
    assert_eq!(g.axis_deg(149.9), Err(LinearError::OutsideTriangle));
    assert_eq!(g.axis_deg(450.1), Err(LinearError::OutsideTriangle));
    // Stroke: 245 ≤ L ≤ 345 (0.01 mm of rounding allowed at the ends).
    assert_eq!(g.axis_deg(244.9), Err(LinearError::OutsideStroke));
    assert_eq!(g.axis_deg(345.1), Err(LinearError::OutsideStroke));
    assert_eq!(g.extension_mm(345.005), Ok(100.0));
    // Axis +30° → γ 105°: L² = 112 500 + 90 000 · 0.2588 = 135 794, L = 368.5
    // mm, beyond the stroke. Axis −80° → γ −5°: no hinge angle.
    assert_eq!(g.length_mm(30.0), Err(LinearError::OutsideStroke));
    assert_eq!(g.length_mm(-80.0), Err(LinearError::AngleOutOfRange));
    // Configurations.
    for bad in [
        ActuatorGeometry { a_mm: 0.0, ..g },
        ActuatorGeometry {
            stroke_mm: -1.0,
            ..g
        },
        ActuatorGeometry {
            retracted_mm: 150.0,
            ..g
        }, // = |a − b|: degenerate
        ActuatorGeometry {
            offset_deg: f32::NAN,
            ..g
        },
    ] {
        assert_eq!(bad.validate(), Err(LinearError::InvalidConfig));
        assert_eq!(bad.length_mm(0.0), Err(LinearError::InvalidConfig));
        assert_eq!(bad.axis_deg(300.0), Err(LinearError::InvalidConfig));
    }
    // Pulses and counts.
    let hall = PulseScale::new(1.0).unwrap();
    assert_eq!(hall.pulses(-2_147_483_648.0), Ok(i32::MIN));
    assert_eq!(
        hall.pulses(2_147_483_648.0),
        Err(LinearError::TooManyPulses)
    );
    assert_eq!(PulseScale::new(f32::NAN), Err(LinearError::InvalidConfig));
    let pot = PotCalibration::new(102, 921, 100.0).unwrap();
    assert_eq!(pot.extension_mm(101), Err(LinearError::OutsideStroke));
    assert_eq!(pot.extension_mm(922), Err(LinearError::OutsideStroke));
    assert_eq!(pot.counts(-0.1), Err(LinearError::OutsideStroke));
    assert_eq!(
        PotCalibration::new(0, 1_023, f32::NAN),
        Err(LinearError::InvalidConfig)
    );
}
