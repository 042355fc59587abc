//! Tilt compensation (Choi et al., "Portable sun tracking system with tilt and
//! magnetic compensation", Expressions (8)–(11)) and min/max hard/soft-iron
//! calibration, against an independent forward model: the test builds the
//! sensor reading from a known mount attitude with its own rotation matrices,
//! `h = Tᵀ·B` with `T = R_Z(γ₀)·R_X(α₀)·R_Y(β₀)` (the paper's Expression
//! (12)) and the earth field `B` in the horizontal frame (X west, Y south, Z up):
//! north component H·cos D, east H·sin D, down H·tan I  ->  B = (−H sin D, −H cos D, −H tan I).

use drivers::compass::calibration::{Calibration, CalibrationError, CalibrationSweep};
use drivers::compass::heading::{
    gamma0_deg, magnetic_heading_deg, magnetic_rotation_deg, true_heading_deg, wrap360_deg,
    HeadingError,
};
use drivers::compass::wmm::WmmModel;
use drivers::compass::Vector3;

type M = [[f64; 3]; 3];

fn mul(a: &M, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| a[r][0] * v[0] + a[r][1] * v[1] + a[r][2] * v[2])
}
fn mat(a: &M, b: &M) -> M {
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| (0..3).map(|k| a[r][k] * b[k][c]).sum()))
}
fn transpose(a: &M) -> M {
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| a[c][r]))
}
fn rx(t: f64) -> M {
    let (s, c) = t.to_radians().sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}
fn ry(t: f64) -> M {
    let (s, c) = t.to_radians().sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}
