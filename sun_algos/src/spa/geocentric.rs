//! From the Earth's heliocentric position to the sun's geocentric apparent
//! right ascension and declination, and the apparent sidereal time (NREL SPA
//! report, section 3.1–3.8).

use super::earth::{c32, heliocentric, is_f32, Heliocentric, DAYS_PER_MILLENNIUM};
use super::nutation::nutation_rad;
use super::split::{frac, Secular, SplitDays};
use crate::float::Float;

/// Days in a Julian century.
const DAYS_PER_CENTURY: f64 = 36_525.0;

/// Mean sidereal time at Greenwich, eq. 12 of section 3.8.1 (report eq. 28):
/// ν0 = 280.46061837 + 360.98564736629 (JD − 2451545) + …, degrees.
const SIDEREAL: Secular = Secular::degrees(280.460_618_37, 360.985_647_366_29);

/// Mean obliquity ε0 in arc seconds, eq. 24: coefficients of U⁰…U¹⁰, U = JME/10.
const OBLIQUITY_ARCSEC: [f64; 11] = [
    84_381.448, -4_680.93, -1.55, 1_999.25, -51.38, -249.67, -39.05, 7.12, 27.87, 5.79, 2.45,
];
/// [`OBLIQUITY_ARCSEC`] rounded to `f32` (no run-time conversion in `f32`).
const OBLIQUITY_ARCSEC_F32: [f32; 11] = {
    let mut out = [0.0f32; 11];
    let mut i = 0;
    while i < 11 {
        out[i] = OBLIQUITY_ARCSEC[i] as f32;
        i += 1;
    }
    out
};

/// Everything SPA knows before it looks at the observer.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Geocentric<T> {
    /// Julian ephemeris century (JCE), eq. 6.
    pub jce: T,
    /// Julian ephemeris millennium (JME), eq. 7.
    pub jme: T,
    /// Earth heliocentric L, B, R.
    pub helio: Heliocentric<T>,
    /// Nutation in longitude Δψ, radians (eq. 22).
    pub dpsi_rad: T,
    /// Nutation in obliquity Δε, radians (eq. 23).
    pub deps_rad: T,
    /// True obliquity ε, radians (eq. 25).
    pub eps_rad: T,
    /// Apparent sun longitude λ, radians (eq. 27).
    pub lambda_rad: T,
    /// Mean sidereal time at Greenwich ν0, radians in `[0, 2π)` (eq. 28).
    pub nu0_rad: T,
    /// Apparent sidereal time at Greenwich ν, radians (eq. 29).
    pub nu_rad: T,
    /// Geocentric right ascension α, radians in `(−π, π]` (eq. 30).
    pub alpha_rad: T,
    /// sin δ and cos δ of the geocentric declination (eq. 31).
    pub sin_delta: T,
    /// cos δ (≥ 0).
    pub cos_delta: T,
}

impl<T: Float> Geocentric<T> {
    /// Geocentric declination δ, radians (eq. 31).
    pub fn delta_rad(&self) -> T {
        self.sin_delta.atan2(self.cos_delta)
    }
}

/// Sections 3.1–3.8 for an instant split into days and fractions.
pub(crate) fn geocentric<T: Float>(t: &SplitDays<T>) -> Geocentric<T> {
    let jce = t.tt_in(DAYS_PER_CENTURY);
    let jme = t.tt_in(DAYS_PER_MILLENNIUM);
    let helio = heliocentric(t.days, t.frac_tt, jme);

    let (dpsi_rad, deps_rad) = nutation_rad(jce);
    let u = jme / T::from_f64(10.0);
    let mut eps0_arcsec = T::ZERO;
    if is_f32::<T>() {
        for c in OBLIQUITY_ARCSEC_F32.iter().rev() {
            eps0_arcsec = eps0_arcsec * u + c32::<T>(*c);
        }
    } else {
        for c in OBLIQUITY_ARCSEC.iter().rev() {
            eps0_arcsec = eps0_arcsec * u + T::from_f64(*c);
        }
    }
    let eps_rad = (eps0_arcsec / T::from_f64(3600.0)).to_radians() + deps_rad;

    // Eq. 13–14 and 26–27: Θ = L + 180°, β = −B, aberration Δτ = −20.4898″/R.
    let aberration_rad = (T::from_f64(-20.4898 / 3600.0) / helio.r_au).to_radians();
    let lambda_rad = helio.l_rad + T::PI + dpsi_rad + aberration_rad;
    let beta_rad = -helio.b_rad;

    // Eq. 28–29 on UT1; the JC² and JC³ terms are below 0.1″ for centuries.
    let jc = t.ut_in(DAYS_PER_CENTURY);
    let nu0_turns = frac(
        SIDEREAL.at(t.days, t.frac_ut)
            + jc * jc
                * (T::from_f64(0.000_387_933 / 360.0)
                    - jc * T::from_f64(1.0 / 38_710_000.0 / 360.0)),
    );
    let nu0_rad = nu0_turns * T::TAU;
    let (sin_eps, cos_eps) = eps_rad.sin_cos();
    let nu_rad = nu0_rad + dpsi_rad * cos_eps;

    // Eq. 30–31.
    let (sin_l, cos_l) = lambda_rad.sin_cos();
    let (sin_b, cos_b) = beta_rad.sin_cos();
    let alpha_rad = (sin_l * cos_eps - (sin_b / cos_b) * sin_eps).atan2(cos_l);
    let sin_delta = (sin_b * cos_eps + cos_b * sin_eps * sin_l).clamp(-T::ONE, T::ONE);
    let cos_delta = (T::ONE - sin_delta * sin_delta).sqrt();
    Geocentric {
        jce,
        jme,
        helio,
        dpsi_rad,
        deps_rad,
        eps_rad,
        lambda_rad,
        nu0_rad,
        nu_rad,
        alpha_rad,
        sin_delta,
        cos_delta,
    }
}
