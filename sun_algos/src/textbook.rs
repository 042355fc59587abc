//! The textbook method: Cooper's declination, Spencer's equation of time and
//! the hour angle from solar time, as in the tracker papers.
//!
//! Sources: Jimoh & Aliyu (2019), eqs. 2–7 (after Duffie & Beckman; Spencer
//! 1971, "Fourier series representation of the position of the sun"), and
//! Dahli & Cheggaga (2023), eqs. 1–7.
//!
//! - Declination (Cooper 1969; Jimoh & Aliyu 2019, eq. 2):
//!   `δ = 23.45° · sin(360°/365 · (284 + n))`, `n` the day of the year
//!   (1 on 1 January). Jimoh & Aliyu print 365.25 in the ratio; Cooper's
//!   original and Dahli & Cheggaga's eq. 4 use 365, which we follow.
//! - Equation of time (Spencer 1971; Jimoh & Aliyu 2019, eqs. 5–6),
//!   minutes:
//!   `E = 229.2·(0.000075 + 0.001868 cos B − 0.032077 sin B − 0.014615 cos 2B
//!   − 0.04089 sin 2B)`, `B = 360°·(n − 1)/365`.
//! - Solar time (Jimoh & Aliyu 2019, eq. 4, with UTC as the standard time
//!   of longitude 0): `ST = UTC + lon/15° + E/60` hours; hour angle
//!   `ω = 15°·(ST − 12)` (eq. 3).
//! - Zenith `cos θz = sin δ sin φ + cos δ cos φ cos ω` (eq. 7); azimuth from
//!   eq. 8 with the sign of ω, computed as in [`crate::psa`]'s `horizontal`
//!   (same result, no sign ambiguity).
//!
//! `n` is the whole day number, as in the papers, so the declination steps
//! once a day. Accuracy: about 1° (max 1.38°, mean 0.44° on sun_2020_2050;
//! see `tests/reference.rs`) — enough for a coarse tracker, far from the
//! others. No parallax, no ΔT. Refraction, when asked for, is
//! [`crate::refraction::apply`].
//!
//! # Example
//!
//! ```
//! use sun_algos::{Algorithm, Options, Site, SunPosition, UtcTime};
//!
//! // tests/data/sun_1999_2022.csv (JPL DE421 through skyfield):
//! // 2006-03-01T13:45:38Z, 34.76767°, −45.58589° → zenith 47.2182225°,
//! // azimuth 149.2139858°. About 1° (1.38° at most over sun_2020_2050).
//! let t: UtcTime = "2006-03-01T13:45:38Z".parse()?;
//! let p = Algorithm::Textbook.position(&t, &Site::new(34.76767f64, -45.58589)?, &Options::default())?;
//! assert!(p.angular_distance_deg(&SunPosition::new(47.218_222_5, 149.213_985_8, false)) < 1.4);
//! # Ok::<(), sun_algos::Error>(())
//! ```

use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;
use crate::psa::horizontal;

/// Cooper's declination in degrees for day of year `n` (Jimoh & Aliyu 2019, eq. 2).
///
/// ```
/// use sun_algos::textbook::declination_deg;
///
/// // pvlib 0.16.1's declination_cooper69 (the same formula, computed apart):
/// // 23.449783° on day 172, −23.449783° on day 355, 0 on day 81.
/// assert!((declination_deg::<f64>(172) - 23.449_783).abs() < 1e-6);
/// assert!((declination_deg::<f64>(355) + 23.449_783).abs() < 1e-6);
/// assert!(declination_deg::<f32>(81).abs() < 1e-5);
/// ```
pub fn declination_deg<T: Float>(day_of_year: u16) -> T {
    let n = T::from_u32(u32::from(day_of_year));
    let arg = (T::from_f64(360.0 / 365.0) * (T::from_f64(284.0) + n)).to_radians();
    T::from_f64(23.45) * arg.sin()
}

/// Spencer's equation of time in minutes for day of year `n` (Jimoh & Aliyu
/// 2019, eqs. 5–6; positive when the sundial is ahead of mean time).
///
/// ```
/// use sun_algos::textbook::equation_of_time_min;
///
/// // pvlib 0.16.1's equation_of_time_spencer71: +16.350 min on day 307,
/// // −14.215 min on day 42. Its constants differ slightly (1440/2π for
/// // 229.2, 0.040849 for 0.04089, 0.0000075 for 0.000075): 0.03 min apart.
/// assert!((equation_of_time_min::<f64>(307) - 16.350).abs() < 0.05);
/// assert!((equation_of_time_min::<f64>(42) + 14.215).abs() < 0.05);
/// ```
pub fn equation_of_time_min<T: Float>(day_of_year: u16) -> T {
    let n = T::from_u32(u32::from(day_of_year));
    let b = (T::from_f64(360.0 / 365.0) * (n - T::ONE)).to_radians();
    let (sb, cb) = b.sin_cos();
    let (s2b, c2b) = (T::from_f64(2.0) * b).sin_cos();
    T::from_f64(229.2)
        * (T::from_f64(0.000_075) + T::from_f64(0.001_868) * cb
            - T::from_f64(0.032_077) * sb
            - T::from_f64(0.014_615) * c2b
            - T::from_f64(0.040_89) * s2b)
}

/// Topocentric (no parallax) sun position by the textbook method.
pub(crate) fn position<T: Float>(inp: &Inputs<'_, T>) -> SunPosition<T> {
    let n = inp.time.day_of_year();
    let dec = declination_deg::<T>(n).to_radians();
    let solar_time_h = inp.time.hours::<T>()
        + inp.site.longitude_deg() / T::from_f64(15.0)
        + equation_of_time_min::<T>(n) / T::from_f64(60.0);
    let omega = (T::from_f64(15.0) * (solar_time_h - T::from_f64(12.0))).to_radians();
    let (sin_dec, cos_dec) = dec.sin_cos();
    let (sin_w, cos_w) = omega.sin_cos();
    let (zenith, azimuth, _) = horizontal(sin_dec, cos_dec * cos_w, cos_dec * sin_w, inp.site);
    let geometric = SunPosition::new(zenith.to_degrees(), azimuth.to_degrees(), false);
    crate::refraction::apply(geometric, inp.atmosphere.as_ref())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn declination_at_solstices_and_equinox() {
        // n = 172 (21 June): 360/365·456 = 449.75° → sin = 0.99996 → 23.45°.
        assert!((declination_deg::<f64>(172) - 23.449).abs() < 0.01);
        // n = 355 (21 December): −23.45° within 0.01°.
        assert!((declination_deg::<f64>(355) + 23.449).abs() < 0.01);
        // n = 81 (22 March): 360/365·365 = 360° → 0.
        assert!(declination_deg::<f64>(81).abs() < 1e-9);
    }

    #[test]
    fn equation_of_time_extremes() {
        // Early November (n = 307) ≈ +16.4 min, mid February (n = 42)
        // ≈ −14.3 min (Duffie & Beckman, Fig. 1.5.1).
        let nov: f64 = equation_of_time_min(307);
        let feb: f64 = equation_of_time_min(42);
        assert!((nov - 16.4).abs() < 0.3, "{nov}");
        assert!((feb + 14.3).abs() < 0.3, "{feb}");
    }
}
