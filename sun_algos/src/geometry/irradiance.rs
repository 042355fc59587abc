//! Irradiance: extraterrestrial, clear sky, on a tilted plane, and a day's
//! energy for fixed, single-axis and dual-axis mounts.
//!
//! - Extraterrestrial normal irradiance G_on = G_sc (1 + 0.033 cos(360° n /
//!   365)) with G_sc = 1367 W/m² (Duffie & Beckman, Solar Engineering of
//!   Thermal Processes, eq 1.4.1a; Dahli & Cheggaga (2023) quote ≈1370
//!   W/m²).
//! - Clear sky: the ASHRAE clear-day model, beam normal I_B = A e^(−k m),
//!   diffuse horizontal C·I_B, with A, k, C from Masters' sinusoidal fits of
//!   the ASHRAE monthly table (G. M. Masters, Renewable and Efficient
//!   Electric Power Systems, 2004, §7.8): A = 1160 + 75 sin(360/365 (n − 275))
//!   W/m², k = 0.174 + 0.035 sin(360/365 (n − 100)), C = 0.095 + 0.04
//!   sin(360/365 (n − 100)); air mass m by Kasten & Young (1989) so it stays
//!   finite at the horizon.
//! - Tilted plane, Dahli & Cheggaga (2023), eq (8) [second one]:
//!   G_T = G_B + G_D + G_R with G_B = I_B cos θ (θ from
//!   [`super::incidence`]), isotropic sky G_D = C I_B (1 + cos β)/2 and
//!   ground albedo ρ: G_R = ρ I_B (cos θz + C) (1 − cos β)/2.
//! - Daily energy: the trapezoid rule over the day's samples, the
//!   "area under the curve" of Chowdhury et al. (2019).
//!
//! # Example
//!
//! ```
//! use sun_algos::geometry::irradiance::{air_mass, clear_sky_beam_normal_w_m2};
//!
//! // ASHRAE clear day, 21 May (n = 141): A = 1104 W/m², k = 0.196 (Masters,
//! // Table 7.6). At zenith 60° (air mass 1.99429, Kasten & Young, as pvlib
//! // 0.16.1 gives it) the beam is 1104 · e^(−0.196 · 1.99429) = 746.8 W/m²;
//! // the sinusoidal fits of the table are within 1 W/m² of it.
//! assert!((air_mass(60.0f64).unwrap() - 1.994_293).abs() < 1e-6);
//! assert!((clear_sky_beam_normal_w_m2(60.0f64, 141) - 746.8).abs() < 1.0);
//! ```

use crate::float::Float;
use crate::position::SunPosition;
use crate::time::UtcTime;

use super::incidence::{cos_incidence, Surface};
use super::GeometryError;

/// Solar constant G_sc, W/m² (WMO 1981, as in Duffie & Beckman).
///
/// ```
/// use sun_algos::geometry::irradiance::{extraterrestrial_normal_w_m2, SOLAR_CONSTANT_W_M2};
///
/// // The WMO 1981 value; the year's mean of the extraterrestrial irradiance.
/// assert_eq!(SOLAR_CONSTANT_W_M2, 1367.0);
/// let mean = (1..=365).map(extraterrestrial_normal_w_m2::<f64>).sum::<f64>() / 365.0;
/// assert!((mean - SOLAR_CONSTANT_W_M2).abs() < 1e-9);
/// ```
pub const SOLAR_CONSTANT_W_M2: f64 = 1367.0;

