//! Michalsky 1988: the Astronomical Almanac's algorithm for approximate
//! solar position (1950–2050), with its corrigenda.
//!
//! Source: J. J. Michalsky, "The Astronomical Almanac's algorithm for
//! approximate solar position (1950–2050)", Solar Energy 40(3) 227–235,
//! 1988; errata Solar Energy 41(1) 113 (1988) and 43(5) 323 (1989);
//! J. W. Spencer, "Comments on …", Solar Energy 42(4) 353 (1989).
//! Called "AA" by Chowdhury et al. (2019).
//!
//! With `n` the days since JD 2451545.0 and `h` the UT hour (degrees):
//! mean longitude `L = 280.460 + 0.9856474·n`, mean anomaly
//! `g = 357.528 + 0.9856003·n`, ecliptic longitude
//! `λ = L + 1.915 sin g + 0.020 sin 2g`, obliquity `ε = 23.439 − 4e−7·n`,
//! right ascension and declination from λ and ε, `gmst = 6.697375 +
//! 0.0657098242·n + h` hours, local mean sidereal time `gmst + lon/15`,
//! hour angle `lmst·15 − ra`, elevation `asin(sin δ sin φ + cos δ cos φ cos H)`.
//!
//! Corrigenda applied:
//! - **Azimuth (Spencer 1989).** Michalsky's quadrant logic (with the
//!   "critical elevation") fails outside mid-northern latitudes. Spencer's
//!   correction takes `az = asin(−cos δ sin H / cos e)` and puts it in the
//!   right quadrant by the sign of `sin δ − sin e sin φ` (= `cos az ·
//!   cos e · cos φ`). We use the equivalent, everywhere-correct
//!   `az = atan2(−cos δ sin H, sin δ cos φ − cos δ cos H sin φ)` (see
//!   [`crate::psa`]'s `horizontal`).
//! - **Century leap years.** Michalsky's Julian Day
//!   (`32916.5 + 365·(y − 1949) + int((y − 1949)/4) + day + h/24`) counts
//!   every fourth year as leap, which is wrong in 1900 and 2100; we take
//!   the day count from [`crate::UtcTime`], which follows the Gregorian rules.
//!
//! **Time scale.** The algorithm is driven by UT; ΔT is not used (its fits
//! absorb TT − UT over 1950–2050).
//!
//! **Parallax.** Michalsky has none; the sun's horizontal parallax (up to
//! 0.0024° at the horizon) makes his position geocentric. The reference data
//! and a tracker want the topocentric direction, so we add the PSA parallax
//! term `(R⊕/AU)·sin θz` ([`crate::psa::PARALLAX_RAD`]). Measured max
//! (mean) error, sun above the horizon, f64 (f32 the same to 0.00002°):
//! sun_1999_2022 0.0083° (0.0029°), sun_2020_2050 0.0103° (0.0033°); without
//! the parallax term they would be 0.0096° (0.0034°) and 0.0118° (0.0037°),
//! the latter matching solposx's published 0.0118° for Michalsky.
//!
//! **Refraction.** When an atmosphere is given, Michalsky's own formula is
//! used ([`refraction_deg`]), scaled by pressure and temperature.
//!
//! **Precision.** As in [`crate::psa`]: whole days are reduced exactly in
//! fixed point, only the part of a day is multiplied in `T`.
//!
//! # Example
//!
//! ```
//! use sun_algos::{Algorithm, Options, Site, SunPosition, UtcTime};
//!
//! // tests/data/sun_1999_2022.csv (JPL DE421 through skyfield):
//! // 2006-03-01T13:45:38Z, 34.76767°, −45.58589° → zenith 47.2182225°,
//! // azimuth 149.2139858°. Michalsky's declared accuracy is 0.01°.
//! let t: UtcTime = "2006-03-01T13:45:38Z".parse()?;
//! let truth = SunPosition::new(47.218_222_5f32, 149.213_985_8, false);
//! let p = Algorithm::Michalsky.position(&t, &Site::new(34.76767f32, -45.58589)?, &Options::default())?;
//! assert!(p.angular_distance_deg(&truth) < 0.01);
//! # Ok::<(), sun_algos::Error>(())
//! ```

use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;
use crate::psa::{horizontal, turns_per_day_fixed, turns_to_rad, whole_day_turns, PARALLAX_RAD};
use crate::site::Atmosphere;

/// Mean longitude at J2000.0 and its daily rate, degrees.
const MEAN_LONGITUDE_DEG: [f64; 2] = [280.460, 0.985_647_4];
/// Mean anomaly at J2000.0 and its daily rate, degrees.
const MEAN_ANOMALY_DEG: [f64; 2] = [357.528, 0.985_600_3];
/// Greenwich mean sidereal time at 0 h UT of J2000.0 and its daily rate, hours.
const GMST_H: [f64; 2] = [6.697_375, 0.065_709_824_2];

