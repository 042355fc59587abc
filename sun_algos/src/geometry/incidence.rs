//! Angle of incidence of beam radiation on a flat surface.
//!
//! One implementation, in terms of the sun's zenith θz and azimuth γs and the
//! surface's slope β and azimuth γ:
//!
//! cos θ = cos θz cos β + sin θz sin β cos(γs − γ)
//!
//! This is seed jimoh-2019 eq (1) (Duffie & Beckman) after substituting the
//! sun's direction from eq (7)/(8), equally its reduced form eq (13) with
//! c1 = cos θz, c2 = sin θz cos γs, c3 = sin θz sin γs (south-referenced
//! azimuths), and seed dahli-2023 eq (8) (Kalogirou's form of the same
//! expression). `tests/geometry_incidence.rs` evaluates the three published
//! forms from latitude, declination and hour angle and checks they agree with
//! this one.

use crate::float::Float;
use crate::position::SunPosition;

use super::GeometryError;

/// Orientation of a flat surface (a panel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface<T> {
    /// Slope β from horizontal in degrees: 0 faces the zenith, 90 is vertical.
    pub slope_deg: T,
    /// Azimuth of the surface normal's horizontal projection, degrees east of
    /// north (`[0, 360)`), the crate's convention. Seed jimoh-2019 measures it
    /// from south, positive west: see [`Surface::azimuth_from_south_deg`].
    pub azimuth_deg: T,
}

impl<T: Float> Surface<T> {
    /// A surface; errors for NaN/infinite angles. The azimuth is folded into
    /// `[0, 360)`; any slope is accepted (slopes above 90° face downward).
    pub fn new(slope_deg: T, azimuth_deg: T) -> Result<Self, GeometryError> {
        if !slope_deg.is_finite() || !azimuth_deg.is_finite() {
            return Err(GeometryError::NotFinite);
        }
        Ok(Surface {
            slope_deg,
            azimuth_deg: azimuth_deg.rem_euclid(T::from_f64(360.0)),
        })
    }

    /// A surface from seed jimoh-2019's convention: azimuth from south,
    /// positive toward west.
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
    pub fn azimuth_from_south_deg(&self) -> T {
        crate::position::azimuth_north_to_south_deg(self.azimuth_deg)
    }

    /// The surface pointed straight at the sun (zero incidence): β = θz,
    /// γ = γs (seed jimoh-2019 eq 14, see [`super::optimum::normal_to_sun`]).
    pub fn facing(sun: &SunPosition<T>) -> Self {
        Surface {
            slope_deg: sun.zenith_deg,
            azimuth_deg: sun.azimuth_deg,
        }
    }

    /// Unit normal in the local East-North-Up frame.
    pub fn normal_enu(&self) -> [T; 3] {
        let (sb, cb) = self.slope_deg.to_radians().sin_cos();
        let (sa, ca) = self.azimuth_deg.to_radians().sin_cos();
        [sb * sa, sb * ca, cb]
    }
}

/// cos θ of the beam on `surface` (seed jimoh-2019 eq 1/13, dahli-2023 eq 8).
/// Negative when the sun is behind the surface.
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
