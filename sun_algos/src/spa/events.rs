//! Sunrise, sun transit and sunset (NREL SPA report, appendix A.2).

use super::geocentric::geocentric;
use super::split::{frac, SplitDays};
use crate::algorithm::{Algorithm, Inputs};
use crate::error::Error;
use crate::float::Float;
use crate::site::{Options, Site};
use crate::time::UtcTime;

/// Altitude of the sun's centre at sunrise and sunset, h0′ = −0.8333°: the
/// sun's radius (0.26667°) plus the refraction at the horizon (0.5667°)
/// (appendix A.2, step 5).
///
/// ```
/// use sun_algos::refraction::SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG;
/// use sun_algos::spa::SUNRISE_ALTITUDE_DEG;
///
/// // The sun's radius 0.26667° plus 0.5667° of refraction at the horizon,
/// // 0.83337°, which the report rounds to 0.8333°.
/// assert!((SUNRISE_ALTITUDE_DEG + SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG).abs() < 1e-4);
/// ```
pub const SUNRISE_ALTITUDE_DEG: f64 = -0.8333;

/// Sun rise and set of one day.
///
/// ```
/// use sun_algos::spa::{rise_transit_set, RiseSet};
/// use sun_algos::{Options, Site, UtcTime};
///
/// // At the June solstice the sun's declination is +23.4°: it never sets north
/// // of 66.6° N and never rises south of 66.6° S (the polar circles).
/// let day: UtcTime = "2026-06-21T00:00:00Z".parse()?;
/// let opts = Options::default();
/// let north = rise_transit_set(&day, &Site::new(80.0f64, 15.0)?, &opts)?;
/// assert_eq!(north.rise_set, RiseSet::AlwaysAbove);
/// let south = rise_transit_set(&day, &Site::new(-80.0f64, 15.0)?, &opts)?;
/// assert_eq!(south.rise_set, RiseSet::AlwaysBelow);
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RiseSet<T> {
    /// The sun rises and sets: hours UT1 from 0 h of the day (both may lie
    /// slightly outside `[0, 24)` when the event falls on a neighbouring UT day).
    Both {
        /// Sunrise, hours after 0 h UT1 (eq. A.2 step 13, "R").
        sunrise_h: T,
        /// Sunset, hours after 0 h UT1 (step 14, "S").
        sunset_h: T,
    },
    /// Polar day: the sun's centre stays above h0′ all day.
    AlwaysAbove,
    /// Polar night: the sun's centre stays below h0′ all day.
    AlwaysBelow,
}

/// Sunrise, transit and sunset of one UT day (appendix A.2).
///
/// ```
/// use sun_algos::spa::{local_hours, rise_transit_set};
/// use sun_algos::{Options, Site, UtcTime};
///
/// // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
/// // 39.742476° N, 105.1786° W, 1830.14 m, ΔT 67 s, time zone −7 h.
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
/// // Transit 11.768045 h local time.
/// let rts = rise_transit_set(&"2003-10-17T00:00:00Z".parse()?, &site, &opts)?;
/// assert!((local_hours(rts.transit_h, -7.0) - 11.768_045).abs() < 1e-5);
/// # Ok::<(), sun_algos::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RiseTransitSet<T> {
    /// Sun transit (local solar noon), hours after 0 h UT1 (step 12, "T").
    pub transit_h: T,
    /// Sunrise and sunset, or why there are none.
    pub rise_set: RiseSet<T>,
}

/// Hours UT1 as local clock hours in `[0, 24)` for a time zone `tz_h` hours
/// east of Greenwich (the report's "local time" with its `timezone`).
///
/// ```
/// use sun_algos::spa::local_hours;
///
/// // NREL SPA worked example: sunrise 13.212067 h UT is 6.212067 h at UTC−7;
/// // 0.338667 h UT is 17.338667 h the evening before.
/// assert!((local_hours(13.212_067f64, -7.0) - 6.212_067).abs() < 1e-12);
/// assert!((local_hours(0.338_667f64, -7.0) - 17.338_667).abs() < 1e-12);
/// ```
pub fn local_hours<T: Float>(utc_h: T, tz_h: T) -> T {
    (utc_h + tz_h).rem_euclid(T::from_f64(24.0))
}

/// `x` into `[0, 1)` when `|x| ≥ 2` (step 10's limit on a and b).
fn limit_difference<T: Float>(x: T) -> T {
    if x.abs() >= T::from_f64(2.0) {
        frac(x)
    } else {
        x
    }
}

/// Step 10: interpolation between the three days' values (degrees).
fn interpolate<T: Float>(v: [T; 3], n: T) -> T {
    let [y1, y2, y3] = v;
    let a = limit_difference(y2 - y1);
    let b = limit_difference(y3 - y2);
    let c = b - a;
    y2 + n * (a + b + c * n) / T::from_f64(2.0)
}

