//! Angle of incidence of beam radiation on a flat surface.
//!
//! One implementation, in terms of the sun's zenith θz and azimuth γs and the
//! surface's slope β and azimuth γ:
//!
//! cos θ = cos θz cos β + sin θz sin β cos(γs − γ)
//!
//! This is eq (1) of Jimoh & Aliyu (2019) (Duffie & Beckman) after
//! substituting the sun's direction from eq (7)/(8), equally its reduced form
//! eq (13) with c1 = cos θz, c2 = sin θz cos γs, c3 = sin θz sin γs
//! (south-referenced azimuths), and eq (8) of Dahli & Cheggaga (2023)
//! (Kalogirou's form of the same expression). `tests/geometry_incidence.rs` evaluates the three published
//! forms from latitude, declination and hour angle and checks they agree with
//! this one.
//!
//! # Example
//!
//! ```
//! use sun_algos::geometry::incidence::{cos_incidence, incidence_deg, Surface};
//! use sun_algos::SunPosition;
//!
//! // NREL SPA report, worked example: the sun at zenith 50.111622°, azimuth
//! // 194.340241°; a surface of slope 30° turned 10° east of south (azimuth
//! // 170°) sees it at I = 25.187000° (nrel_spa_test_vector.json).
//! let sun = SunPosition::new(50.111_622f64, 194.340_241, true);
//! let panel = Surface::from_south_referenced(30.0, -10.0)?;
//! assert!((incidence_deg(&sun, &panel) - 25.187_000).abs() < 1e-5);
//! assert!((cos_incidence(&sun, &panel) - 25.187_000f64.to_radians().cos()).abs() < 1e-7);
//! # Ok::<(), sun_algos::geometry::GeometryError>(())
//! ```

use crate::float::Float;
use crate::position::SunPosition;

use super::GeometryError;

/// Orientation of a flat surface (a panel).
///
/// ```
/// use sun_algos::geometry::incidence::{incidence_deg, Surface};
/// use sun_algos::SunPosition;
///
/// // A panel tilted 30° facing due south, with the sun due south 30° from the
/// // zenith: the beam hits it square (hand geometry).
/// let panel = Surface { slope_deg: 30.0f64, azimuth_deg: 180.0 };
/// assert!(incidence_deg(&SunPosition::new(30.0, 180.0, false), &panel) < 1e-6);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Surface<T> {
    /// Slope β from horizontal in degrees: 0 faces the zenith, 90 is vertical.
    pub slope_deg: T,
    /// Azimuth of the surface normal's horizontal projection, degrees east of
    /// north (`[0, 360)`), the crate's convention. Jimoh & Aliyu (2019)
    /// measure it from south, positive west: see [`Surface::azimuth_from_south_deg`].
    pub azimuth_deg: T,
}

impl<T: Float> Surface<T> {
    /// A surface; errors for NaN/infinite angles. The azimuth is folded into
    /// `[0, 360)`; any slope is accepted (slopes above 90° face downward).
    ///
    /// ```
    /// use sun_algos::geometry::{GeometryError, Surface};
    ///
    /// let s = Surface::new(30.0f64, 370.0)?;
    /// assert_eq!(s.azimuth_deg, 10.0);
    /// assert_eq!(Surface::new(f32::NAN, 0.0), Err(GeometryError::NotFinite));
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn new(slope_deg: T, azimuth_deg: T) -> Result<Self, GeometryError> {
        if !slope_deg.is_finite() || !azimuth_deg.is_finite() {
            return Err(GeometryError::NotFinite);
        }
        Ok(Surface {
            slope_deg,
            azimuth_deg: azimuth_deg.rem_euclid(T::from_f64(360.0)),
        })
    }

    /// A surface in the convention of Jimoh & Aliyu (2019): azimuth from
    /// south, positive toward west.
    ///
    /// ```
    /// use sun_algos::geometry::Surface;
    ///
    /// // NREL SPA worked example: surface azimuth rotation −10° (east of south)
    /// // is 170° east of north.
    /// assert_eq!(Surface::from_south_referenced(30.0f64, -10.0)?.azimuth_deg, 170.0);
    /// // Jimoh & Aliyu (2019): 0 is south, +90 west.
    /// assert_eq!(Surface::from_south_referenced(30.0f64, 90.0)?.azimuth_deg, 270.0);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn from_south_referenced(
        slope_deg: T,
        azimuth_from_south_deg: T,
    ) -> Result<Self, GeometryError> {
        Self::new(
            slope_deg,
            crate::position::azimuth_south_to_north_deg(azimuth_from_south_deg),
        )
    }

    /// Surface azimuth from south, positive toward west, `(−180, 180]`.
    ///
    /// ```
    /// use sun_algos::geometry::Surface;
    ///
    /// assert_eq!(Surface::new(30.0f64, 170.0)?.azimuth_from_south_deg(), -10.0);
    /// assert_eq!(Surface::new(30.0f64, 0.0)?.azimuth_from_south_deg(), 180.0);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn azimuth_from_south_deg(&self) -> T {
        crate::position::azimuth_north_to_south_deg(self.azimuth_deg)
    }

    /// The surface pointed straight at the sun (zero incidence): β = θz,
    /// γ = γs (Jimoh & Aliyu 2019, eq 14, see [`super::optimum::normal_to_sun`]).
    ///
    /// ```
    /// use sun_algos::geometry::{incidence::incidence_deg, Surface};
    /// use sun_algos::SunPosition;
    ///
    /// let sun = SunPosition::new(50.111_622f64, 194.340_241, true);
    /// let s = Surface::facing(&sun);
    /// assert_eq!((s.slope_deg, s.azimuth_deg), (50.111_622, 194.340_241));
    /// assert!(incidence_deg(&sun, &s) < 1e-6);
    /// ```
    pub fn facing(sun: &SunPosition<T>) -> Self {
        Surface {
            slope_deg: sun.zenith_deg,
            azimuth_deg: sun.azimuth_deg,
        }
    }

    /// Unit normal in the local East-North-Up frame.
    ///
    /// ```
    /// use sun_algos::geometry::Surface;
    ///
    /// // Vertical, facing east: the east unit vector; flat: up.
    /// let [e, n, u] = Surface::new(90.0f64, 90.0)?.normal_enu();
    /// assert!((e - 1.0).abs() < 1e-15 && n.abs() < 1e-15 && u.abs() < 1e-15);
    /// assert_eq!(Surface::new(0.0f64, 0.0)?.normal_enu(), [0.0, 0.0, 1.0]);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn normal_enu(&self) -> [T; 3] {
        let (sb, cb) = self.slope_deg.to_radians().sin_cos();
        let (sa, ca) = self.azimuth_deg.to_radians().sin_cos();
        [sb * sa, sb * ca, cb]
    }
}

