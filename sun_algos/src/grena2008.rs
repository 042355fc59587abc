//! Grena, R. (2008), "An algorithm for the computation of the solar
//! position", Solar Energy 82, 462–470 (the "ENEA" algorithm), valid
//! 2003–2022.
//!
//! Time (section 3.1) is JDₜ = JD − 2 452 640 (UT; 2003-01-01 00:00 is 0.5)
//! and t = JDₜ + ΔT/86 400 (TT). Its secular terms, Earth's mean motion in
//! the heliocentric longitude and Earth's rotation in the hour angle, are
//! evaluated from the whole days in exact fixed-point turns
//! (the crate-private `spa::split`), so `f32` keeps its precision; the periodic terms
//! take t directly. Coefficients are the paper's (sections 3.2–3.8).
//!
//! # Example
//!
//! ```
//! use sun_algos::{Algorithm, Options, Site, SunPosition, UtcTime};
//!
//! // tests/data/sun_1999_2022.csv (JPL DE421 through skyfield):
//! // 2005-03-30T13:27:49Z, 16.06476°, −6.58661°, ΔT 64.757 s → zenith
//! // 18.5379338°, azimuth 230.6523814°. Grena 2008 (ENEA) declares 0.0027°.
//! let t: UtcTime = "2005-03-30T13:27:49Z".parse()?;
//! let site = Site::new(16.06476f64, -6.58661)?;
//! let opts = Options { delta_t_s: Some(64.757), ..Options::default() };
//! let p = Algorithm::Grena2008.position(&t, &site, &opts)?;
//! assert!(p.angular_distance_deg(&SunPosition::new(18.537_933_8, 230.652_381_4, false)) < 0.0027);
//! # Ok::<(), sun_algos::Error>(())
//! ```

use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;
use crate::spa::split::Secular;
use crate::time::MS_PER_DAY;

/// Days from 2000-01-01 to 2003-01-01.
const DAYS_2000_TO_2003: i32 = 1096;

const fn turns(rad: f64) -> f64 {
    rad / core::f64::consts::TAU
}

/// Section 3.2.1: L = 1.740940 + 1.7202768683 × 10⁻² t + … (t from JD 2452640).
/// The day count here starts at 2003-01-01 00:00, half a day after the
/// paper's origin, so the offset takes that half day.
const L_LINEAR: Secular = Secular::turns(
    turns(1.740_940 + 0.5 * 1.720_276_868_3e-2),
    turns(1.720_276_868_3e-2),
);
/// Section 3.6: H = 6.30038809903 JDₜ + 4.8824623 + 0.9174 Δψ + θ − α.
const H_LINEAR: Secular = Secular::turns(
    turns(4.882_462_3 + 0.5 * 6.300_388_099_03),
    turns(6.300_388_099_03),
);

/// `a · sin(w t + p)`, constants folded at compile time.
#[inline(always)]
fn wave<T: Float>(a: f64, w: f64, p: f64, t: T) -> T {
    T::from_f64(a) * (T::from_f64(w) * t + T::from_f64(p)).sin()
}