/// Extraterrestrial irradiance on a plane normal to the beam for day of
/// year `n`, W/m² (Duffie & Beckman eq 1.4.1a).
///
/// ```
/// use sun_algos::geometry::irradiance::extraterrestrial_normal_w_m2;
///
/// // pvlib 0.16.1, get_extra_radiation(n, solar_constant=1367, method="asce"):
/// // 1412.104316 W/m² on 1 January, 1321.890671 W/m² on 2 July (n = 183).
/// assert!((extraterrestrial_normal_w_m2::<f64>(1) - 1412.104_316).abs() < 1e-5);
/// assert!((extraterrestrial_normal_w_m2::<f64>(183) - 1321.890_671).abs() < 1e-5);
/// ```
pub fn extraterrestrial_normal_w_m2<T: Float>(day_of_year: u16) -> T {
    let a = (T::from_f64(360.0 / 365.0) * T::from_u32(u32::from(day_of_year))).to_radians();
    T::from_f64(SOLAR_CONSTANT_W_M2) * (T::ONE + T::from_f64(0.033) * a.cos())
}

/// Coefficients of the ASHRAE clear-day model for a day of the year.
///
/// ```
/// use sun_algos::geometry::irradiance::ashrae_coefficients;
///
/// // The ASHRAE table's 21 May row (Masters, Table 7.6): A = 1104 W/m²,
/// // k = 0.196, C = 0.121.
/// let c = ashrae_coefficients::<f64>(141);
/// assert!((c.a_w_m2 - 1104.0).abs() < 2.0 && (c.k - 0.196).abs() < 0.002 && (c.c - 0.121).abs() < 0.002);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AshraeCoefficients<T> {
    /// Apparent extraterrestrial flux A, W/m².
    pub a_w_m2: T,
    /// Optical depth k.
    pub k: T,
    /// Sky diffuse factor C.
    pub c: T,
}

/// Masters' fits of the ASHRAE A, k, C for day of year `n`.
///
/// ```
/// use sun_algos::geometry::irradiance::ashrae_coefficients;
///
/// // The ASHRAE table's 21 May row (Masters, Table 7.6): A = 1104 W/m²,
/// // k = 0.196, C = 0.121; the fits are within 2 W/m² and 0.002.
/// let c = ashrae_coefficients::<f32>(141);
/// assert!((c.a_w_m2 - 1104.0).abs() < 2.0);
/// assert!((c.k - 0.196).abs() < 0.002);
/// assert!((c.c - 0.121).abs() < 0.002);
/// ```
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
///
/// ```
/// use sun_algos::geometry::irradiance::air_mass;
///
/// // pvlib 0.16.1, get_relative_airmass(z, "kastenyoung1989"): 0.999712 at
/// // the zenith, 1.994293 at 60°, 10.305791 at 85°.
/// assert!((air_mass(0.0f64).unwrap() - 0.999_712).abs() < 1e-6);
/// assert!((air_mass(60.0f64).unwrap() - 1.994_293).abs() < 1e-6);
/// assert!((air_mass(85.0f64).unwrap() - 10.305_791).abs() < 1e-5);
/// assert_eq!(air_mass(90.0f64), None);
/// ```
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
///
/// ```
/// use sun_algos::geometry::irradiance::clear_sky_beam_normal_w_m2;
///
/// // 21 May, zenith 60°: the ASHRAE table's A = 1104 W/m² and k = 0.196
/// // (Masters, Table 7.6) with pvlib's Kasten–Young air mass 1.994293 give
/// // 1104 · e^(−0.196 · 1.994293) = 746.81 W/m².
/// assert!((clear_sky_beam_normal_w_m2(60.0f64, 141) - 746.81).abs() < 1.0);
/// assert_eq!(clear_sky_beam_normal_w_m2(95.0f64, 141), 0.0); // sun down
/// ```
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
///
/// ```
/// use sun_algos::geometry::irradiance::clear_sky_on_plane;
/// use sun_algos::geometry::Surface;
/// use sun_algos::SunPosition;
///
/// // pvlib 0.16.1: the ASHRAE fits of 21 May (n = 141) in numpy, Kasten–Young
/// // air mass (get_relative_airmass) and the isotropic plane-of-array sum
/// // (irradiance.get_total_irradiance) for the sun at zenith 30°, azimuth
/// // 150° and a panel tilted 25° toward the south, albedo 0.2: beam
/// // 851.866692, sky diffuse 101.461117, ground 8.138713, total 961.466522 W/m².
/// let sun = SunPosition::new(30.0f64, 150.0, false);
/// let panel = Surface::new(25.0, 180.0)?;
/// let g = clear_sky_on_plane(&sun, &panel, 141, 0.2);
/// assert!((g.beam_w_m2 - 851.866_692).abs() < 1e-5);
/// assert!((g.diffuse_w_m2 - 101.461_117).abs() < 1e-5);
/// assert!((g.reflected_w_m2 - 8.138_713).abs() < 1e-5);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlaneIrradiance<T> {
    /// Beam G_B.
    pub beam_w_m2: T,
    /// Sky diffuse G_D (isotropic sky).
    pub diffuse_w_m2: T,
    /// Ground-reflected G_R.
    pub reflected_w_m2: T,
}