/// cos θ of the beam on `surface` (Jimoh & Aliyu 2019, eq 1/13; Dahli &
/// Cheggaga 2023, eq 8).
/// Negative when the sun is behind the surface.
///
/// ```
/// use sun_algos::geometry::incidence::{cos_incidence, Surface};
/// use sun_algos::SunPosition;
///
/// // NREL SPA report, worked example: the sun at zenith 50.111622°, azimuth
/// // 194.340241°; a surface of slope 30° turned 10° east of south (azimuth
/// // 170°) sees it at I = 25.187000° (nrel_spa_test_vector.json).
/// let sun = SunPosition::new(50.111_622f64, 194.340_241, true);
/// let c = cos_incidence(&sun, &Surface::new(30.0, 170.0)?);
/// assert!((c - 25.187_000f64.to_radians().cos()).abs() < 1e-7);
/// // Sun behind a vertical wall: negative.
/// let wall = Surface::new(90.0f64, 0.0)?;
/// assert!(cos_incidence(&sun, &wall) < 0.0);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
pub fn cos_incidence<T: Float>(sun: &SunPosition<T>, surface: &Surface<T>) -> T {
    let (sz, cz) = sun.zenith_deg.to_radians().sin_cos();
    let (sb, cb) = surface.slope_deg.to_radians().sin_cos();
    let d = (sun.azimuth_deg - surface.azimuth_deg).to_radians();
    let c = cz * cb + sz * sb * d.cos();
    c.clamp(-T::ONE, T::ONE)
}

/// Angle of incidence θ in degrees, `[0, 180]`.
///
/// Computed as the angle between the sun vector and the surface normal with
/// `atan2(|a × b|, a · b)`, which keeps precision near 0° where `acos` of the
/// cosine loses it (at 0.01°, acos of an f32 cosine is off by ~0.02°).
///
/// ```
/// use sun_algos::geometry::incidence::{incidence_deg, Surface};
/// use sun_algos::SunPosition;
///
/// // NREL SPA report, worked example: the sun at zenith 50.111622°, azimuth
/// // 194.340241°; a surface of slope 30° turned 10° east of south (azimuth
/// // 170°) sees it at I = 25.187000° (nrel_spa_test_vector.json).
/// let sun = SunPosition::new(50.111_622f64, 194.340_241, true);
/// assert!((incidence_deg(&sun, &Surface::new(30.0, 170.0)?) - 25.187_000).abs() < 1e-5);
/// // pvlib 0.16.1's aoi(30, 170, 50.111622, 194.340241) is 25.187000 as well;
/// // in f32 the same to 1e-4°.
/// let sun32 = SunPosition::new(50.111_622f32, 194.340_241, true);
/// assert!((incidence_deg(&sun32, &Surface::new(30.0, 170.0)?) - 25.187).abs() < 1e-4);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
pub fn incidence_deg<T: Float>(sun: &SunPosition<T>, surface: &Surface<T>) -> T {
    crate::position::angle_between_deg(&sun.unit_vector_enu(), &surface.normal_enu())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn horizontal_surface_sees_the_zenith_angle() {
        let sun = SunPosition::new(37.0f64, 123.0, false);
        let flat = Surface::new(0.0, 200.0).unwrap();
        assert!((incidence_deg(&sun, &flat) - 37.0).abs() < 1e-9);
        assert!((cos_incidence(&sun, &flat) - 37.0f64.to_radians().cos()).abs() < 1e-12);
    }

    #[test]
    fn vertical_wall_facing_the_sun_azimuth() {
        // Sun on the horizon due east; a wall facing east receives it at 0°,
        // a wall facing south at 90° (hand geometry).
        let sun = SunPosition::new(90.0f64, 90.0, false);
        let east = Surface::new(90.0, 90.0).unwrap();
        let south = Surface::new(90.0, 180.0).unwrap();
        assert!(incidence_deg(&sun, &east).abs() < 1e-9);
        assert!((incidence_deg(&sun, &south) - 90.0).abs() < 1e-9);
    }

    #[test]
    fn nan_surface_is_an_error() {
        assert_eq!(Surface::new(f32::NAN, 0.0), Err(GeometryError::NotFinite));
    }
}