/// The sun's position by Grena 2008 for validated inputs.
pub(crate) fn position<T: Float>(inp: &Inputs<'_, T>) -> SunPosition<T> {
    let f = T::from_f64;
    // Whole days since 2003-01-01 and the day's fraction (UT and TT).
    let days = inp.time.days_since_2000() - DAYS_2000_TO_2003;
    let frac_ut = T::from_u32(inp.time.ms_of_day()) * f(1.0 / MS_PER_DAY as f64);
    let frac_tt = frac_ut + inp.delta_t_s * f(1.0 / 86_400.0);
    // t of the paper (TT, days from JD 2452640), for the periodic terms.
    let t = T::from_i32(days) + frac_tt + f(0.5);

    // 3.2.1 linear increase with the annual oscillation.
    let ang = f(1.72019e-2) * t - f(0.0563);
    let mut l = L_LINEAR.rad(days, frac_tt)
        + f(3.34118e-2) * ang.sin()
        + f(3.488e-4) * (f(2.0) * ang).sin();
    // 3.2.2 Moon perturbation.
    l += wave(3.13e-5, 2.127_730e-1, -0.585, t);
    // 3.2.3 harmonic correction.
    l += wave(1.26e-5, 4.243e-3, 1.46, t)
        + wave(2.35e-5, 1.0727e-2, 0.72, t)
        + wave(2.76e-5, 1.5799e-2, 2.35, t)
        + wave(2.75e-5, 2.1551e-2, -1.98, t)
        + wave(1.26e-5, 3.1490e-2, -0.80, t);
    // 3.2.4 polynomial correction (t₂ = t/1000).
    let t2 = t / f(1000.0);
    l += (((f(-2.30796e-7) * t2 + f(3.7976e-6)) * t2 - f(2.0458e-5)) * t2 + f(3.976e-5)) * t2 * t2;

    // 3.3 nutation, 3.4 obliquity, 3.5 geocentric coordinates (with aberration).
    let nut = f(9.252e-4) * t;
    let dpsi = f(8.33e-5) * (nut - f(1.173)).sin();
    let eps = f(-6.21e-9) * t + f(0.409_086) + f(4.46e-5) * (nut + f(0.397)).sin();
    let lambda = l + T::PI + dpsi - f(9.932e-5);
    let (sl, cl) = lambda.sin_cos();
    let (se, ce) = eps.sin_cos();
    let alpha = (sl * ce).atan2(cl);
    let delta = (sl * se).clamp(-T::ONE, T::ONE).asin();

    // 3.6 local hour angle (on UT), 3.7 parallax corrections.
    let (sp, cp) = inp.site.latitude_deg().to_radians().sin_cos();
    let h = H_LINEAR.rad(days, frac_ut) + f(0.9174) * dpsi + inp.site.longitude_deg().to_radians()
        - alpha;
    let (sh, ch) = h.sin_cos();
    let dalpha = f(-4.26e-5) * cp * sh;
    let delta_t = delta - f(4.26e-5) * (sp - delta * cp);
    let (sdt, cdt) = delta_t.sin_cos();
    let ch_t = ch + dalpha * sh;
    let sh_t = sh - dalpha * ch;

    // 3.8 elevation, refraction (only above −0.01 rad), azimuth.
    let up = sp * sdt + cp * cdt * ch_t;
    let north = cp * sdt - sp * cdt * ch_t;
    let east = -cdt * sh_t;
    let e0 = up.atan2((east * east + north * north).sqrt());
    let de = match &inp.atmosphere {
        Some(atm) if e0 > f(-0.01) => {
            let p_atm = atm.pressure_hpa() / f(1013.25);
            f(0.084_217) * p_atm
                / ((f(273.0) + atm.temperature_c())
                    * (e0 + f(0.003_137_6) / (e0 + f(0.089_186))).tan())
        }
        _ => T::ZERO,
    };
    SunPosition::new(
        (T::FRAC_PI_2 - e0 - de).to_degrees(),
        east.atan2(north).to_degrees(),
        inp.atmosphere.is_some(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algorithm::Algorithm;
    use crate::site::{Options, Site};
    use crate::time::UtcTime;

    /// Grena 2008 written literally as in the paper (JDₜ from its calendar
    /// formula, the full t in one double, asin for the elevation), as an
    /// independent check of the split time.
    fn literal(ymd: (i32, i32, i32), ut_h: f64, dt: f64, lat: f64, lon: f64) -> (f64, f64) {
        let (y, mo, d) = ymd;
        let (yt, mt) = if mo <= 2 { (y - 1, mo + 12) } else { (y, mo) };
        let jd_t = (365.25 * f64::from(yt - 2000)).trunc()
            + (30.6001 * f64::from(mt + 1)).trunc()
            + f64::from(d)
            + ut_h / 24.0
            - 1158.5;
        let t = jd_t + dt / 86400.0;
        let ang = 1.72019e-2 * t - 0.0563;
        let mut l =
            1.740940 + 1.7202768683e-2 * t + 3.34118e-2 * ang.sin() + 3.488e-4 * (2.0 * ang).sin();
        l += 3.13e-5 * (2.127730e-1 * t - 0.585).sin();
        l += 1.26e-5 * (4.243e-3 * t + 1.46).sin()
            + 2.35e-5 * (1.0727e-2 * t + 0.72).sin()
            + 2.76e-5 * (1.5799e-2 * t + 2.35).sin()
            + 2.75e-5 * (2.1551e-2 * t - 1.98).sin()
            + 1.26e-5 * (3.1490e-2 * t - 0.80).sin();
        let t2 = t / 1000.0;
        l += (((-2.30796e-7 * t2 + 3.7976e-6) * t2 - 2.0458e-5) * t2 + 3.976e-5) * t2 * t2;
        let dpsi = 8.33e-5 * (9.252e-4 * t - 1.173).sin();
        let eps = -6.21e-9 * t + 0.409086 + 4.46e-5 * (9.252e-4 * t + 0.397).sin();
        let lambda = l + core::f64::consts::PI + dpsi - 9.932e-5;
        let sl = lambda.sin();
        let ra = (sl * eps.cos()).atan2(lambda.cos());
        let dec = (sl * eps.sin()).asin();
        let h = 6.30038809903 * jd_t + 4.8824623 + dpsi * 0.9174 + lon.to_radians() - ra;
        let (sp, cp) = lat.to_radians().sin_cos();
        let (sh, ch) = h.sin_cos();
        let da = -4.26e-5 * cp * sh;
        let dec_t = dec - 4.26e-5 * (sp - dec * cp);
        let (sdt, cdt) = dec_t.sin_cos();
        let (cht, sht) = (ch + da * sh, sh - da * ch);
        let e0 = (sp * sdt + cp * cdt * cht).asin();
        let az = sht.atan2(cht * sp - sdt / cdt * cp);
        (
            90.0 - e0.to_degrees(),
            (az.to_degrees() + 180.0).rem_euclid(360.0),
        )
    }

    #[test]
    fn matches_the_literal_paper_form() {
        let cases = [
            ((2003, 1, 1), 0.0, 64.3, 45.0, 7.0),
            ((2008, 2, 29), 13.5125, 65.5, -23.5, 150.25),
            ((2015, 7, 4), 5.75, 67.6, 60.1, -110.0),
            ((2022, 12, 31), 23.99, 69.3, 10.0, 179.9),
        ];
        for &((y, mo, d), ut_h, dt, lat, lon) in &cases {
            let ms = (ut_h * 3_600_000.0f64).round() as u32;
            let base = UtcTime::from_ymd_hms(y, mo as u8, d as u8, 0, 0, 0).unwrap();
            let time = UtcTime::from_days_ms(base.days_since_2000(), ms).unwrap();
            let site = Site::new(lat, lon).unwrap();
            let opts = Options {
                delta_t_s: Some(dt),
                ..Options::default()
            };
            let inp = Inputs::new(Algorithm::Grena2008, &time, &site, &opts).unwrap();
            let p = position(&inp);
            let (z, a) = literal((y, mo, d), f64::from(ms) / 3_600_000.0, dt, lat, lon);
            let want = SunPosition::new(z, a, false);
            let dist = p.angular_distance_deg(&want);
            assert!(dist < 1e-8, "{y}-{mo}-{d}: {p:?} vs {want:?}: {dist}");
        }
    }

    /// Refraction (section 3.7 of the paper) against Bennett's formula.
    #[test]
    fn refraction_agrees_with_bennett() {
        crate::refraction::tests::assert_close_to_bennett(Algorithm::Grena2008, 2015);
    }
}