impl<T: Float> PlaneIrradiance<T> {
    /// G_T = G_B + G_D + G_R (Dahli & Cheggaga 2023).
    ///
    /// ```
    /// use sun_algos::geometry::irradiance::clear_sky_on_plane;
    /// use sun_algos::geometry::Surface;
    /// use sun_algos::SunPosition;
    ///
    /// // pvlib 0.16.1: the ASHRAE fits of 21 May (n = 141) in numpy, Kasten–Young
    /// // air mass (get_relative_airmass) and the isotropic plane-of-array sum
    /// // (irradiance.get_total_irradiance) for the sun at zenith 30°, azimuth
    /// // 150° and a panel tilted 25° toward the south, albedo 0.2: beam
    /// // 851.866692, sky diffuse 101.461117, ground 8.138713, total 961.466522 W/m².
    /// let sun = SunPosition::new(30.0f64, 150.0, false);
    /// let panel = Surface::new(25.0, 180.0)?;
    /// let g = clear_sky_on_plane(&sun, &panel, 141, 0.2);
    /// assert!((g.total_w_m2() - 961.466_522).abs() < 1e-5);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn total_w_m2(&self) -> T {
        self.beam_w_m2 + self.diffuse_w_m2 + self.reflected_w_m2
    }
}

/// Clear-sky irradiance on `surface` for the sun at `sun` on day `n`, with
/// ground albedo `albedo` (0…1; 0.2 is the usual grass/soil value).
///
/// ```
/// use sun_algos::geometry::irradiance::clear_sky_on_plane;
/// use sun_algos::geometry::Surface;
/// use sun_algos::SunPosition;
///
/// // pvlib 0.16.1: the ASHRAE fits of 21 May (n = 141) in numpy, Kasten–Young
/// // air mass (get_relative_airmass) and the isotropic plane-of-array sum
/// // (irradiance.get_total_irradiance) for the sun at zenith 30°, azimuth
/// // 150° and a panel tilted 25° toward the south, albedo 0.2: beam
/// // 851.866692, sky diffuse 101.461117, ground 8.138713, total 961.466522 W/m².
/// let sun = SunPosition::new(30.0f64, 150.0, false);
/// let panel = Surface::new(25.0, 180.0)?;
/// let g = clear_sky_on_plane(&sun, &panel, 141, 0.2);
/// assert!((g.total_w_m2() - 961.466_522).abs() < 1e-5);
/// // Nothing at night.
/// let night = clear_sky_on_plane(&SunPosition::new(100.0, 0.0, false), &panel, 141, 0.2);
/// assert_eq!(night.total_w_m2(), 0.0);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
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
///
/// ```
/// use sun_algos::geometry::irradiance::Mount;
/// use sun_algos::geometry::incidence::incidence_deg;
/// use sun_algos::SunPosition;
///
/// // A dual-axis mount leaves no incidence; a latitude-tilt fixed panel does.
/// let sun = SunPosition::new(40.0f64, 120.0, false);
/// assert!(incidence_deg(&sun, &Mount::DualAxis.surface(&sun)) < 1e-6);
/// assert!(incidence_deg(&sun, &Mount::fixed_latitude_tilt(25.4).surface(&sun)) > 20.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    ///
    /// ```
    /// use sun_algos::geometry::irradiance::Mount;
    /// use sun_algos::geometry::Surface;
    ///
    /// // Doha (25.37° N) faces south, Cape Town (33.92° S) north.
    /// assert_eq!(Mount::fixed_latitude_tilt(25.37f64), Mount::Fixed(Surface::new(25.37, 180.0)?));
    /// assert_eq!(Mount::fixed_latitude_tilt(-33.92f64), Mount::Fixed(Surface::new(33.92, 0.0)?));
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn fixed_latitude_tilt(latitude_deg: T) -> Self {
        let az = if latitude_deg >= T::ZERO { 180.0 } else { 0.0 };
        Mount::Fixed(Surface {
            slope_deg: latitude_deg.abs(),
            azimuth_deg: T::from_f64(az),
        })
    }

    /// The panel's orientation with the sun at `sun`.
    ///
    /// ```
    /// use sun_algos::geometry::irradiance::Mount;
    /// use sun_algos::SunPosition;
    ///
    /// // pvlib 0.16.1, tracking.singleaxis(50, 100, axis_tilt=0, axis_azimuth=180,
    /// // max_angle=60, backtrack=False): surface tilt 49.567539°, azimuth 90°.
    /// let single = Mount::HorizontalNorthSouthAxis { max_rotation_deg: 60.0 };
    /// let s = single.surface(&SunPosition::new(50.0f64, 100.0, false));
    /// assert!((s.slope_deg - 49.567_539).abs() < 1e-6);
    /// assert_eq!(s.azimuth_deg, 90.0);
    /// ```
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
/// Wh/m² (the area under the curve of Chowdhury et al. 2019).
///
/// ```
/// use sun_algos::geometry::irradiance::trapezoid_wh_m2;
///
/// // A triangle: 0 to 1000 W/m² in one hour and back in another: 1000 Wh/m².
/// let e = trapezoid_wh_m2([(0.0f64, 0.0), (3600.0, 1000.0), (7200.0, 0.0)]);
/// assert!((e - 1000.0).abs() < 1e-9);
/// ```
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
///
/// ```
/// use sun_algos::geometry::events::solar_day_start;
/// use sun_algos::geometry::irradiance::{clear_sky_day_energy_wh_m2, Mount};
/// use sun_algos::{Algorithm, Options, Site};
///
/// // Doha on 2016-03-21, 24 h from mean solar midnight every 300 s, albedo
/// // 0.2: pvlib 0.16.1 (SPA positions, the same ASHRAE fits, singleaxis,
/// // get_total_irradiance) gives 7756.7989, 9904.1979 and 10439.5993 Wh/m²
/// // for a latitude-tilt fixed panel, a north–south single axis and a dual
/// // axis (tests/data/doha_clear_sky_energy_pvlib.csv).
/// let (lat, lon) = (25.37463f64, 51.49128);
/// let site = Site::new(lat, lon)?;
/// let mounts = [
///     Mount::fixed_latitude_tilt(lat),
///     Mount::HorizontalNorthSouthAxis { max_rotation_deg: 90.0 },
///     Mount::DualAxis,
/// ];
/// let start = solar_day_start(2016, 3, 21, lon)?;
/// let got = clear_sky_day_energy_wh_m2(&start, 300, &mounts, 0.2, |t| {
///     Algorithm::Spa.position(t, &site, &Options::default())
/// })?;
/// for (g, want) in got.iter().zip([7756.7989, 9904.1979, 10439.5993]) {
///     assert!((g - want).abs() < 1e-5 * want, "{g} vs {want}");
/// }
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
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
