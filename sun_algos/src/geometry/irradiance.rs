//! Irradiance: extraterrestrial, clear sky, on a tilted plane, and a day's
//! energy for fixed, single-axis and dual-axis mounts.
//!
//! - Extraterrestrial normal irradiance G_on = G_sc (1 + 0.033 cos(360° n /
//!   365)) with G_sc = 1367 W/m² (Duffie & Beckman, Solar Engineering of
//!   Thermal Processes, eq 1.4.1a; seed dahli-2023 quotes ≈1370 W/m²).
//! - Clear sky: the ASHRAE clear-day model, beam normal I_B = A e^(−k m),
//!   diffuse horizontal C·I_B, with A, k, C from Masters' sinusoidal fits of
//!   the ASHRAE monthly table (G. M. Masters, Renewable and Efficient
//!   Electric Power Systems, 2004, §7.8): A = 1160 + 75 sin(360/365 (n − 275))
//!   W/m², k = 0.174 + 0.035 sin(360/365 (n − 100)), C = 0.095 + 0.04
//!   sin(360/365 (n − 100)); air mass m by Kasten & Young (1989) so it stays
//!   finite at the horizon.
//! - Tilted plane, seed dahli-2023 eq (8) [second one]: G_T = G_B + G_D + G_R
//!   with G_B = I_B cos θ (θ from [`super::incidence`]), isotropic sky
//!   G_D = C I_B (1 + cos β)/2 and ground albedo ρ: G_R = ρ I_B (cos θz + C)
//!   (1 − cos β)/2.
//! - Daily energy: the trapezoid rule over the day's samples, seed
//!   chowdhury-2019's "area under the curve".

use crate::float::Float;
use crate::position::SunPosition;
use crate::time::UtcTime;

use super::incidence::{cos_incidence, Surface};
use super::GeometryError;

/// Solar constant G_sc, W/m² (WMO 1981, as in Duffie & Beckman).
pub const SOLAR_CONSTANT_W_M2: f64 = 1367.0;

/// Extraterrestrial irradiance on a plane normal to the beam for day of
/// year `n`, W/m² (Duffie & Beckman eq 1.4.1a).
pub fn extraterrestrial_normal_w_m2<T: Float>(day_of_year: u16) -> T {
    let a = (T::from_f64(360.0 / 365.0) * T::from_u32(u32::from(day_of_year))).to_radians();
    T::from_f64(SOLAR_CONSTANT_W_M2) * (T::ONE + T::from_f64(0.033) * a.cos())
}

/// Coefficients of the ASHRAE clear-day model for a day of the year.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AshraeCoefficients<T> {
    /// Apparent extraterrestrial flux A, W/m².
    pub a_w_m2: T,
    /// Optical depth k.
    pub k: T,
    /// Sky diffuse factor C.
    pub c: T,
}

/// Masters' fits of the ASHRAE A, k, C for day of year `n`.
pub fn ashrae_coefficients<T: Float>(day_of_year: u16) -> AshraeCoefficients<T> {
    let n = T::from_u32(u32::from(day_of_year));
    let w = T::from_f64(360.0 / 365.0);
    let s275 = (w * (n - T::from_f64(275.0))).to_radians().sin();
    let s100 = (w * (n - T::from_f64(100.0))).to_radians().sin();
    AshraeCoefficients {
        a_w_m2: T::from_f64(1160.0) + T::from_f64(75.0) * s275,
        k: T::from_f64(0.174) + T::from_f64(0.035) * s100,
        c: T::from_f64(0.095) + T::from_f64(0.04) * s100,
    }
}

/// Relative optical air mass for a zenith angle in degrees (Kasten & Young
/// 1989): 1/(cos z + 0.50572 (96.07995 − z)^−1.6364). `None` at or below
/// the horizon (z ≥ 90°).
pub fn air_mass<T: Float>(zenith_deg: T) -> Option<T> {
    // NaN fails this test too.
    if !zenith_deg.is_finite() || zenith_deg >= T::from_f64(90.0) {
        return None;
    }
    let z = zenith_deg.max(T::ZERO);
    let cz = z.to_radians().cos();
    let corr = T::from_f64(0.50572) * (T::from_f64(96.07995) - z).powf(T::from_f64(-1.6364));
    Some(T::ONE / (cz + corr))
}