/// Topocentric sun position by Michalsky 1988 (with corrigenda).
pub(crate) fn position<T: Float>(inp: &Inputs<'_, T>) -> SunPosition<T> {
    let days = inp.time.days_since_2000();
    // n = days + frac; frac = hour/24 − 0.5.
    let frac = inp.time.day_fraction::<T>() - T::from_f64(0.5);
    let n = T::from_i32(days) + frac;

    let mean_longitude = daily_angle_rad(MEAN_LONGITUDE_DEG, 360.0, days, frac);
    let mean_anomaly = daily_angle_rad(MEAN_ANOMALY_DEG, 360.0, days, frac);
    let (sin_g, cos_g) = mean_anomaly.sin_cos();
    let ecliptic_longitude = mean_longitude
        + T::from_f64(1.915f64.to_radians()) * sin_g
        + T::from_f64(0.020f64.to_radians()) * (T::from_f64(2.0) * sin_g * cos_g);
    let obliquity = T::from_f64(23.439f64.to_radians()) - T::from_f64(4e-7f64.to_radians()) * n;

    // ra = atan2(cos ε sin λ, cos λ), δ = asin(sin ε sin λ): kept as the
    // equatorial unit vector (x = cos δ cos ra, y = cos δ sin ra).
    let (sin_l, cos_l) = ecliptic_longitude.sin_cos();
    let (sin_eps, cos_eps) = obliquity.sin_cos();
    let x = cos_l;
    let y = cos_eps * sin_l;
    let sin_dec = sin_eps * sin_l;

    // lmst = gmst + lon/15 (hours); H = lmst·15° − ra.
    let gmst_turns = daily_turns(GMST_H, 24.0, days, frac) + inp.time.day_fraction::<T>();
    let lmst = turns_to_rad(gmst_turns) + inp.site.longitude_deg().to_radians();
    let (sin_t, cos_t) = lmst.sin_cos();
    let cos_dec_cos_h = x * cos_t + y * sin_t;
    let cos_dec_sin_h = x * sin_t - y * cos_t;

    let (zenith, azimuth, sin_zenith) = horizontal(sin_dec, cos_dec_cos_h, cos_dec_sin_h, inp.site);
    let zenith = zenith + T::from_f64(PARALLAX_RAD) * sin_zenith;
    let geometric = SunPosition::new(zenith.to_degrees(), azimuth.to_degrees(), false);
    match inp.atmosphere {
        None => geometric,
        Some(atm) => {
            let e = geometric.elevation_deg();
            let e = e + refraction_deg(e, &atm);
            SunPosition::new(T::from_f64(90.0) - e, geometric.azimuth_deg, true)
        }
    }
}

/// `a[0] + a[1]·n` in units of which `per_turn` make a turn, reduced and
/// returned in radians.
#[inline(always)]
fn daily_angle_rad<T: Float>(a: [f64; 2], per_turn: f64, days: i32, frac: T) -> T {
    turns_to_rad(daily_turns(a, per_turn, days, frac))
}

/// `a[0] + a[1]·n` in turns (not reduced; within a few turns): whole days
/// exactly in fixed point, the part of a day in `T`.
#[inline(always)]
fn daily_turns<T: Float>(a: [f64; 2], per_turn: f64, days: i32, frac: T) -> T {
    let rate_turns = a[1] / per_turn;
    T::from_f64(a[0] / per_turn)
        + whole_day_turns::<T>(turns_per_day_fixed(rate_turns), days)
        + T::from_f64(rate_turns) * frac
}

/// Michalsky's refraction in degrees for the true elevation `e_deg`:
/// `3.51561·(0.1594 + 0.0196 e + 0.00002 e²) / (1 + 0.505 e + 0.0845 e²)`
/// above −0.56°, and 0.56° below (Michalsky 1988). His factor 3.51561 is
/// `1013.2 mb / 288.2 K`; we use `P / (273.2 + T)` for the given atmosphere.
///
/// ```
/// use sun_algos::michalsky::refraction_deg;
/// use sun_algos::Atmosphere;
///
/// // Michalsky's own conditions, 1013.2 mb and 15 °C (his factor 3.51561):
/// // on the horizon 3.51561 × 0.1594 = 0.56038° (hand evaluation of his
/// // formula); 0.56° below −0.56°.
/// let atm = Atmosphere::new(1013.2f64, 15.0)?;
/// assert!((refraction_deg(0.0, &atm) - 0.560_38).abs() < 1e-5);
/// assert_eq!(refraction_deg(-5.0, &atm), 0.56);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn refraction_deg<T: Float>(e_deg: T, atm: &Atmosphere<T>) -> T {
    if e_deg < T::from_f64(-0.56) {
        return T::from_f64(0.56);
    }
    let scale = atm.pressure_hpa() / (T::from_f64(273.2) + atm.temperature_c());
    scale
        * (T::from_f64(0.1594)
            + T::from_f64(0.0196) * e_deg
            + T::from_f64(0.000_02) * e_deg * e_deg)
        / (T::ONE + T::from_f64(0.505) * e_deg + T::from_f64(0.0845) * e_deg * e_deg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refraction_matches_the_paper_at_standard_conditions() {
        // 1013.2 mb and 15 °C give Michalsky's factor 3.51561: at e = 0 the
        // refraction is 3.51561 × 0.1594 = 0.56038° (hand computation).
        let atm = Atmosphere::new(1013.2f64, 15.0).unwrap();
        assert!((refraction_deg(0.0, &atm) - 0.560_388).abs() < 1e-5);
        // e = 10°: 3.51561 × 0.3574 / 14.5 = 0.086654° (hand computation).
        assert!((refraction_deg(10.0, &atm) - 0.086_654).abs() < 1e-5);
        assert_eq!(refraction_deg(-5.0, &atm), 0.56);
    }
}
