//! Grena, R. (2012), "Five new algorithms for the computation of sun position
//! from 2010 to 2110", Solar Energy 86, 1323–1337: algorithms 1–5.
//!
//! Time is t = days from 2060-01-01 00:00 UT (the paper's origin, section
//! 3.1) and tₑ = t + ΔT/86 400 on TT. Both reach ±18 000 days, where an `f32`
//! keeps only 0.002 day (0.7° of hour angle): the whole days stay an integer
//! and the secular terms (rate × t) are reduced in exact fixed-point turns
//! ([`crate::spa::split`]); only small arguments reach the float type.
//!
//! The coefficients are the paper's (sections 3.3–3.7). Algorithms 1 and 2
//! fit α and δ directly with 2 and 4 harmonics; 3 fits the ecliptic
//! longitude; 4 adds the main nutation term; 5 adds further harmonic and
//! perturbation terms. Stated maximum errors in 2010–2110: 0.19°, 0.034°,
//! 0.0094°, 0.0093°, 0.0027°. Parallax (−4.26 × 10⁻⁵ rad · cos e) and
//! Grena's refraction formula (section 3.7) when an atmosphere is given.

use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;
use crate::site::Atmosphere;
use crate::spa::split::{frac, Secular};
use crate::time::MS_PER_DAY;

/// The five algorithms of Grena 2012.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// Algorithm 1: α and δ with two harmonics (max error 0.19°).
    No1,
    /// Algorithm 2: α and δ with four harmonics (0.034°).
    No2,
    /// Algorithm 3: ecliptic longitude with two harmonics (0.0094°).
    No3,
    /// Algorithm 4: algorithm 3 plus the main nutation term (0.0093°).
    No4,
    /// Algorithm 5: the most accurate, with perturbation terms (0.0027°).
    No5,
}

/// Days from 2000-01-01 to 2060-01-01, the paper's time origin.
pub(crate) const DAYS_2000_TO_2060: i32 = 21_915;

/// Radians → turns for a constant.
const fn turns(rad: f64) -> f64 {
    rad / core::f64::consts::TAU
}

/// Split time of section 3.1: t = `days + frac_ut`, tₑ = `days + frac_tt`.
#[derive(Debug, Clone, Copy)]
struct Time<T> {
    days: i32,
    frac_ut: T,
    frac_tt: T,
    /// tₑ rounded to `T` (for slow terms only).
    te: T,
}

impl<T: Float> Time<T> {
    fn new(inp: &Inputs<'_, T>) -> Self {
        let days = inp.time.days_since_2000() - DAYS_2000_TO_2060;
        let frac_ut = T::from_u32(inp.time.ms_of_day()) / T::from_u32(MS_PER_DAY);
        let frac_tt = frac_ut + inp.delta_t_s / T::from_f64(86_400.0);
        Time {
            days,
            frac_ut,
            frac_tt,
            te: T::from_i32(days) + frac_tt,
        }
    }
    /// A secular angle at tₑ, radians in about `[0, 2π)`.
    fn at_te(&self, s: &Secular) -> T {
        frac(s.at(self.days, self.frac_tt)) * T::TAU
    }
    /// A secular angle at t (UT), radians in about `[0, 2π)`.
    fn at_t(&self, s: &Secular) -> T {
        frac(s.at(self.days, self.frac_ut)) * T::TAU
    }
}

/// ω tₑ of algorithms 1–2 (ω = 0.017202786 day⁻¹).
const WTE_12: Secular = Secular::turns(0.0, turns(0.017_202_786));
/// ω tₑ of algorithms 3–5 (ω = 0.0172019715 day⁻¹).
const WTE_345: Secular = Secular::turns(0.0, turns(0.017_201_971_5));
/// Algorithms 1–2: α = −1.38880 + 1.72027920 × 10⁻² tₑ + …
const ALPHA_12: Secular = Secular::turns(turns(-1.388_80), turns(1.720_279_20e-2));
/// Algorithm 3: λ = −1.388803 + 1.720279216 × 10⁻² tₑ + …
const LAMBDA_3: Secular = Secular::turns(turns(-1.388_803), turns(1.720_279_216e-2));
/// Algorithm 4: L = 1.752790 + 1.720279216 × 10⁻² tₑ + …
const L_4: Secular = Secular::turns(turns(1.752_790), turns(1.720_279_216e-2));
/// Algorithm 5: L = 1.7527901 + 1.7202792159 × 10⁻² tₑ + …
const L_5: Secular = Secular::turns(turns(1.752_790_1), turns(1.720_279_215_9e-2));
/// Algorithms 1–2: H = 1.75283 + 6.3003881 t + θ − α.
const H0_12: Secular = Secular::turns(turns(1.752_83), turns(6.300_388_1));
/// Algorithms 3–5: H = 1.7528311 + 6.300388099 t + θ − α (+ 0.92 Δλ).
const H0_345: Secular = Secular::turns(turns(1.752_831_1), turns(6.300_388_099));