fn rz(t: f64) -> M {
    let (s, c) = t.to_radians().sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// Sensor reading (tracker axes) for mount angles γ₀, α₀, β₀ (degrees), a field of
/// horizontal strength `h`, inclination `inc` and declination `dec` (degrees).
fn sensor(gamma0: f64, alpha0: f64, beta0: f64, h: f64, inc: f64, dec: f64) -> [f64; 3] {
    let t = mat(&rz(gamma0), &mat(&rx(alpha0), &ry(beta0)));
    let d = dec.to_radians();
    let earth = [-h * d.sin(), -h * d.cos(), -h * inc.to_radians().tan()];
    mul(&transpose(&t), earth)
}

/// Magnetic-only reading (D = 0) for a mount whose +y axis has magnetic azimuth
/// `heading` (γ₀ = 180 − heading), tilted by roll α₀ and pitch β₀.
fn body_field(heading: f64, alpha0: f64, beta0: f64, h: f64, inc: f64) -> [f64; 3] {
    sensor(180.0 - heading, alpha0, beta0, h, inc, 0.0)
}

fn v(b: [f64; 3]) -> Vector3 {
    Vector3::new(b[0] as f32, b[1] as f32, b[2] as f32)
}

fn angle_diff(a: f32, b: f32) -> f32 {
    let d = wrap360_deg(a - b);
    d.min(360.0 - d)
}

#[test]
fn level_hand_cases() {
    // Home pose (γ₀ = 0, level): y points south, so magnetic north is -y and
    // down is -z: h = (0, -H, -Z). δ₀ = atan2(0, H) = 0, heading of +y = 180.
    let h = Vector3::new(0.0, -20.0, -40.0);
    assert!(magnetic_rotation_deg(h, 0.0, 0.0).unwrap().abs() < 1e-4);
    assert!((magnetic_heading_deg(h, 0.0, 0.0).unwrap() - 180.0).abs() < 1e-4);
    // +y pointing east (γ₀ = 90): x points south, north is -x: h = (-H, 0, -Z).
    let h = Vector3::new(-20.0, 0.0, -40.0);
    assert!((magnetic_rotation_deg(h, 0.0, 0.0).unwrap() - 90.0).abs() < 1e-4);
    assert!((magnetic_heading_deg(h, 0.0, 0.0).unwrap() - 90.0).abs() < 1e-4);
}

#[test]
fn tilt_compensation_recovers_heading() {
    // Tianjin-like field: H = 30 uT, I = 58 deg (steep: tilt errors are large uncompensated).
    let mut worst = 0.0f32;
    let mut worst_uncompensated = 0.0f32;
    for heading in (0..360).step_by(15) {
        for &(roll, pitch) in &[
            (0.0, 0.0),
            (20.0, 0.0),
            (0.0, 30.0),
            (-25.0, 15.0),
            (40.0, -35.0),
        ] {
            let b = v(body_field(heading as f64, roll, pitch, 30.0, 58.0));
            let got =
                magnetic_heading_deg(b, (roll as f32).to_radians(), (pitch as f32).to_radians())
                    .unwrap();
            worst = worst.max(angle_diff(got, heading as f32));
            let flat = magnetic_heading_deg(b, 0.0, 0.0).unwrap();
            worst_uncompensated = worst_uncompensated.max(angle_diff(flat, heading as f32));
        }
    }
    println!("tilt compensation: worst error {worst:.5} deg (uncompensated {worst_uncompensated:.1} deg)");
    assert!(worst < 0.01, "worst {worst}");
    assert!(worst_uncompensated > 10.0);
}

#[test]
fn declination_gives_true_heading() {
    // Expression (11): γ₀ = δ₀ − D. WMM2025 at Tianjin (39.1 N, 117.2 E), 2026.5.
    let d = WmmModel::wmm2025()
        .declination_deg(39.1, 117.2, 0.0, 2026.5)
        .unwrap();
    assert!(d < -6.0 && d > -9.0, "Tianjin declination {d}"); // the paper: 6-8 deg west in Korea
    let mut worst = 0.0f32;
    for gamma0 in (-180..180).step_by(20) {
        let h = v(sensor(gamma0 as f64, 10.0, -5.0, 30.0, 58.0, d));
        let (a, b) = (10f32.to_radians(), (-5f32).to_radians());
        let g = gamma0_deg(h, a, b, d as f32).unwrap();
        worst = worst.max(angle_diff(g, gamma0 as f32));
        // Azimuth of +y = 180 - γ₀ (what MountAttitude::from_sensors takes).
        let t = true_heading_deg(h, a, b, d as f32).unwrap();
        assert!(angle_diff(t, 180.0 - gamma0 as f32) < 0.01);
        // Uncorrected, the error is the declination itself.
        let m = magnetic_heading_deg(h, a, b).unwrap();
        assert!((angle_diff(m, t) - (d as f32).abs()).abs() < 0.01);
    }
    assert!(worst < 0.01, "{worst}");
}

#[test]
fn heading_errors() {
    assert_eq!(
        magnetic_heading_deg(Vector3::new(f32::NAN, 0.0, 1.0), 0.0, 0.0),
        Err(HeadingError::NonFinite)
    );
    assert_eq!(
        magnetic_heading_deg(Vector3::new(0.0, 0.0, -50.0), 0.0, 0.0),
        Err(HeadingError::NoHorizontalField)
    );
    assert_eq!(
        true_heading_deg(Vector3::new(1.0, 0.0, 1.0), 0.0, 0.0, f32::INFINITY),
        Err(HeadingError::NonFinite)
    );
}

/// Applies axis-aligned soft iron then hard iron, as the min/max model assumes.
fn distort(b: [f64; 3]) -> Vector3 {
    let scale = [1.25, 0.8, 1.05];
    let offset = [12.0, -9.0, 4.0];
    v([0, 1, 2].map(|i| b[i] * scale[i] + offset[i]))
}

/// Deterministic pseudo-random noise in -amp..amp (64-bit LCG, Knuth's MMIX constants).
fn noisy(v: Vector3, state: &mut u64, amp: f32) -> Vector3 {
    let mut next = || {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*state >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0) * amp
    };
    Vector3::new(v.x + next(), v.y + next(), v.z + next())
}

