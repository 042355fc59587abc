//! The published forms of the incidence angle agree with the one
//! implementation (`sun_algos::geometry::incidence`).
//!
//! Each form is evaluated here as printed, from latitude φ, declination δ,
//! hour angle ω, slope β and surface azimuth γ (from south, west positive):
//! Jimoh & Aliyu (2019), eq (1), its reduced form eq (13) with c1–c3, and
//! Dahli & Cheggaga (2023), eq (8). The implementation receives the sun's
//! direction from Jimoh & Aliyu's eq (7)/(8b) and the surface in the crate's
//! north-referenced convention, so the test also pins the conventions.

use sun_algos::geometry::incidence::{cos_incidence, incidence_deg, Surface};
use sun_algos::geometry::optimum::eq14_slope_deg;
use sun_algos::geometry::simple::position_from_angles;

/// xorshift64*: deterministic inputs without a dependency.
struct Rng(u64);
impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

fn rad(d: f64) -> f64 {
    d.to_radians()
}

/// Jimoh & Aliyu (2019), eq (1), as printed.
fn jimoh_eq1(phi: f64, delta: f64, omega: f64, beta: f64, gamma: f64) -> f64 {
    let (sp, cp) = rad(phi).sin_cos();
    let (sd, cd) = rad(delta).sin_cos();
    let (sw, cw) = rad(omega).sin_cos();
    let (sb, cb) = rad(beta).sin_cos();
    let (sg, cg) = rad(gamma).sin_cos();
    sd * sp * cb + cd * cp * cb * cw + cd * sp * sb * cg * cw + cd * sb * sg * sw
        - sd * cp * sb * cg
}

/// Jimoh & Aliyu (2019), eq (13), with its c1, c2, c3.
fn jimoh_eq13(phi: f64, delta: f64, omega: f64, beta: f64, gamma: f64) -> f64 {
    let (sp, cp) = rad(phi).sin_cos();
    let (sd, cd) = rad(delta).sin_cos();
    let (sw, cw) = rad(omega).sin_cos();
    let c1 = sd * sp + cd * cp * cw;
    let c2 = cd * sp * cw - sd * cp;
    let c3 = cd * sw;
    let (sb, cb) = rad(beta).sin_cos();
    let (sg, cg) = rad(gamma).sin_cos();
    c1 * cb + c2 * sb * cg + c3 * sb * sg
}

/// Dahli & Cheggaga (2023), eq (8), as printed (L latitude, h hour angle,
/// Z_s the surface azimuth).
fn dahli_eq8(l: f64, delta: f64, h: f64, beta: f64, zs: f64) -> f64 {
    let (sl, cl) = rad(l).sin_cos();
    let (sd, cd) = rad(delta).sin_cos();
    let (sh, ch) = rad(h).sin_cos();
    let (sb, cb) = rad(beta).sin_cos();
    let (sz, cz) = rad(zs).sin_cos();
    sl * sd * cb - cl * sd * sb * cz
        + cl * cd * ch * cb
        + sl * cd * ch * sb * cz
        + cd * sh * sb * sz
}

#[test]
fn published_forms_agree_with_the_implementation() {
    let mut rng = Rng(0x5EED_1234_ABCD_0001);
    let mut worst = 0.0f64;
    for _ in 0..20_000 {
        let phi = rng.range(-89.9, 89.9);
        let delta = rng.range(-23.45, 23.45);
        let omega = rng.range(-180.0, 180.0);
        let beta = rng.range(0.0, 180.0);
        let gamma = rng.range(-180.0, 180.0);
        let sun = position_from_angles(phi, delta, omega);
        let surface = Surface::from_south_referenced(beta, gamma).unwrap();
        let ours = cos_incidence(&sun, &surface);
        for published in [
            jimoh_eq1(phi, delta, omega, beta, gamma),
            jimoh_eq13(phi, delta, omega, beta, gamma),
            dahli_eq8(phi, delta, omega, beta, gamma),
        ] {
            worst = worst.max((ours - published).abs());
        }
    }
    assert!(worst < 1e-12, "largest cos θ difference {worst:e}");
}

#[test]
fn f32_agrees_with_f64() {
    let mut rng = Rng(77);
    for _ in 0..5_000 {
        let (phi, delta, omega) = (
            rng.range(-89.0, 89.0),
            rng.range(-23.0, 23.0),
            rng.range(-170.0, 170.0),
        );
        let (beta, gamma) = (rng.range(0.0, 90.0), rng.range(-180.0, 180.0));
        let s64 = position_from_angles(phi, delta, omega);
        let s32 = position_from_angles(phi as f32, delta as f32, omega as f32);
        let a = incidence_deg(&s64, &Surface::from_south_referenced(beta, gamma).unwrap());
        let b = incidence_deg(
            &s32,
            &Surface::from_south_referenced(beta as f32, gamma as f32).unwrap(),
        );
        assert!((a - f64::from(b)).abs() < 0.01, "{a} {b}");
    }
}

#[test]
fn eq14_root_is_the_zenith_angle() {
    // With γ = γs, eq (14)'s c6 = cos θz and c7 = sin θz (eq 7, 8b), so the
    // root is β = θz: solve eq 14 from the coefficients as printed.
    let mut rng = Rng(99);
    for _ in 0..5_000 {
        let (phi, delta, omega) = (
            rng.range(-80.0, 80.0),
            rng.range(-23.0, 23.0),
            rng.range(-100.0, 100.0),
        );
        let sun = position_from_angles(phi, delta, omega);
        if sun.zenith_deg > 89.0 || sun.zenith_deg < 0.5 {
            continue;
        }
        let gs = rad(sun.azimuth_from_south_deg());
        let (sp, cp) = rad(phi).sin_cos();
        let (sd, cd) = rad(delta).sin_cos();
        let (sw, cw) = rad(omega).sin_cos();
        let c6 = sd * sp + cd * cp * cw;
        let c7 = cd * sp * cw * gs.cos() + cd * sw * gs.sin() - sd * cp * gs.cos();
        let beta = eq14_slope_deg(c6, c7);
        assert!((beta - sun.zenith_deg).abs() < 1e-9);
        // And the residual of eq 14 vanishes there.
        let r = c6 * rad(beta).cos() + c7 * rad(beta).sin() - 1.0;
        assert!(r.abs() < 1e-12);
    }
}
