//! Atmospheric refraction shared by the algorithms that have none of their own.
//!
//! # Example
//!
//! ```
//! use sun_algos::{refraction, Atmosphere, SunPosition};
//!
//! // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
//! // true elevation 39.872046° at 820 hPa and 11 °C is seen at 39.888378°.
//! let atm = Atmosphere::new(820.0f64, 11.0)?;
//! let geometric = SunPosition::new(90.0 - 39.872_046, 194.340_241, false);
//! let apparent = refraction::apply(geometric, Some(&atm));
//! assert!((apparent.elevation_deg() - 39.888_378).abs() < 1e-6);
//! # Ok::<(), sun_algos::Error>(())
//! ```

use crate::float::Float;
use crate::position::SunPosition;
use crate::site::Atmosphere;

/// The sun's semi-diameter plus the refraction at the horizon in degrees
/// (NREL SPA report, eq. 43: 0.26667° + 0.5667°): below this the sun is set
/// and no refraction is applied.
///
/// ```
/// use sun_algos::refraction::SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG;
///
/// // NREL SPA eq. 43: the sun's radius 0.26667° and 0.5667° of refraction at
/// // the horizon (nrel_spa_test_vector.json: atmospheric_refraction_at_horizon).
/// assert!((SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG - 0.83337).abs() < 1e-12);
/// ```
pub const SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG: f64 = 0.26667 + 0.5667;

/// Refraction correction Δe in degrees for a true (geometric) elevation
/// `e0_deg` (Reda & Andreas 2004, NREL SPA eq. 42, Bennett's formula scaled
/// by pressure and temperature). Zero when the sun is below the horizon
/// limit of eq. 43.
///
/// ```
/// use sun_algos::refraction::refraction_deg;
/// use sun_algos::Atmosphere;
///
/// // NREL SPA worked example: Δe = 0.016332° for e0 = 39.872046°, 820 hPa, 11 °C.
/// let atm = Atmosphere::new(820.0f64, 11.0)?;
/// assert!((refraction_deg(39.872_046, &atm) - 0.016_332).abs() < 1e-6);
/// // Below the horizon limit of eq. 43 (−0.83337°): none.
/// assert_eq!(refraction_deg(-1.0, &atm), 0.0);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn refraction_deg<T: Float>(e0_deg: T, atmosphere: &Atmosphere<T>) -> T {
    if e0_deg < -T::from_f64(SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG) {
        return T::ZERO;
    }
    let arg = (e0_deg + T::from_f64(10.3) / (e0_deg + T::from_f64(5.11))).to_radians();
    (atmosphere.pressure_hpa() / T::from_f64(1010.0))
        * (T::from_f64(283.0) / (T::from_f64(273.0) + atmosphere.temperature_c()))
        * T::from_f64(1.02)
        / (T::from_f64(60.0) * arg.tan())
}

/// Applies [`refraction_deg`] to a geometric position when an atmosphere is
/// given; returns it unchanged otherwise.
///
/// ```
/// use sun_algos::refraction::apply;
/// use sun_algos::{Atmosphere, SunPosition};
///
/// // NREL SPA worked example: geometric zenith 90° − 39.872046° becomes the
/// // apparent 50.111622°.
/// let atm = Atmosphere::new(820.0f64, 11.0)?;
/// let p = apply(SunPosition::new(90.0 - 39.872_046, 194.340_241, false), Some(&atm));
/// assert!(p.refracted && (p.zenith_deg - 50.111_622).abs() < 1e-6);
/// // Without an atmosphere: unchanged.
/// let g = SunPosition::new(50.0f64, 194.0, false);
/// assert_eq!(apply(g, None), g);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn apply<T: Float>(
    geometric: SunPosition<T>,
    atmosphere: Option<&Atmosphere<T>>,
) -> SunPosition<T> {
    match atmosphere {
        None => geometric,
        Some(atm) => {
            let e0 = geometric.elevation_deg();
            let e = e0 + refraction_deg(e0, atm);
            SunPosition::new(T::from_f64(90.0) - e, geometric.azimuth_deg, true)
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::{Algorithm, Options, Site, UtcTime};

    /// An algorithm's own refraction against an independent formula,
    /// Bennett's (1982) R = cot(h + 7.31/(h + 4.4)) arc minutes at 1010 hPa
    /// and 10 °C, scaled by P/1010 · 283/(273 + T): within 4 % above 5° of
    /// elevation, and none applied below −1°. Sampled over 1 June of `year`.
    pub(crate) fn assert_close_to_bennett(algorithm: Algorithm, year: i32) {
        let site = Site::new(45.0f64, 0.0).unwrap();
        let atm = Atmosphere::new(950.0, 25.0).unwrap();
        let geo = Options {
            delta_t_s: Some(69.0),
            ..Options::default()
        };
        let app = Options {
            atmosphere: Some(atm),
            ..geo
        };
        let mut checked = 0;
        for minute in (0..1440).step_by(7) {
            let t = UtcTime::from_ymd_hms(year, 6, 1, (minute / 60) as u8, (minute % 60) as u8, 0)
                .unwrap();
            let g = algorithm.position(&t, &site, &geo).unwrap();
            let a = algorithm.position(&t, &site, &app).unwrap();
            assert!(a.refracted && !g.refracted);
            let h = g.elevation_deg();
            let got = g.zenith_deg - a.zenith_deg;
            if h < -1.0 {
                assert_eq!(got, 0.0);
            } else if h > 5.0 {
                let bennett_arcmin = 1.0 / (h + 7.31 / (h + 4.4)).to_radians().tan();
                let want = bennett_arcmin / 60.0 * (950.0 / 1010.0) * (283.0 / 298.0);
                assert!((got - want).abs() < 0.04 * want, "h {h}: {got} vs {want}");
                checked += 1;
            }
        }
        assert!(checked > 50);
    }

    #[test]
    fn nrel_worked_example_refraction() {
        // NREL SPA report worked example: e0 = 39.872046°, 820 hPa, 11 °C
        // → Δe = 0.016332° (shared/reference/nrel_spa_test_vector.json).
        let atm = Atmosphere::new(820.0f64, 11.0).unwrap();
        let d = refraction_deg(39.872_046, &atm);
        assert!((d - 0.016_332).abs() < 1e-6, "{d}");
    }

    #[test]
    fn no_refraction_below_the_horizon_limit() {
        let atm = Atmosphere::standard();
        assert_eq!(refraction_deg(-5.0f64, &atm), 0.0);
        assert!(refraction_deg(0.0f64, &atm) > 0.4);
    }
}