#[test]
fn min_max_calibration_from_3d_sweep() {
    let mut sweep = CalibrationSweep::new();
    let mut rng = 1u64;
    // Full rotation sweep (a hand-held calibration before mounting): heading 0..360
    // in 5 deg steps, pitch and roll each all the way round in 15 deg steps.
    // (A sweep that never turns z against the field cannot centre z: see finish_xy.)
    for heading in (0..360).step_by(5) {
        for tilt in (-180..180).step_by(15) {
            // 0.2 uT sensor noise on a 57 uT field.
            let a = distort(body_field(heading as f64, 0.0, tilt as f64, 30.0, 58.0));
            let b = distort(body_field(heading as f64, tilt as f64, 0.0, 30.0, 58.0));
            sweep.add(noisy(a, &mut rng, 0.2)).unwrap();
            sweep.add(noisy(b, &mut rng, 0.2)).unwrap();
        }
    }
    let cal = sweep.finish(100, 5.0).unwrap();
    // Expected offsets are the injected hard iron; scale ratios undo 1.25 : 0.8 : 1.05.
    assert!((cal.offset.x - 12.0).abs() < 0.3 && (cal.offset.y + 9.0).abs() < 0.3);
    assert!((cal.offset.z - 4.0).abs() < 0.3);
    assert!(((cal.scale.y / cal.scale.x) - 1.25 / 0.8).abs() < 0.02);

    let mut worst_raw = 0.0f32;
    let mut worst_cal = 0.0f32;
    for heading in (0..360).step_by(7) {
        for &(roll, pitch) in &[(0.0, 0.0), (15.0, -10.0), (-30.0, 25.0)] {
            let raw = distort(body_field(heading as f64, roll, pitch, 30.0, 58.0));
            let (r, p) = ((roll as f32).to_radians(), (pitch as f32).to_radians());
            let h_raw = magnetic_heading_deg(raw, r, p).unwrap();
            let h_cal = magnetic_heading_deg(cal.apply(raw), r, p).unwrap();
            worst_raw = worst_raw.max(angle_diff(h_raw, heading as f32));
            worst_cal = worst_cal.max(angle_diff(h_cal, heading as f32));
        }
    }
    println!(
        "calibration: worst heading error {worst_raw:.1} deg raw, {worst_cal:.3} deg calibrated"
    );
    assert!(worst_raw > 10.0);
    assert!(worst_cal < 1.0, "{worst_cal}");
}

#[test]
fn xy_calibration_from_azimuth_only_sweep() {
    let mut sweep = CalibrationSweep::new();
    for heading in 0..360 {
        sweep
            .add(distort(body_field(heading as f64, 0.0, 0.0, 30.0, 58.0)))
            .unwrap();
    }
    // z hardly moves in an azimuth sweep: 3-axis calibration must refuse.
    assert_eq!(sweep.finish(100, 5.0), Err(CalibrationError::SpanTooSmall));
    let cal = sweep.finish_xy(100, 5.0).unwrap();
    assert_eq!((cal.offset.z, cal.scale.z), (0.0, 1.0));
    let mut worst = 0.0f32;
    for heading in (0..360).step_by(3) {
        let raw = distort(body_field(heading as f64, 0.0, 0.0, 30.0, 58.0));
        let h = magnetic_heading_deg(cal.apply(raw), 0.0, 0.0).unwrap();
        worst = worst.max(angle_diff(h, heading as f32));
    }
    println!("xy calibration: worst level heading error {worst:.3} deg");
    assert!(worst < 0.2, "{worst}");
}

#[test]
fn calibration_errors() {
    let mut s = CalibrationSweep::new();
    assert_eq!(
        s.add(Vector3::new(f32::NAN, 0.0, 0.0)),
        Err(CalibrationError::NonFinite)
    );
    assert_eq!(s.samples(), 0);
    s.add(Vector3::new(1.0, 1.0, 1.0)).unwrap();
    assert_eq!(s.finish(10, 1.0), Err(CalibrationError::TooFewSamples));
    assert_eq!(
        Calibration::IDENTITY.apply(Vector3::new(1.0, 2.0, 3.0)),
        Vector3::new(1.0, 2.0, 3.0)
    );
}
