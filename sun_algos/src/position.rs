//! The result: where the sun is in the observer's sky.

use crate::float::Float;

/// The sun's topocentric direction.
///
/// ```
/// use sun_algos::{Algorithm, Options, Site, SunPosition, UtcTime};
///
/// // A row of the reference file sun_1999_2022.csv (JPL DE421 through
/// // skyfield, topocentric, geometric): 2006-03-01T13:45:38Z at 34.76767° N,
/// // 45.58589° W, ΔT 64.886 s → zenith 47.2182225°, azimuth 149.2139858°.
/// let truth = SunPosition::new(47.218_222_5f64, 149.213_985_8, false);
/// let t: UtcTime = "2006-03-01T13:45:38Z".parse()?;
/// let site = Site::new(34.76767, -45.58589)?;
/// let opts = Options { delta_t_s: Some(64.886), ..Options::default() };
/// let p = Algorithm::Spa.position(&t, &site, &opts)?;
/// // SPA's stated uncertainty is ±0.0003° (Reda & Andreas 2004).
/// assert!(p.angular_distance_deg(&truth) < 0.0003);
/// assert!(p.is_above_horizon() && !p.refracted);
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    ///
    /// ```
    /// use sun_algos::SunPosition;
    ///
    /// // −90° east of north is 270° (west).
    /// assert_eq!(SunPosition::new(30.0f64, -90.0, false).azimuth_deg, 270.0);
    /// assert_eq!(SunPosition::new(30.0f64, 720.0, false).azimuth_deg, 0.0);
    /// ```
    pub fn new(zenith_deg: T, azimuth_deg: T, refracted: bool) -> Self {
        SunPosition {
            zenith_deg,
            azimuth_deg: azimuth_deg.rem_euclid(T::from_f64(360.0)),
            refracted,
        }
    }

    /// Elevation (altitude) above the horizon in degrees: 90° − zenith.
    ///
    /// ```
    /// use sun_algos::SunPosition;
    ///
    /// // NREL SPA worked example: apparent zenith 50.111622° is elevation 39.888378°.
    /// let p = SunPosition::new(50.111_622f64, 194.340_241, true);
    /// assert!((p.elevation_deg() - 39.888_378).abs() < 1e-9);
    /// ```
    pub fn elevation_deg(&self) -> T {
        T::from_f64(90.0) - self.zenith_deg
    }

    /// True when the sun's centre is above the (geometric or apparent) horizon.
    ///
    /// ```
    /// use sun_algos::SunPosition;
    ///
    /// assert!(SunPosition::new(89.9f32, 270.0, false).is_above_horizon());
    /// assert!(!SunPosition::new(90.0f32, 270.0, false).is_above_horizon());
    /// ```
    pub fn is_above_horizon(&self) -> bool {
        self.zenith_deg < T::from_f64(90.0)
    }

    /// Azimuth measured from south, positive toward west, in `(−180, 180]`:
    /// the convention of Jimoh & Aliyu (2019): solar azimuth γs zero due
    /// south, negative before noon, positive after.
    ///
    /// ```
    /// use sun_algos::SunPosition;
    ///
    /// // NREL SPA worked example: azimuth 194.340241° east of north is the
    /// // topocentric astronomers' azimuth Γ = 14.340241° west of south (eq. 45).
    /// let p = SunPosition::new(50.111_622f64, 194.340_241, true);
    /// assert!((p.azimuth_from_south_deg() - 14.340_241).abs() < 1e-9);
    /// // Morning sun in the east: negative (the convention of Jimoh & Aliyu).
    /// assert_eq!(SunPosition::new(60.0f64, 90.0, false).azimuth_from_south_deg(), -90.0);
    /// ```
    pub fn azimuth_from_south_deg(&self) -> T {
        azimuth_north_to_south_deg(self.azimuth_deg)
    }

    /// Unit vector toward the sun in the local East-North-Up frame.
    ///
    /// ```
    /// use sun_algos::SunPosition;
    ///
    /// // On the horizon due east: (1, 0, 0); overhead: (0, 0, 1).
    /// let [e, n, u] = SunPosition::new(90.0f64, 90.0, false).unit_vector_enu();
    /// assert!((e - 1.0).abs() < 1e-15 && n.abs() < 1e-15 && u.abs() < 1e-15);
    /// assert_eq!(SunPosition::new(0.0f64, 123.0, false).unit_vector_enu(), [0.0, 0.0, 1.0]);
    /// ```
    pub fn unit_vector_enu(&self) -> [T; 3] {
        let (sz, cz) = self.zenith_deg.to_radians().sin_cos();
        let (sa, ca) = self.azimuth_deg.to_radians().sin_cos();
        [sz * sa, sz * ca, cz]
    }

    /// Angle in degrees between this direction and another.
    ///
    /// ```
    /// use sun_algos::SunPosition;
    ///
    /// // NREL SPA worked example: the sun (zenith 50.111622°, azimuth 194.340241°)
    /// // and the normal of a surface tilted 30° toward azimuth 170° (rotation −10°
    /// // from south) are the incidence angle apart: 25.187000°.
    /// let sun = SunPosition::new(50.111_622f64, 194.340_241, true);
    /// let normal = SunPosition::new(30.0, 170.0, false);
    /// assert!((sun.angular_distance_deg(&normal) - 25.187_000).abs() < 1e-5);
    /// ```
    pub fn angular_distance_deg(&self, other: &SunPosition<T>) -> T {
        angle_between_deg(&self.unit_vector_enu(), &other.unit_vector_enu())
    }
}