/// Sunrise, sun transit and sunset on the UT1 day of `day` (its time of day
/// is ignored) at `site`, by appendix A.2 of the SPA report. The ΔT of
/// `options` (or the built-in model) is used; `options.atmosphere` is not:
/// the horizon is h0′ = [`SUNRISE_ALTITUDE_DEG`]. Polar day and night are
/// [`RiseSet::AlwaysAbove`] and [`RiseSet::AlwaysBelow`]; the transit is
/// always given.
///
/// ```
/// use sun_algos::spa::{local_hours, rise_transit_set, RiseSet};
/// use sun_algos::{Options, Site, UtcTime};
///
/// // NREL SPA report, worked example (shared/reference/nrel_spa_test_vector.json):
/// // 39.742476° N, 105.1786° W, 1830.14 m, ΔT 67 s, time zone −7 h.
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
/// // The report's sunrise 6.212067 h, transit 11.768045 h and sunset
/// // 17.338667 h local time.
/// let rts = rise_transit_set(&"2003-10-17T12:30:30Z".parse()?, &site, &opts)?;
/// let RiseSet::Both { sunrise_h, sunset_h } = rts.rise_set else {
///     panic!("Golden, Colorado has a sunrise and a sunset in October");
/// };
/// assert!((local_hours(sunrise_h, -7.0) - 6.212_067).abs() < 1e-5);
/// assert!((local_hours(rts.transit_h, -7.0) - 11.768_045).abs() < 1e-5);
/// assert!((local_hours(sunset_h, -7.0) - 17.338_667).abs() < 1e-5);
/// # Ok::<(), sun_algos::Error>(())
/// ```
pub fn rise_transit_set<T: Float>(
    day: &UtcTime,
    site: &Site<T>,
    options: &Options<T>,
) -> Result<RiseTransitSet<T>, Error> {
    let day = day.start_of_day();
    let inp = Inputs::new(Algorithm::Spa, &day, site, options)?;
    let half = T::from_f64(0.5);
    let n = day.days_since_2000();
    // Step 1: apparent sidereal time at 0 h UT.
    let nu_deg = geocentric(&SplitDays::new(&day, inp.delta_t_s))
        .nu_rad
        .to_degrees();
    // Step 2: α and δ at 0 h TT of the day before, the day and the day after.
    let mut alpha_deg = [T::ZERO; 3];
    let mut delta_deg = [T::ZERO; 3];
    for ((a, d), k) in alpha_deg.iter_mut().zip(delta_deg.iter_mut()).zip(-1..=1) {
        let g = geocentric(&SplitDays {
            days: n + k,
            frac_ut: -half,
            frac_tt: -half,
        });
        *a = g.alpha_rad.to_degrees().rem_euclid(T::from_f64(360.0));
        *d = g.delta_rad().to_degrees();
    }
    let [_, alpha2, _] = alpha_deg;
    let [_, delta2, _] = delta_deg;
    let lat_deg = site.latitude_deg();
    let lon_deg = site.longitude_deg();
    let (sin_lat, cos_lat) = lat_deg.to_radians().sin_cos();
    let deg360 = T::from_f64(360.0);
    let h0p_deg = T::from_f64(SUNRISE_ALTITUDE_DEG);
    let sin_h0p = h0p_deg.to_radians().sin();

    // Step 3: approximate transit time (fraction of the day).
    let m0 = frac((alpha2 - lon_deg - nu_deg) / deg360);
    // Steps 7–11 for one approximate time m: interpolated δ′, local hour
    // angle H′ in (−180°, 180°] and altitude h.
    let refine = |m: T| -> (T, T, T) {
        let nu_i = nu_deg + T::from_f64(360.985_647) * m;
        let n_i = m + inp.delta_t_s / T::from_f64(86_400.0);
        let alpha_p = interpolate(alpha_deg, n_i);
        let delta_p = interpolate(delta_deg, n_i);
        let h_p =
            (nu_i + lon_deg - alpha_p + T::from_f64(180.0)).rem_euclid(deg360) - T::from_f64(180.0);
        let (sd, cd) = delta_p.to_radians().sin_cos();
        let sin_h = (sin_lat * sd + cos_lat * cd * h_p.to_radians().cos()).clamp(-T::ONE, T::ONE);
        (delta_p, h_p, sin_h.asin().to_degrees())
    };
    let (_, h_p0, _) = refine(m0);
    // Step 12 (transit), in hours after 0 h UT.
    let transit_h = (m0 - h_p0 / deg360) * T::from_f64(24.0);

    // Step 4: hour angle at rise/set, or polar day/night.
    let (sd2, cd2) = delta2.to_radians().sin_cos();
    let num = sin_h0p - sin_lat * sd2;
    let den = cos_lat * cd2;
    let rise_set = if num <= -den {
        RiseSet::AlwaysAbove
    } else if num >= den {
        RiseSet::AlwaysBelow
    } else {
        let h0_deg = (num / den).clamp(-T::ONE, T::ONE).acos().to_degrees();
        // Steps 5–6.
        let m1 = frac(m0 - h0_deg / deg360);
        let m2 = frac(m0 + h0_deg / deg360);
        // Steps 13–14: correction from the altitude error at the approximate time.
        let event = |m: T| -> T {
            let (delta_p, h_p, h) = refine(m);
            let d = deg360 * delta_p.to_radians().cos() * cos_lat * h_p.to_radians().sin();
            let corr = (h - h0p_deg) / d;
            let t = if corr.is_finite() { m + corr } else { m };
            t * T::from_f64(24.0)
        };
        RiseSet::Both {
            sunrise_h: event(m1),
            sunset_h: event(m2),
        }
    };
    Ok(RiseTransitSet {
        transit_h,
        rise_set,
    })
}
