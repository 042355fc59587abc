//! Grena, R. (2012), "Five new algorithms for the computation of sun position
//! from 2010 to 2110", Solar Energy 86, 1323–1337: algorithms 1–5.
//!
//! Time is t = days from 2060-01-01 00:00 UT (the paper's origin, section
//! 3.1) and tₑ = t + ΔT/86 400 on TT. Both reach ±18 000 days, where an `f32`
//! keeps only 0.002 day (0.7° of hour angle): the whole days stay an integer
//! and the secular terms (rate × t) are reduced in exact fixed-point turns
//! (the crate-private `spa::split`); only small arguments reach the float type.
//!
//! The coefficients are the paper's (sections 3.3–3.7). Algorithms 1 and 2
//! fit α and δ directly with 2 and 4 harmonics; 3 fits the ecliptic
//! longitude; 4 adds the main nutation term; 5 adds further harmonic and
//! perturbation terms. Stated maximum errors in 2010–2110: 0.19°, 0.034°,
//! 0.0094°, 0.0093°, 0.0027°. Parallax (−4.26 × 10⁻⁵ rad · cos e) and
//! Grena's refraction formula (section 3.7) when an atmosphere is given.
//!
//! # Example
//!
//! ```
//! use sun_algos::{Algorithm, Options, Site, SunPosition, UtcTime};
//!
//! // tests/data/sun_2010_2110.csv (JPL DE421 through skyfield):
//! // 2043-07-21T13:59:03Z, 59.44343°, −27.75479°, ΔT 70.21 s → zenith
//! // 39.0347647°, azimuth 180.572822°. Each algorithm within the maximum
//! // error Grena 2012 states for it.
//! let t: UtcTime = "2043-07-21T13:59:03Z".parse()?;
//! let site = Site::new(59.44343f64, -27.75479)?;
//! let opts = Options { delta_t_s: Some(70.21), ..Options::default() };
//! let truth = SunPosition::new(39.034_764_7, 180.572_822, false);
//! for (a, stated_deg) in [
//!     (Algorithm::Grena2012No1, 0.19),
//!     (Algorithm::Grena2012No2, 0.034),
//!     (Algorithm::Grena2012No3, 0.0094),
//!     (Algorithm::Grena2012No4, 0.0093),
//!     (Algorithm::Grena2012No5, 0.0027),
//! ] {
//!     let p = a.position(&t, &site, &opts)?;
//!     assert!(p.angular_distance_deg(&truth) < stated_deg, "{}", a.name());
//! }
//! # Ok::<(), sun_algos::Error>(())
//! ```

use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;
use crate::site::Atmosphere;
use crate::spa::split::Secular;
use crate::time::MS_PER_DAY;