/// Angle in degrees between two vectors, `atan2(|a × b|, a · b)`, which keeps
/// its precision for tiny angles where `acos` of the dot product loses it.
///
/// ```
/// use sun_algos::position::angle_between_deg;
///
/// assert!((angle_between_deg(&[1.0f64, 0.0, 0.0], &[0.0, 1.0, 0.0]) - 90.0).abs() < 1e-12);
/// // A tiny angle keeps its precision in f32: 1e-4 rad is 0.0057296°.
/// let a = angle_between_deg(&[1.0f32, 0.0, 0.0], &[1.0, 1e-4, 0.0]);
/// assert!((a - 0.005_729_578).abs() < 1e-7);
/// ```
pub fn angle_between_deg<T: Float>(a: &[T; 3], b: &[T; 3]) -> T {
    let cx = a[1] * b[2] - a[2] * b[1];
    let cy = a[2] * b[0] - a[0] * b[2];
    let cz = a[0] * b[1] - a[1] * b[0];
    let cross = (cx * cx + cy * cy + cz * cz).sqrt();
    let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    cross.atan2(dot).to_degrees()
}

/// Azimuth east of north → azimuth from south, positive west, `(−180, 180]`.
///
/// ```
/// use sun_algos::position::azimuth_north_to_south_deg;
///
/// // South is 0, west +90, east −90, north 180.
/// assert_eq!(azimuth_north_to_south_deg(180.0f64), 0.0);
/// assert_eq!(azimuth_north_to_south_deg(270.0f64), 90.0);
/// assert_eq!(azimuth_north_to_south_deg(90.0f64), -90.0);
/// assert_eq!(azimuth_north_to_south_deg(0.0f64), 180.0);
/// ```
pub fn azimuth_north_to_south_deg<T: Float>(azimuth_deg: T) -> T {
    let a = (azimuth_deg - T::from_f64(180.0)).rem_euclid(T::from_f64(360.0));
    if a > T::from_f64(180.0) {
        a - T::from_f64(360.0)
    } else {
        a
    }
}

/// Azimuth from south, positive west → azimuth east of north, `[0, 360)`.
///
/// ```
/// use sun_algos::position::azimuth_south_to_north_deg;
///
/// // NREL SPA worked example: surface azimuth rotation −10° (east of south)
/// // is 170° east of north.
/// assert_eq!(azimuth_south_to_north_deg(-10.0f64), 170.0);
/// assert_eq!(azimuth_south_to_north_deg(180.0f64), 0.0);
/// ```
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
