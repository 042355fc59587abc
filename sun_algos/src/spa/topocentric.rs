//! From geocentric to topocentric: the observer's hour angle, parallax and
//! horizon coordinates (NREL SPA report, section 3.9–3.14).

use super::geocentric::Geocentric;
use crate::float::Float;

/// Earth's polar to equatorial radius, 0.99664719 (eq. 35).
const POLAR_RATIO: f64 = 0.996_647_19;
/// Earth's equatorial radius in metres (eq. 36–37).
const EQUATORIAL_RADIUS_M: f64 = 6_378_140.0;
/// Equatorial horizontal parallax of the sun at 1 AU, arc seconds (eq. 33).
const PARALLAX_1AU_ARCSEC: f64 = 8.794;

/// The observer's constants of eq. 34–37: sin φ, cos φ and the geocentric
/// position terms x = ρ cos φ′ and y = ρ sin φ′ (in Earth radii).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Observer<T> {
    pub sin_lat: T,
    pub cos_lat: T,
    pub x: T,
    pub y: T,
    pub lon_rad: T,
}

impl<T: Float> Observer<T> {
    /// Eq. 34–37. u = atan(0.99664719 tan φ) is taken through its cosine and
    /// sine, (cos φ, 0.99664719 sin φ) / norm, which stays finite at the poles.
    pub fn new(lat_deg: T, lon_deg: T, elevation_m: T) -> Self {
        let (sin_lat, cos_lat) = lat_deg.to_radians().sin_cos();
        let k = T::from_f64(POLAR_RATIO);
        let n = (cos_lat * cos_lat + k * k * sin_lat * sin_lat).sqrt();
        let (cos_u, sin_u) = (cos_lat / n, k * sin_lat / n);
        let h = elevation_m / T::from_f64(EQUATORIAL_RADIUS_M);
        Observer {
            sin_lat,
            cos_lat,
            x: cos_u + h * cos_lat,
            y: k * sin_u + h * sin_lat,
            lon_rad: lon_deg.to_radians(),
        }
    }
}

/// The topocentric sun.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Topocentric<T> {
    /// Observer local hour angle H, radians (eq. 32).
    pub h_rad: T,
    /// The sun's direction from the observer in the equatorial frame that
    /// turns with the local meridian: x toward the meridian on the equator,
    /// y toward the west point, z toward the celestial pole; length is the
    /// topocentric distance over the geocentric one (eq. 38–39 in vector form).
    pub v: [T; 3],
    /// Topocentric elevation angle e0 without refraction, radians (eq. 41).
    pub e0_rad: T,
    /// Topocentric azimuth Φ east of north, radians in `(−π, π]` (eq. 44–46).
    pub azimuth_rad: T,
}

impl<T: Float> Topocentric<T> {
    /// Parallax in right ascension Δα, radians (eq. 38).
    pub fn dalpha_rad(&self) -> T {
        self.h_rad - self.h_prime_rad()
    }
    /// Topocentric hour angle H′, radians (eq. 40).
    pub fn h_prime_rad(&self) -> T {
        let [vx, vy, _] = self.v;
        // H grows westward; vy is the westward component.
        let h = vy.atan2(vx);
        // Keep H′ on the same turn as H.
        h + ((self.h_rad - h) / T::TAU + T::from_f64(0.5)).floor() * T::TAU
    }
    /// Topocentric declination δ′, radians (eq. 39).
    pub fn delta_prime_rad(&self) -> T {
        let [vx, vy, vz] = self.v;
        vz.atan2((vx * vx + vy * vy).sqrt())
    }
}

/// Section 3.9–3.14. The parallax of eq. 38–39 is the exact shift of the
/// sun's direction by the observer's geocentric position (the same
/// geometry written as a vector difference, which also gives H′ and δ′);
/// elevation and azimuth follow from that vector's horizon components
/// (eq. 41–46, with atan2 in place of asin for precision near the zenith).
pub(crate) fn topocentric<T: Float>(geo: &Geocentric<T>, obs: &Observer<T>) -> Topocentric<T> {
    let h_rad = geo.nu_rad + obs.lon_rad - geo.alpha_rad;
    let xi_rad = (T::from_f64(PARALLAX_1AU_ARCSEC / 3600.0) / geo.helio.r_au).to_radians();
    let sin_xi = xi_rad.sin();
    let (sin_h, cos_h) = h_rad.sin_cos();
    // Sun direction (unit, geocentric) minus observer position in units of
    // the sun's distance: (cos δ cos H − x sin ξ, cos δ sin H, sin δ − y sin ξ).
    let vx = geo.cos_delta * cos_h - obs.x * sin_xi;
    let vy = geo.cos_delta * sin_h;
    let vz = geo.sin_delta - obs.y * sin_xi;
    let up = obs.sin_lat * vz + obs.cos_lat * vx;
    let north = obs.cos_lat * vz - obs.sin_lat * vx;
    let east = -vy;
    Topocentric {
        h_rad,
        v: [vx, vy, vz],
        e0_rad: up.atan2((east * east + north * north).sqrt()),
        azimuth_rad: east.atan2(north),
    }
}