/// The five algorithms of Grena 2012, chosen through [`crate::Algorithm`]
/// (`Grena2012No1` … `Grena2012No5`); the module documentation compares all
/// five with the reference ephemeris.
///
/// ```
/// use sun_algos::grena2012::Variant;
/// use sun_algos::{Algorithm, Options, Site, SunPosition, UtcTime};
///
/// // tests/data/sun_2010_2110.csv (JPL DE421 through skyfield):
/// // 2043-07-21T13:59:03Z, 59.44343°, −27.75479°, ΔT 70.21 s → zenith
/// // 39.0347647°, azimuth 180.572822°; algorithm 5 states 0.0027°.
/// let t: UtcTime = "2043-07-21T13:59:03Z".parse()?;
/// let opts = Options { delta_t_s: Some(70.21), ..Options::default() };
/// let p = Algorithm::Grena2012No5.position(&t, &Site::new(59.44343f64, -27.75479)?, &opts)?;
/// assert!(p.angular_distance_deg(&SunPosition::new(39.034_764_7, 180.572_822, false)) < 0.0027);
/// assert_ne!(Variant::No1, Variant::No5);
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
        let frac_ut = T::from_u32(inp.time.ms_of_day()) * T::from_f64(1.0 / MS_PER_DAY as f64);
        let frac_tt = frac_ut + inp.delta_t_s * T::from_f64(1.0 / 86_400.0);
        Time {
            days,
            frac_ut,
            frac_tt,
            te: T::from_i32(days) + frac_tt,
        }
    }
    /// A secular angle at tₑ, radians within a few turns of `[0, 2π)`.
    fn at_te(&self, s: &Secular) -> T {
        s.rad(self.days, self.frac_tt)
    }
    /// A secular angle at t (UT), radians within a few turns of `[0, 2π)`.
    fn at_t(&self, s: &Secular) -> T {
        s.rad(self.days, self.frac_ut)
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

/// cos and sin of the phase 0.06172 of algorithms 3–4 (section 3.4).
const COS_SIN_PHASE_1: (f64, f64) = (0.998_095_925_357_038_8, 0.061_680_821_862_848_165);
/// cos and sin of the phase 0.1163 of algorithms 3–4.
const COS_SIN_PHASE_2: (f64, f64) = (0.993_244_774_242_846, 0.116_038_004_288_586_22);
/// The obliquity's constant term ε₀ = 0.4089567 rad (sections 3.4–3.6).
#[cfg(test)]
const EPS0_RAD: f64 = 0.408_956_7;
/// cos ε₀ and sin ε₀.
const COS_SIN_EPS0: (f64, f64) = (0.917_536_192_721_599_4, 0.397_652_279_065_457_1);

/// `sin(wte − p)` from `sin wte`, `cos wte` and `(cos p, sin p)`.
#[inline]
fn sin_minus<T: Float>(s: T, c: T, phase: (f64, f64)) -> T {
    s * T::from_f64(phase.0) - c * T::from_f64(phase.1)
}

/// sin and cos of ε₀ + x for the obliquity's small variation x (|x| <
/// 2 × 10⁻⁴ rad in 2010–2110), by the addition theorem with the series of
/// sin x and cos x to the order the type can hold (x⁵/120 < 10⁻²⁰).
#[inline]
fn sin_cos_eps<T: Float>(x: T) -> (T, T) {
    let f = T::from_f64;
    let x2 = x * x;
    let sx = x * (T::ONE - x2 / f(6.0));
    let cx = T::ONE - x2 / f(2.0) * (T::ONE - x2 / f(12.0));
    let (c0, s0) = (f(COS_SIN_EPS0.0), f(COS_SIN_EPS0.1));
    (s0 * cx + c0 * sx, c0 * cx - s0 * sx)
}

/// The sun's position by Grena 2012 algorithm `v` for validated inputs.
pub(crate) fn position<T: Float>(inp: &Inputs<'_, T>, v: Variant) -> SunPosition<T> {
    let t = Time::new(inp);
    let f = T::from_f64;
    let lon_rad = inp.site.longitude_deg().to_radians();
    // (sin δ, cos δ cos H, cos δ sin H) per algorithm.
    let (sin_d, cd_ch, cd_sh) = match v {
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
            let (sh, ch) = (t.at_t(&H0_12) + lon_rad - alpha).sin_cos();
            (sd, cd * ch, cd * sh)
        }
        Variant::No3 | Variant::No4 | Variant::No5 => {
            let (s1, c1) = t.at_te(&WTE_345).sin_cos();
            // The two annual harmonics of algorithms 3–4, by the addition
            // theorem from sin and cos of ω tₑ.
            let harmonics = |l: T| {
                let (s2, c2) = (f(2.0) * s1 * c1, (c1 + s1) * (c1 - s1));
                l + f(3.3366e-2) * sin_minus(s1, c1, COS_SIN_PHASE_1)
                    + f(3.53e-4) * sin_minus(s2, c2, COS_SIN_PHASE_2)
            };
            let (lambda, eps_var, dlambda) = match v {
                Variant::No3 => (harmonics(t.at_te(&LAMBDA_3)), f(-6.19e-9) * t.te, T::ZERO),
                _ => {
                    let l = if v == Variant::No4 {
                        harmonics(t.at_te(&L_4))
                    } else {
                        l_no5(&t, s1, c1)
                    };
                    // Nutation: ν = 9.282 × 10⁻⁴ tₑ − 0.8.
                    let (s_nu, c_nu) = (f(9.282e-4) * t.te - f(0.8)).sin_cos();
                    let dlambda = f(8.34e-5) * s_nu;
                    let eps_var = f(-6.19e-9) * t.te + f(4.46e-5) * c_nu;
                    (l + T::PI + dlambda, eps_var, dlambda)
                }
            };
            let (sl, cl) = lambda.sin_cos();
            let (se, ce) = sin_cos_eps(eps_var);
            // α = atan2(sin λ cos ε, cos λ) and H = H₀ + θ − α: with
            // cos δ cos α = cos λ and cos δ sin α = sin λ cos ε, the
            // subtraction theorem gives cos δ cos H and cos δ sin H directly.
            let (sb, cb) = (t.at_t(&H0_345) + lon_rad + f(0.92) * dlambda).sin_cos();
            let sl_ce = sl * ce;
            (sl * se, cb * cl + sb * sl_ce, sb * cl - cb * sl_ce)
        }
    };
    horizon(
        inp.site.latitude_deg().to_radians(),
        sin_d,
        cd_ch,
        cd_sh,
        inp.atmosphere.as_ref(),
    )
}