/// Clear-sky beam normal irradiance I_B = A e^(−k m), W/m²; 0 with the sun
/// down.
pub fn clear_sky_beam_normal_w_m2<T: Float>(zenith_deg: T, day_of_year: u16) -> T {
    match air_mass(zenith_deg) {
        None => T::ZERO,
        Some(m) => {
            let c = ashrae_coefficients::<T>(day_of_year);
            c.a_w_m2 * (-(c.k * m)).exp()
        }
    }
}

/// Irradiance on a tilted plane, W/m².
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlaneIrradiance<T> {
    /// Beam G_B.
    pub beam_w_m2: T,
    /// Sky diffuse G_D (isotropic sky).
    pub diffuse_w_m2: T,
    /// Ground-reflected G_R.
    pub reflected_w_m2: T,
}

impl<T: Float> PlaneIrradiance<T> {
    /// G_T = G_B + G_D + G_R (seed dahli-2023).
    pub fn total_w_m2(&self) -> T {
        self.beam_w_m2 + self.diffuse_w_m2 + self.reflected_w_m2
    }
}

/// Clear-sky irradiance on `surface` for the sun at `sun` on day `n`, with
/// ground albedo `albedo` (0…1; 0.2 is the usual grass/soil value).
pub fn clear_sky_on_plane<T: Float>(
    sun: &SunPosition<T>,
    surface: &Surface<T>,
    day_of_year: u16,
    albedo: T,
) -> PlaneIrradiance<T> {
    let ib = clear_sky_beam_normal_w_m2(sun.zenith_deg, day_of_year);
    if !ib.is_finite() || ib <= T::ZERO {
        return PlaneIrradiance::default();
    }
    let c = ashrae_coefficients::<T>(day_of_year).c;
    let cos_t = cos_incidence(sun, surface).max(T::ZERO);
    let cb = surface.slope_deg.to_radians().cos();
    let half = T::from_f64(0.5);
    let cz = sun.zenith_deg.to_radians().cos().max(T::ZERO);
    PlaneIrradiance {
        beam_w_m2: ib * cos_t,
        diffuse_w_m2: c * ib * (T::ONE + cb) * half,
        reflected_w_m2: albedo * ib * (cz + c) * (T::ONE - cb) * half,
    }
}

/// How the panel is held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mount<T> {
    /// Fixed slope and azimuth.
    Fixed(Surface<T>),
    /// One horizontal north–south axis, turned east–west toward the sun,
    /// rotation limited to ±`max_rotation_deg` from horizontal.
    HorizontalNorthSouthAxis {
        /// Rotation limit, degrees (90 = unlimited).
        max_rotation_deg: T,
    },
    /// Two axes, normal to the sun (zero incidence).
    DualAxis,
}

impl<T: Float> Mount<T> {
    /// A fixed panel tilted at |latitude|, facing the equator (the usual
    /// year-round rule of thumb).
    pub fn fixed_latitude_tilt(latitude_deg: T) -> Self {
        let az = if latitude_deg >= T::ZERO { 180.0 } else { 0.0 };
        Mount::Fixed(Surface {
            slope_deg: latitude_deg.abs(),
            azimuth_deg: T::from_f64(az),
        })
    }

    /// The panel's orientation with the sun at `sun`.
    pub fn surface(&self, sun: &SunPosition<T>) -> Surface<T> {
        match *self {
            Mount::Fixed(s) => s,
            Mount::DualAxis => Surface::facing(sun),
            Mount::HorizontalNorthSouthAxis { max_rotation_deg } => {
                // The normal turns in the east–up plane: n = (sin ρ, 0, cos ρ);
                // the best ρ points it at the sun's projection on that plane.
                let v = sun.unit_vector_enu();
                let lim = max_rotation_deg.abs().min(T::from_f64(90.0));
                let rho = v[0].atan2(v[2].max(T::ZERO)).to_degrees().clamp(-lim, lim);
                let az = if rho >= T::ZERO { 90.0 } else { 270.0 };
                Surface {
                    slope_deg: rho.abs(),
                    azimuth_deg: T::from_f64(az),
                }
            }
        }
    }
}

