//! The textbook sun model of Jimoh & Aliyu (2019, eq 2–8), used by the
//! simple sunrise/sunset model of [`super::events`] and for local solar time.
//!
//! Accuracy is that of Cooper's declination and Spencer's equation of time
//! (a few tenths of a degree, about a minute); the precise algorithms are in
//! [`crate::Algorithm`].
//!
//! # Example
//!
//! ```
//! use sun_algos::geometry::simple;
//! use sun_algos::{SunPosition, UtcTime};
//!
//! // tests/data/sun_1999_2022.csv (JPL DE421 through skyfield):
//! // 2006-03-01T13:45:38Z, 34.76767°, −45.58589° → zenith 47.2182225°,
//! // azimuth 149.2139858°. Jimoh & Aliyu's model is about 1° off.
//! let t: UtcTime = "2006-03-01T13:45:38Z".parse()?;
//! let p = simple::position(&t, 34.76767f64, -45.58589);
//! assert!(p.angular_distance_deg(&SunPosition::new(47.218_222_5, 149.213_985_8, false)) < 1.4);
//! # Ok::<(), sun_algos::Error>(())
//! ```

use crate::float::Float;
use crate::position::SunPosition;
use crate::time::UtcTime;

/// Declination δ in degrees for day of year `n` (1 on 1 January): Jimoh &
/// Aliyu (2019), eq (2), δ = 23.45° sin[(360/365.25)(284 + n)] as printed
/// there (Cooper's original divides by 365).
///
/// ```
/// use sun_algos::geometry::simple::declination_deg;
///
/// // Hand evaluation of Jimoh & Aliyu's eq. 2 for 21 June (n = 172):
/// // 23.45 · sin(360/365.25 · 456°) = 23.448902°.
/// assert!((declination_deg::<f64>(172) - 23.448_902).abs() < 1e-6);
/// assert!(declination_deg::<f32>(172) > 23.44);
/// ```
pub fn declination_deg<T: Float>(day_of_year: u16) -> T {
    let arg = T::from_f64(360.0 / 365.25) * T::from_u32(284 + u32::from(day_of_year));
    T::from_f64(23.45) * arg.to_radians().sin()
}

/// Equation of time in hours (apparent minus mean solar time): Jimoh
/// & Aliyu (2019), eq (5) (Spencer 1971), with B from eq (6).
///
/// ```
/// use sun_algos::geometry::simple::equation_of_time_h;
///
/// // pvlib 0.16.1's equation_of_time_spencer71 on day 307: +16.350 min (its
/// // constants differ slightly, 0.03 min).
/// assert!((equation_of_time_h::<f64>(307) * 60.0 - 16.350).abs() < 0.05);
/// ```
pub fn equation_of_time_h<T: Float>(day_of_year: u16) -> T {
    let n = T::from_u32(u32::from(day_of_year));
    let b = (T::from_f64(360.0) * (n - T::ONE) / T::from_f64(365.0)).to_radians();
    let (s1, c1) = b.sin_cos();
    let (s2, c2) = (b + b).sin_cos();
    T::from_f64(229.2 / 60.0)
        * (T::from_f64(0.000_075) + T::from_f64(0.001_868) * c1
            - T::from_f64(0.032_077) * s1
            - T::from_f64(0.014_615) * c2
            - T::from_f64(0.040_89) * s2)
}

/// Local apparent solar time in hours (may leave 0…24) of a UTC instant at
/// `longitude_deg` (east positive): Jimoh & Aliyu (2019), eq (4), with the
/// standard meridian at Greenwich, ST = UTC + λ/15 + ET. (The paper writes
/// −4(ψst − ψa) minutes with west longitudes positive; it is the same.)
///
/// ```
/// use sun_algos::geometry::simple::solar_time_h;
/// use sun_algos::UtcTime;
///
/// // Noon UTC on 3 November (day 307) at Greenwich: 12 h plus the equation of
/// // time, +16.350 min by pvlib 0.16.1's equation_of_time_spencer71.
/// let t: UtcTime = "2026-11-03T12:00:00Z".parse()?;
/// assert!((solar_time_h(&t, 0.0f64) - (12.0 + 16.350 / 60.0)).abs() < 0.05 / 60.0);
/// // 15° east: one hour later in solar time.
/// assert!((solar_time_h(&t, 15.0f64) - solar_time_h(&t, 0.0) - 1.0).abs() < 1e-12);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn solar_time_h<T: Float>(time: &UtcTime, longitude_deg: T) -> T {
    time.hours::<T>() + longitude_deg / T::from_f64(15.0) + equation_of_time_h(time.day_of_year())
}