/// Algorithm 5's heliocentric longitude L (section 3.6).
fn l_no5<T: Float>(t: &Time<T>, s1: T, c1: T) -> T {
    let f = T::from_f64;
    let te = t.te;
    let (s2, c2) = (f(2.0) * s1 * c1, (c1 + s1) * (c1 - s1));
    let (s3, c3) = (s2 * c1 + c2 * s1, c2 * c1 - s2 * s1);
    let mut l = t.at_te(&L_5) + f(3.33024e-2) * s1 - f(2.0582e-3) * c1 + f(3.512e-4) * s2
        - f(4.07e-5) * c2
        + f(5.2e-6) * s3
        - f(9e-7) * c3
        - f(8.23e-5) * s1 * (f(2.92e-5) * te).sin();
    // Slow perturbations: amplitude, frequency (day⁻¹), phase.
    let wave = |a: f64, w: f64, p: f64| f(a) * (f(w) * te + f(p)).sin();
    l += wave(1.27e-5, 1.49e-3, -2.337)
        + wave(1.21e-5, 4.31e-3, 3.065)
        + wave(2.33e-5, 1.076e-2, -1.533)
        + wave(3.49e-5, 1.575e-2, -2.358)
        + wave(2.67e-5, 2.152e-2, 0.074)
        + wave(1.28e-5, 3.152e-2, 1.547)
        + wave(3.14e-5, 2.1277e-1, -0.488);
    l
}

