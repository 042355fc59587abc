//! Expressions (6)–(7) of Choi et al., "Portable sun tracking system with
//! tilt and magnetic compensation" (see drivers/src/tilt/mount.rs for the
//! reconstruction, T = Rz(γ0)·Rx(α0)·Ry(β0) as in the tracker's attitude
//! module). Numbers from the paper's Table IV: Case 1 is the level mount
//! (α0 = β0 = 0), Case 2 has α0 = 35.26°, β0 = 30°. By hand (checked
//! with Python's math module), Case 2 gives cos θy = sin 35.26° = 0.577288
//! (θy = 54.740°) and cos θx = −cos 35.26° · sin 30° = −0.408270
//! (θx = 114.096°).

use drivers::tilt::adxl345::inclination_from_gravity;
use drivers::tilt::{
    axis_angles, axis_angles_from_elevations, axis_angles_from_gravity, mount_tilt, Acceleration,
    MountTilt, MountTiltError,
};
use drivers::tilt::{axis_angles_from_inclination, Inclination};

#[test]
fn table_iv_case_1_level() {
    let t = mount_tilt(90.0, 90.0).unwrap();
    assert!(t.alpha0_deg.abs() < 1e-5 && t.beta0_deg.abs() < 1e-5);
}

#[test]
fn table_iv_case_2() {
    let t = mount_tilt(114.096, 54.740).unwrap();
    assert!((t.alpha0_deg - 35.26).abs() < 0.01, "{t:?}");
    assert!((t.beta0_deg - 30.0).abs() < 0.01, "{t:?}");
    let (tx, ty) = axis_angles(&MountTilt {
        alpha0_deg: 35.26,
        beta0_deg: 30.0,
    });
    assert!(
        (tx - 114.096).abs() < 0.01 && (ty - 54.740).abs() < 0.01,
        "{tx} {ty}"
    );
}

#[test]
fn round_trip_over_the_range() {
    for a in (-85..=85).step_by(5) {
        for b in (-85..=85).step_by(5) {
            let tilt = MountTilt {
                alpha0_deg: a as f32,
                beta0_deg: b as f32,
            };
            let (tx, ty) = axis_angles(&tilt);
            let back = mount_tilt(tx, ty).unwrap();
            assert!(
                (back.alpha0_deg - a as f32).abs() < 0.05,
                "{a} {b} {back:?}"
            );
            assert!((back.beta0_deg - b as f32).abs() < 0.05, "{a} {b} {back:?}");
        }
    }
}

#[test]
fn bad_inputs_are_errors() {
    assert_eq!(mount_tilt(-1.0, 90.0), Err(MountTiltError::OutOfRange));
    assert_eq!(mount_tilt(90.0, 181.0), Err(MountTiltError::OutOfRange));
    assert_eq!(mount_tilt(f32::NAN, 90.0), Err(MountTiltError::OutOfRange));
    // Both axes 10° from vertical: cos² + cos² = 1.94 > 1.
    assert_eq!(mount_tilt(10.0, 10.0), Err(MountTiltError::Inconsistent));
    // y axis vertical.
    assert_eq!(mount_tilt(90.0, 0.0), Err(MountTiltError::Degenerate));
}

#[test]
fn from_accelerometer_and_elevations() {
    // Gravity reaction along +z only: both axes horizontal.
    let level = axis_angles_from_gravity(&Acceleration {
        x_g: 0.0,
        y_g: 0.0,
        z_g: 1.0,
    })
    .unwrap();
    assert!((level.0 - 90.0).abs() < 1e-4 && (level.1 - 90.0).abs() < 1e-4);
    // Case 2 as an accelerometer at rest would see it: its axes' vertical
    // components (cos θx, cos θy, cos α0 cos β0) = (−0.408270, 0.577288, 0.707145).
    let (tx, ty) = axis_angles_from_gravity(&Acceleration {
        x_g: -0.408_270,
        y_g: 0.577_288,
        z_g: 0.707_145,
    })
    .unwrap();
    let t = mount_tilt(tx, ty).unwrap();
    assert!((t.alpha0_deg - 35.26).abs() < 0.01 && (t.beta0_deg - 30.0).abs() < 0.01);
    assert_eq!(axis_angles_from_elevations(-24.0, 35.0), (114.0, 55.0));
    assert_eq!(
        axis_angles_from_gravity(&Acceleration {
            x_g: 0.0,
            y_g: 0.0,
            z_g: 0.0
        }),
        None
    );
}

#[test]
fn roll_pitch_path_agrees_with_gravity_path() {
    // Any gravity direction: angles straight from it, or via roll/pitch
    // (AN3461 formulas) and back, must agree.
    for (x, y, z) in [
        (-0.408_270f32, 0.577_288f32, 0.707_145f32),
        (0.2, -0.3, 0.93),
        (0.0, 0.0, 1.0),
        (0.5, 0.5, -0.707),
    ] {
        let a = Acceleration {
            x_g: x,
            y_g: y,
            z_g: z,
        };
        let direct = axis_angles_from_gravity(&a).unwrap();
        let incl = inclination_from_gravity(&a).unwrap();
        let via = axis_angles_from_inclination(&incl);
        assert!((direct.0 - via.0).abs() < 1e-3, "{direct:?} {via:?}");
        assert!((direct.1 - via.1).abs() < 1e-3, "{direct:?} {via:?}");
    }
    // Level sensor: 90°, 90°.
    let (tx, ty) = axis_angles_from_inclination(&Inclination {
        roll_deg: 0.0,
        pitch_deg: 0.0,
    });
    assert!((tx - 90.0).abs() < 1e-4 && (ty - 90.0).abs() < 1e-4);
}
