//! The result: where the sun is in the observer's sky.

use crate::float::Float;

/// The sun's topocentric direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunPosition<T> {
    /// Zenith angle in degrees, 0 overhead, 90 on the horizon.
    pub zenith_deg: T,
    /// Azimuth in degrees east of north, in `[0, 360)`.
    pub azimuth_deg: T,
    /// True when atmospheric refraction was applied (an apparent position).
    pub refracted: bool,
}

impl<T: Float> SunPosition<T> {
    /// Builds a position, folding the azimuth into `[0, 360)`.
    pub fn new(zenith_deg: T, azimuth_deg: T, refracted: bool) -> Self {
        SunPosition {
            zenith_deg,
            azimuth_deg: azimuth_deg.rem_euclid(T::from_f64(360.0)),
            refracted,
        }
    }

    /// Elevation (altitude) above the horizon in degrees: 90° − zenith.
    pub fn elevation_deg(&self) -> T {
        T::from_f64(90.0) - self.zenith_deg
    }

    /// True when the sun's centre is above the (geometric or apparent) horizon.
    pub fn is_above_horizon(&self) -> bool {
        self.zenith_deg < T::from_f64(90.0)
    }

    /// Azimuth measured from south, positive toward west, in `(−180, 180]`:
    /// the convention of seed jimoh-2019 (solar azimuth γs zero due south,
    /// negative before noon, positive after).
    pub fn azimuth_from_south_deg(&self) -> T {
        azimuth_north_to_south_deg(self.azimuth_deg)
    }

    /// Unit vector toward the sun in the local East-North-Up frame.
    pub fn unit_vector_enu(&self) -> [T; 3] {
        let (sz, cz) = self.zenith_deg.to_radians().sin_cos();
        let (sa, ca) = self.azimuth_deg.to_radians().sin_cos();
        [sz * sa, sz * ca, cz]
    }

    /// Angle in degrees between this direction and another.
    pub fn angular_distance_deg(&self, other: &SunPosition<T>) -> T {
        angle_between_deg(&self.unit_vector_enu(), &other.unit_vector_enu())
    }
}

/// Angle in degrees between two vectors, `atan2(|a × b|, a · b)`, which keeps
/// its precision for tiny angles where `acos` of the dot product loses it.
pub fn angle_between_deg<T: Float>(a: &[T; 3], b: &[T; 3]) -> T {
    let cx = a[1] * b[2] - a[2] * b[1];
    let cy = a[2] * b[0] - a[0] * b[2];
    let cz = a[0] * b[1] - a[1] * b[0];
    let cross = (cx * cx + cy * cy + cz * cz).sqrt();
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    cross.atan2(dot).to_degrees()
}

/// Azimuth east of north → azimuth from south, positive west, `(−180, 180]`.
pub fn azimuth_north_to_south_deg<T: Float>(azimuth_deg: T) -> T {
    let a = (azimuth_deg - T::from_f64(180.0)).rem_euclid(T::from_f64(360.0));
    if a > T::from_f64(180.0) {
        a - T::from_f64(360.0)
    } else {
        a
    }
}

/// Azimuth from south, positive west → azimuth east of north, `[0, 360)`.
pub fn azimuth_south_to_north_deg<T: Float>(azimuth_from_south_deg: T) -> T {
    (azimuth_from_south_deg + T::from_f64(180.0)).rem_euclid(T::from_f64(360.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn south_convention_round_trip() {
        for (north, south) in [(180.0, 0.0), (90.0, -90.0), (270.0, 90.0), (0.0, 180.0)] {
            assert!((azimuth_north_to_south_deg(north) - south).abs() < 1e-12f64);
            assert!((azimuth_south_to_north_deg(south) - north).abs() < 1e-12f64);
        }
    }

    #[test]
    fn angular_distance_of_orthogonal_directions() {
        let a = SunPosition::new(90.0f64, 0.0, false);
        let b = SunPosition::new(0.0f64, 123.0, false);
        assert!((a.angular_distance_deg(&b) - 90.0).abs() < 1e-12);
        let c = SunPosition::new(45.0f64, 10.0, false);
        assert!(c.angular_distance_deg(&c).abs() < 1e-12);
    }
}