/// Hour angle ω in degrees for solar time `st_h`: Jimoh & Aliyu (2019), eq (3).
///
/// ```
/// use sun_algos::geometry::simple::hour_angle_deg;
///
/// // Jimoh & Aliyu (2019), eq. 3: 15° per hour from solar noon, negative before.
/// assert_eq!(hour_angle_deg(13.5f64), 22.5);
/// assert_eq!(hour_angle_deg(6.0f32), -90.0);
/// ```
pub fn hour_angle_deg<T: Float>(solar_time_h: T) -> T {
    T::from_f64(15.0) * (solar_time_h - T::from_f64(12.0))
}

/// Zenith and azimuth from latitude φ, declination δ and hour angle ω
/// (degrees): Jimoh & Aliyu (2019), eq (7) for the zenith and eq (8b) for
/// the azimuth, with the sign of ω as the paper prescribes, written as one
/// `atan2` so it never divides by sin θz.
///
/// ```
/// use sun_algos::geometry::simple::position_from_angles;
///
/// // pvlib 0.16.1's solar_zenith_analytical and solar_azimuth_analytical for
/// // latitude 40°, declination 10°, hour angle 30°: zenith 40.097092°,
/// // azimuth 229.862675°.
/// let p = position_from_angles(40.0f64, 10.0, 30.0);
/// assert!((p.zenith_deg - 40.097_092).abs() < 1e-6);
/// assert!((p.azimuth_deg - 229.862_675).abs() < 1e-6);
/// // Solar noon: zenith |φ − δ| (eq. 7 with ω = 0).
/// assert!((position_from_angles(12.0f64, -10.0, 0.0).zenith_deg - 22.0).abs() < 1e-9);
/// ```
pub fn position_from_angles<T: Float>(
    latitude_deg: T,
    declination_deg: T,
    hour_angle_deg: T,
) -> SunPosition<T> {
    let (sp, cp) = latitude_deg.to_radians().sin_cos();
    let (sd, cd) = declination_deg.to_radians().sin_cos();
    let (sw, cw) = hour_angle_deg.to_radians().sin_cos();
    let cos_z = (sd * sp + cd * cw * cp).clamp(-T::ONE, T::ONE);
    // Horizontal components: toward south (eq 8b numerator) and toward west.
    let south = cd * sp * cw - sd * cp;
    let west = cd * sw;
    let sin_z = (south * south + west * west).sqrt();
    let zenith = sin_z.atan2(cos_z).to_degrees();
    let az_from_south = west.atan2(south).to_degrees();
    SunPosition::new(zenith, az_from_south + T::from_f64(180.0), false)
}

/// Jimoh & Aliyu's whole simple model at a UTC instant (eq 2–8).
///
/// ```
/// use sun_algos::geometry::simple;
/// use sun_algos::{SunPosition, UtcTime};
///
/// // tests/data/sun_1999_2022.csv (JPL DE421 through skyfield):
/// // 2006-03-01T13:45:38Z, 34.76767°, −45.58589° → zenith 47.2182225°,
/// // azimuth 149.2139858°: within about 1°, in f32 as in f64.
/// let t: UtcTime = "2006-03-01T13:45:38Z".parse()?;
/// let p = simple::position(&t, 34.76767f32, -45.58589);
/// assert!(p.angular_distance_deg(&SunPosition::new(47.218_222_5, 149.213_985_8, false)) < 1.4);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn position<T: Float>(time: &UtcTime, latitude_deg: T, longitude_deg: T) -> SunPosition<T> {
    let delta = declination_deg::<T>(time.day_of_year());
    let omega = hour_angle_deg(solar_time_h(time, longitude_deg));
    position_from_angles(latitude_deg, delta, omega)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn declination_at_the_solstices() {
        // Day 172 (21 June): 23.45 sin(360/365.25 × 456) = 23.45 sin(449.4°)
        // = 23.45 × 0.99995 ≈ 23.45° (hand calculation).
        let d: f64 = declination_deg(172);
        assert!((d - 23.45).abs() < 0.01, "{d}");
        let d: f64 = declination_deg(355);
        assert!((d + 23.45).abs() < 0.05, "{d}");
    }

    #[test]
    fn equation_of_time_early_november() {
        // Spencer's EoT peaks near +16.4 min around 3 November (day 307);
        // hand evaluation of eq 5 at n = 307 gives +16.4 min.
        let e: f64 = equation_of_time_h(307);
        assert!((e * 60.0 - 16.4).abs() < 0.2, "{}", e * 60.0);
    }

    #[test]
    fn azimuth_signs_follow_the_hour_angle() {
        let am = position_from_angles(12.0f64, -10.0, -30.0);
        let pm = position_from_angles(12.0f64, -10.0, 30.0);
        assert!(am.azimuth_from_south_deg() < 0.0 && pm.azimuth_from_south_deg() > 0.0);
        assert!((am.zenith_deg - pm.zenith_deg).abs() < 1e-9);
        // Solar noon: zenith = |φ − δ| (eq 7 with ω = 0).
        let noon = position_from_angles(12.0f64, -10.0, 0.0);
        assert!((noon.zenith_deg - 22.0).abs() < 1e-9);
    }
}