/// The sun's position by Grena 2012 algorithm `v` for validated inputs.
pub(crate) fn position<T: Float>(inp: &Inputs<'_, T>, v: Variant) -> SunPosition<T> {
    let t = Time::new(inp);
    let f = T::from_f64;
    // (α, sin δ, cos δ, H without θ) per algorithm.
    let (alpha, sin_d, cos_d, h_base) = match v {
        Variant::No1 | Variant::No2 => {
            let (s1, c1) = t.at_te(&WTE_12).sin_cos();
            let (s2, c2) = (f(2.0) * s1 * c1, (c1 + s1) * (c1 - s1));
            let mut alpha = t.at_te(&ALPHA_12) + f(3.199e-2) * s1 - f(2.65e-3) * c1
                + f(4.050e-2) * s2
                + f(1.525e-2) * c2;
            let mut delta = f(6.57e-3) + f(7.347e-2) * s1 - f(3.9919e-1) * c1 + f(7.3e-4) * s2
                - f(6.60e-3) * c2;
            if v == Variant::No2 {
                let (s3, c3) = (s2 * c1 + c2 * s1, c2 * c1 - s2 * s1);
                let (s4, c4) = (f(2.0) * s2 * c2, (c2 + s2) * (c2 - s2));
                alpha += f(1.33e-3) * s3 + f(3.8e-4) * c3 + f(7.3e-4) * s4 + f(6.2e-4) * c4;
                delta += f(1.50e-3) * s3 - f(2.58e-3) * c3 + f(6e-5) * s4 - f(1.3e-4) * c4;
            }
            let (sd, cd) = delta.sin_cos();
            (alpha, sd, cd, t.at_t(&H0_12))
        }
        Variant::No3 | Variant::No4 | Variant::No5 => {
            let wte = t.at_te(&WTE_345);
            let (lambda, eps, dlambda) = match v {
                Variant::No3 => {
                    let lambda = t.at_te(&LAMBDA_3)
                        + f(3.3366e-2) * (wte - f(0.06172)).sin()
                        + f(3.53e-4) * (f(2.0) * wte - f(0.1163)).sin();
                    (lambda, f(4.089_567e-1) - f(6.19e-9) * t.te, T::ZERO)
                }
                _ => {
                    let l = if v == Variant::No4 {
                        t.at_te(&L_4)
                            + f(3.3366e-2) * (wte - f(0.06172)).sin()
                            + f(3.53e-4) * (f(2.0) * wte - f(0.1163)).sin()
                    } else {
                        l_no5(&t, wte)
                    };
                    // Nutation: ν = 9.282 × 10⁻⁴ tₑ − 0.8.
                    let (s_nu, c_nu) = (f(9.282e-4) * t.te - f(0.8)).sin_cos();
                    let dlambda = f(8.34e-5) * s_nu;
                    let eps = f(4.089_567e-1) - f(6.19e-9) * t.te + f(4.46e-5) * c_nu;
                    (l + T::PI + dlambda, eps, dlambda)
                }
            };
            let (sl, cl) = lambda.sin_cos();
            let (se, ce) = eps.sin_cos();
            let alpha = (sl * ce).atan2(cl);
            let sin_d = sl * se;
            let cos_d = (T::ONE - sin_d * sin_d).sqrt();
            (alpha, sin_d, cos_d, t.at_t(&H0_345) + f(0.92) * dlambda)
        }
    };
    let h = h_base + inp.site.longitude_deg().to_radians() - alpha;
    horizon(
        inp.site.latitude_deg().to_radians(),
        sin_d,
        cos_d,
        h,
        inp.atmosphere.as_ref(),
    )
}

/// Algorithm 5's heliocentric longitude L (section 3.6).
fn l_no5<T: Float>(t: &Time<T>, wte: T) -> T {
    let f = T::from_f64;
    let te = t.te;
    let (s1, c1) = wte.sin_cos();
    let (s2, c2) = (f(2.0) * s1 * c1, (c1 + s1) * (c1 - s1));
    let (s3, c3) = (s2 * c1 + c2 * s1, c2 * c1 - s2 * s1);
    // Slow perturbations: [amplitude, frequency (day⁻¹), phase].
    const TERMS: [[f64; 3]; 7] = [
        [1.27e-5, 1.49e-3, -2.337],
        [1.21e-5, 4.31e-3, 3.065],
        [2.33e-5, 1.076e-2, -1.533],
        [3.49e-5, 1.575e-2, -2.358],
        [2.67e-5, 2.152e-2, 0.074],
        [1.28e-5, 3.152e-2, 1.547],
        [3.14e-5, 2.1277e-1, -0.488],
    ];
    let mut l = t.at_te(&L_5) + f(3.33024e-2) * s1 - f(2.0582e-3) * c1 + f(3.512e-4) * s2
        - f(4.07e-5) * c2
        + f(5.2e-6) * s3
        - f(9e-7) * c3
        - f(8.23e-5) * s1 * (f(2.92e-5) * te).sin();
    for [a, w, p] in TERMS {
        l += f(a) * (f(w) * te + f(p)).sin();
    }
    l
}

/// Section 3.7: topocentric elevation (parallax −4.26 × 10⁻⁵ rad · cos e0),
/// azimuth, and Grena's refraction for an elevation above 0 (pressure in
/// atm, temperature in °C).
fn horizon<T: Float>(
    lat_rad: T,
    sin_d: T,
    cos_d: T,
    h: T,
    atmosphere: Option<&Atmosphere<T>>,
) -> SunPosition<T> {
    let f = T::from_f64;
    let (sp, cp) = lat_rad.sin_cos();
    let (sh, ch) = h.sin_cos();
    let up = sp * sin_d + cp * cos_d * ch;
    let north = cp * sin_d - sp * cos_d * ch;
    let east = -cos_d * sh;
    let horiz = (east * east + north * north).sqrt();
    let ep = up.atan2(horiz) - f(4.26e-5) * horiz;
    let de = match atmosphere {
        Some(atm) if ep > T::ZERO => {
            let p_atm = atm.pressure_hpa() / f(1013.25);
            f(0.08422) * p_atm
                / ((f(273.0) + atm.temperature_c()) * (ep + f(0.003138) / (ep + f(0.08919))).tan())
        }
        _ => T::ZERO,
    };
    SunPosition::new(
        (T::FRAC_PI_2 - ep - de).to_degrees(),
        east.atan2(north).to_degrees(),
        atmosphere.is_some(),
    )
}