/// Section 3.7 from sin δ, cos δ cos H and cos δ sin H: topocentric elevation (parallax −4.26 × 10⁻⁵ rad · cos e0),
/// azimuth, and Grena's refraction for an elevation above 0 (pressure in
/// atm, temperature in °C).
fn horizon<T: Float>(
    lat_rad: T,
    sin_d: T,
    cd_ch: T,
    cd_sh: T,
    atmosphere: Option<&Atmosphere<T>>,
) -> SunPosition<T> {
    let f = T::from_f64;
    let (sp, cp) = lat_rad.sin_cos();
    let up = sp * sin_d + cp * cd_ch;
    let north = cp * sin_d - sp * cd_ch;
    let east = -cd_sh;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithm::Algorithm;
    use crate::site::{Options, Site};
    use crate::time::UtcTime;

    #[test]
    fn precomputed_constants() {
        for (x, (c, s)) in [
            (0.06172f64, COS_SIN_PHASE_1),
            (0.1163, COS_SIN_PHASE_2),
            (EPS0_RAD, COS_SIN_EPS0),
        ] {
            assert!((x.cos() - c).abs() < 1e-16 && (x.sin() - s).abs() < 1e-16);
        }
        for x in [-2e-4f64, -3e-5, 0.0, 1e-6, 2e-4] {
            let (s, c) = sin_cos_eps(x);
            assert!((s - (EPS0_RAD + x).sin()).abs() < 2e-16);
            assert!((c - (EPS0_RAD + x).cos()).abs() < 2e-16);
        }
    }

    /// Algorithms 3–5 written literally as in the paper (t from the
    /// paper's calendar formula, fmod, atan2 and asin), in f64, as an
    /// independent check of the split time and the trigonometric identities.
    #[allow(clippy::too_many_arguments)]
    fn literal(
        v: Variant,
        y: i32,
        mo: i32,
        d: i32,
        ut_h: f64,
        dt: f64,
        lat: f64,
        lon: f64,
    ) -> (f64, f64) {
        let (yt, mt) = if mo <= 2 { (y - 1, mo + 12) } else { (y, mo) };
        let t = (365.25 * f64::from(yt - 2000)).trunc() + (30.6001 * f64::from(mt + 1)).trunc()
            - (0.01 * f64::from(yt)).trunc()
            + f64::from(d)
            + ut_h / 24.0
            - 21958.0;
        let te = t + dt / 86400.0;
        let wte = 0.0172019715 * te;
        let pi = core::f64::consts::PI;
        let (lambda, epsi, dlam) = match v {
            Variant::No3 => (
                -1.388803
                    + 1.720279216e-2 * te
                    + 3.3366e-2 * (wte - 0.06172).sin()
                    + 3.53e-4 * (2.0 * wte - 0.1163).sin(),
                4.089567e-1 - 6.19e-9 * te,
                0.0,
            ),
            _ => {
                let l = if v == Variant::No4 {
                    1.752790
                        + 1.720279216e-2 * te
                        + 3.3366e-2 * (wte - 0.06172).sin()
                        + 3.53e-4 * (2.0 * wte - 0.1163).sin()
                } else {
                    let (s1, c1) = wte.sin_cos();
                    let (s2, c2) = (2.0 * s1 * c1, (c1 + s1) * (c1 - s1));
                    let (s3, c3) = (s2 * c1 + c2 * s1, c2 * c1 - s2 * s1);
                    1.7527901 + 1.7202792159e-2 * te + 3.33024e-2 * s1 - 2.0582e-3 * c1
                        + 3.512e-4 * s2
                        - 4.07e-5 * c2
                        + 5.2e-6 * s3
                        - 9e-7 * c3
                        - 8.23e-5 * s1 * (2.92e-5 * te).sin()
                        + 1.27e-5 * (1.49e-3 * te - 2.337).sin()
                        + 1.21e-5 * (4.31e-3 * te + 3.065).sin()
                        + 2.33e-5 * (1.076e-2 * te - 1.533).sin()
                        + 3.49e-5 * (1.575e-2 * te - 2.358).sin()
                        + 2.67e-5 * (2.152e-2 * te + 0.074).sin()
                        + 1.28e-5 * (3.152e-2 * te + 1.547).sin()
                        + 3.14e-5 * (2.1277e-1 * te - 0.488).sin()
                };
                let nu = 9.282e-4 * te - 0.8;
                let dlam = 8.34e-5 * nu.sin();
                (
                    l + pi + dlam,
                    4.089567e-1 - 6.19e-9 * te + 4.46e-5 * nu.cos(),
                    dlam,
                )
            }
        };
        let (sl, cl) = lambda.sin_cos();
        let (se, ce) = epsi.sin_cos();
        let ra = (sl * ce).atan2(cl);
        let dec = (sl * se).asin();
        let h = 1.7528311 + 6.300388099 * t + lon.to_radians() - ra + 0.92 * dlam;
        let h = (h + pi).rem_euclid(2.0 * pi) - pi;
        let (sp, cp) = lat.to_radians().sin_cos();
        let (sd, cd) = dec.sin_cos();
        let (sh, ch) = h.sin_cos();
        let se0 = sp * sd + cp * cd * ch;
        let ep = se0.asin() - 4.26e-5 * (1.0 - se0 * se0).sqrt();
        let az = sh.atan2(ch * sp - sd * cp / cd);
        (
            90.0 - ep.to_degrees(),
            (az.to_degrees() + 180.0).rem_euclid(360.0),
        )
    }

    #[test]
    fn matches_the_literal_paper_form() {
        let cases = [
            (2012, 1, 1, 11.25, 66.9, 41.9, 12.5),
            (2031, 4, 5, 6.1189, 70.0, -33.9, 18.4),
            (2060, 1, 1, 0.0, 90.0, 60.0, -150.0),
            (2095, 8, 17, 20.27, 95.0, 3.9, -174.8),
        ];
        for v in [Variant::No3, Variant::No4, Variant::No5] {
            for &(y, mo, d, ut_h, dt, lat, lon) in &cases {
                let ms = (ut_h * 3_600_000.0f64).round() as u32;
                let base = UtcTime::from_ymd_hms(y, mo as u8, d as u8, 0, 0, 0).unwrap();
                let time = UtcTime::from_days_ms(base.days_since_2000(), ms).unwrap();
                let site = Site::new(lat, lon).unwrap();
                let opts = Options {
                    delta_t_s: Some(dt),
                    ..Options::default()
                };
                let inp = Inputs::new(Algorithm::Grena2012No3, &time, &site, &opts).unwrap();
                let p = position(&inp, v);
                let (z, a) = literal(v, y, mo, d, f64::from(ms) / 3_600_000.0, dt, lat, lon);
                // The paper's 0.0416667 h⁻¹ and 1.1574e-5 s⁻¹ round 1/24 and
                // 1/86400; the literal form uses them exactly, so the two
                // agree to far below the algorithms' accuracy.
                let want = SunPosition::new(z, a, false);
                let d = p.angular_distance_deg(&want);
                assert!(d < 1e-8, "{v:?} {y}: {p:?} vs {want:?}: {d}");
            }
        }
    }

    /// Refraction (section 3.7 of the paper) against Bennett's formula.
    #[test]
    fn refraction_agrees_with_bennett() {
        crate::refraction::tests::assert_close_to_bennett(Algorithm::Grena2012No3, 2030);
    }
}