/// Trapezoid rule over `(seconds, watts per m²)` samples in time order, in
/// Wh/m² (seed chowdhury-2019's area under the curve).
pub fn trapezoid_wh_m2<T: Float>(samples: impl IntoIterator<Item = (T, T)>) -> T {
    let mut total = T::ZERO;
    let mut prev: Option<(T, T)> = None;
    for (t, p) in samples {
        if let Some((t0, p0)) = prev {
            total += (t - t0) * (p0 + p) * T::from_f64(0.5);
        }
        prev = Some((t, p));
    }
    total / T::from_f64(3600.0)
}

/// Clear-sky energy on each of `mounts` over the 24 h from `start`, Wh/m²,
/// sampled every `step_s` seconds (60…3600, dividing 86 400) from the
/// position source `sun` (one position per sample, shared by the mounts),
/// integrated by the trapezoid rule.
pub fn clear_sky_day_energy_wh_m2<T, F, const K: usize>(
    start: &UtcTime,
    step_s: u32,
    mounts: &[Mount<T>; K],
    albedo: T,
    mut sun: F,
) -> Result<[T; K], GeometryError>
where
    T: Float,
    F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
{
    if !(60..=3600).contains(&step_s) || 86_400 % step_s != 0 {
        return Err(GeometryError::InvalidInterval);
    }
    if !albedo.is_finite() {
        return Err(GeometryError::NotFinite);
    }
    let n = 86_400 / step_s;
    let mut total = [T::ZERO; K];
    let mut prev = [T::ZERO; K];
    let half_dt = T::from_u32(step_s) * T::from_f64(0.5);
    for i in 0..=n {
        let t = start.add_seconds(i64::from(i * step_s))?;
        let p = sun(&t)?;
        for ((m, tot), pr) in mounts.iter().zip(total.iter_mut()).zip(prev.iter_mut()) {
            let g = clear_sky_on_plane(&p, &m.surface(&p), t.day_of_year(), albedo).total_w_m2();
            if i > 0 {
                *tot += half_dt * (*pr + g);
            }
            *pr = g;
        }
    }
    Ok(total.map(|e| e / T::from_f64(3600.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ashrae_fits_match_the_may_table_row() {
        // ASHRAE clear-day table, 21 May (n = 141): A = 1104 W/m², k = 0.196,
        // C = 0.121 (Masters Table 7.6 / ASHRAE 1985).
        let c = ashrae_coefficients::<f64>(141);
        assert!((c.a_w_m2 - 1104.0).abs() < 2.0, "{c:?}");
        assert!((c.k - 0.196).abs() < 0.002);
        assert!((c.c - 0.121).abs() < 0.002);
    }

    #[test]
    fn extraterrestrial_perihelion_and_aphelion() {
        // 1367 × 1.033 = 1412.1 on 1 January; 1367 × (1 − 0.033 × 0.9999)
        // ≈ 1321.9 near 2 July (n = 183), hand calculation.
        let jan: f64 = extraterrestrial_normal_w_m2(1);
        assert!((jan - 1412.1).abs() < 0.2, "{jan}");
        let jul: f64 = extraterrestrial_normal_w_m2(183);
        assert!((jul - 1321.9).abs() < 0.2, "{jul}");
    }

    #[test]
    fn air_mass_near_horizon_is_finite() {
        // Kasten & Young's formula gives m ≈ 37.92 at the horizon (hand
        // evaluation: 1/(0.50572 × 6.07995^−1.6364)); z = 89.999° is just
        // inside.
        let m: f64 = air_mass(89.999).unwrap();
        assert!((m - 37.92).abs() < 0.05, "{m}");
        assert_eq!(air_mass(90.0f64), None);
        assert!((air_mass(0.0f64).unwrap() - 1.0).abs() < 1e-3);
    }

    #[test]
    fn trapezoid_of_a_constant() {
        // 1000 W/m² for one hour, in two trapezoids = 1000 Wh/m².
        let e = trapezoid_wh_m2([(0.0f64, 1000.0), (1800.0, 1000.0), (3600.0, 1000.0)]);
        assert!((e - 1000.0).abs() < 1e-9);
    }
}
