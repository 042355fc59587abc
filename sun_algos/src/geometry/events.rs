//! Sunrise, transit, sunset and daylight hours.
//!
//! Two models:
//! - [`simple()`]: seed jimoh-2019 eq (9)–(12) on the seed's declination and
//!   equation of time, with polar day and night exactly as the seed states:
//!   no sunrise when −tan φ tan δ ≥ 1 (ω_sr = ω_ss = 0, both at solar 12 h),
//!   no sunset when −tan φ tan δ ≤ −1 (ω = ∓180°, solar 0 h and 24 h).
//! - [`find`]: precise events of any position source (any [`Algorithm`], in
//!   f32 or f64) by bracketing and bisection: the day is sampled every
//!   10 minutes, each crossing of the zenith limit 90.8333° (SPA's convention,
//!   NREL SPA report appendix A.2, h0′ = −0.8333°: sun radius 0.26667° plus refraction 0.5667°) is
//!   bisected to 1 s, and the transit is found by a golden-section search on
//!   the zenith around the highest sample.
//! - [`spa()`]: SPA's own closed-form routine (Reda & Andreas appendix A.2)
//!   from the SPA module, as [`Events`].
//!
//! The day examined is the local mean solar day: 24 h starting at mean solar
//! midnight, 00:00 UTC − λ/15 h of the given date, so that a site at 170° E
//! or 170° W still gets its whole daylight in one window.

use crate::algorithm::Algorithm;
use crate::float::Float;
use crate::position::SunPosition;
use crate::refraction::SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG;
use crate::site::{Options, Site};
use crate::time::UtcTime;

use super::simple;
use super::GeometryError;

/// Whether the sun rises and sets on a day.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DayKind {
    /// The sun rises and sets (or at least one of the two happens).
    Normal,
    /// Above the horizon all day: no sunrise, no sunset.
    PolarDay,
    /// Below the horizon all day.
    PolarNight,
}

/// The seed's simple events in local apparent solar time (eq 9–12).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimpleEvents<T> {
    /// Normal day, polar day or polar night (from −tan φ tan δ).
    pub kind: DayKind,
    /// Sunset hour angle ω_s in degrees (eq 9), 0…180; sunrise is −ω_s.
    pub sunset_hour_angle_deg: T,
    /// Solar time of sunrise in hours, 12 − ω_s/15.
    pub sunrise_solar_h: T,
    /// Solar time of sunset in hours, 12 + ω_s/15.
    pub sunset_solar_h: T,
    /// Daylight hours N = 2ω_s/15 (eq 12).
    pub daylight_h: T,
    /// Declination used (eq 2), degrees.
    pub declination_deg: T,
    /// Equation of time used (eq 5), hours.
    pub equation_of_time_h: T,
}

impl<T: Float> SimpleEvents<T> {
    /// Solar hours → UTC hours of the same date at `longitude_deg`
    /// (UTC = ST − λ/15 − ET; may leave 0…24 for far-east/west sites).
    pub fn solar_to_utc_h(&self, solar_h: T, longitude_deg: T) -> T {
        solar_h - longitude_deg / T::from_f64(15.0) - self.equation_of_time_h
    }
}

/// Seed jimoh-2019 eq (9)–(12) for `latitude_deg` on `day_of_year`.
/// Never NaN: the acos argument −tan φ tan δ is formed as a ratio only
/// after the polar cases are taken out.
pub fn simple<T: Float>(
    latitude_deg: T,
    day_of_year: u16,
) -> Result<SimpleEvents<T>, GeometryError> {
    if !latitude_deg.is_finite() {
        return Err(GeometryError::NotFinite);
    }
    let lat = latitude_deg.clamp(T::from_f64(-90.0), T::from_f64(90.0));
    let delta: T = simple::declination_deg(day_of_year);
    let (sp, cp) = lat.to_radians().sin_cos();
    let (sd, cd) = delta.to_radians().sin_cos();
    // −tan φ tan δ = num / den with den = cos φ cos δ ≥ 0.
    let num = -(sp * sd);
    let den = cp.abs() * cd;
    let (kind, ws) = if num >= den {
        (DayKind::PolarNight, T::ZERO)
    } else if num <= -den {
        (DayKind::PolarDay, T::from_f64(180.0))
    } else {
        (
            DayKind::Normal,
            (num / den).clamp(-T::ONE, T::ONE).acos().to_degrees(),
        )
    };
    let half_h = ws / T::from_f64(15.0);
    Ok(SimpleEvents {
        kind,
        sunset_hour_angle_deg: ws,
        sunrise_solar_h: T::from_f64(12.0) - half_h,
        sunset_solar_h: T::from_f64(12.0) + half_h,
        daylight_h: half_h + half_h,
        declination_deg: delta,
        equation_of_time_h: simple::equation_of_time_h(day_of_year),
    })
}

/// Precise events of one local solar day.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Events<T> {
    /// Normal day, polar day or polar night.
    pub kind: DayKind,
    /// Start of the examined 24 h window (mean solar midnight).
    pub window_start: UtcTime,
    /// First upward crossing of the horizon limit, if any (±1 s).
    pub sunrise: Option<UtcTime>,
    /// Instant of the smallest zenith angle (±1 s).
    pub transit: UtcTime,
    /// Zenith angle at transit, degrees.
    pub transit_zenith_deg: T,
    /// Last downward crossing, if any (±1 s).
    pub sunset: Option<UtcTime>,
    /// Seconds the sun's upper limb is above the horizon in the window.
    pub daylight_s: u32,
}

/// Sampling step of [`find`], seconds.
const STEP_S: i64 = 600;
/// Samples per window (24 h / 10 min + 1).
const SAMPLES: i64 = 86_400 / STEP_S + 1;

/// Start of the local mean solar day containing local date `(y, m, d)` at
/// `longitude_deg`: 00:00 UTC − λ/15 h, rounded to the second.
pub fn solar_day_start<T: Float>(
    year: i32,
    month: u8,
    day: u8,
    longitude_deg: T,
) -> Result<UtcTime, GeometryError> {
    if !longitude_deg.is_finite() || longitude_deg.abs() > T::from_f64(180.0) {
        return Err(GeometryError::Position(crate::Error::LongitudeOutOfRange));
    }
    let midnight = UtcTime::from_ymd_hms(year, month, day, 0, 0, 0)?;
    let shift_s = -(longitude_deg * T::from_f64(240.0)).to_f64();
    // |shift| ≤ 43 200 s, exact enough as an integer second.
    let shift_s = if shift_s >= 0.0 {
        (shift_s + 0.5) as i64
    } else {
        (shift_s - 0.5) as i64
    };
    Ok(midnight.add_seconds(shift_s)?)
}

/// Precise events in the 24 h from `window_start`, from any position
/// source `sun` (method in the module documentation; about 190 calls).
pub fn find<T, F>(window_start: UtcTime, mut sun: F) -> Result<Events<T>, GeometryError>
where
    T: Float,
    F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
{
    let limit = T::from_f64(90.0 + SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG);
    // Height above the limit; positive when the sun is up.
    let mut up = |t: &UtcTime| -> Result<T, GeometryError> {
        let p = sun(t)?;
        if !p.zenith_deg.is_finite() {
            return Err(GeometryError::NotFinite);
        }
        Ok(limit - p.zenith_deg)
    };
    let at = |s: i64| window_start.add_seconds(s);

    let mut prev = up(&window_start)?;
    let first_up = prev > T::ZERO;
    let mut sunrise: Option<UtcTime> = None;
    let mut sunset: Option<UtcTime> = None;
    let mut any_up = first_up;
    let mut best_i: i64 = 0;
    let mut best_v = prev;
    for i in 1..SAMPLES {
        let v = up(&at(i * STEP_S)?)?;
        if v > best_v {
            best_v = v;
            best_i = i;
        }
        let crossed_up = prev <= T::ZERO && v > T::ZERO;
        let crossed_down = prev > T::ZERO && v <= T::ZERO;
        if crossed_up && sunrise.is_none() {
            sunrise = Some(bisect(&mut up, &at((i - 1) * STEP_S)?, true)?);
        }
        if crossed_down {
            sunset = Some(bisect(&mut up, &at((i - 1) * STEP_S)?, false)?);
        }
        any_up |= v > T::ZERO;
        prev = v;
    }
    // Transit: golden-section search on the height over ±1 step around the
    // highest sample, to 1 s.
    let lo = (best_i - 1).max(0) * STEP_S;
    let hi = ((best_i + 1) * STEP_S).min(86_400);
    let (transit_s, transit_v) = golden_max(&mut up, &window_start, lo, hi)?;
    let transit = at(transit_s)?;
    let kind = match (sunrise, sunset) {
        (None, None) if any_up => DayKind::PolarDay,
        (None, None) => DayKind::PolarNight,
        _ => DayKind::Normal,
    };
    let end_s: i64 = 86_400;
    let rise_s = sunrise.map(|t| t.unix_seconds() - window_start.unix_seconds());
    let set_s = sunset.map(|t| t.unix_seconds() - window_start.unix_seconds());
    let daylight_s = match kind {
        DayKind::PolarDay => end_s,
        DayKind::PolarNight => 0,
        DayKind::Normal => match (rise_s, set_s) {
            (Some(r), Some(s)) if s > r => s - r,
            // Set then rose again (up at both ends of the window).
            (Some(r), Some(s)) => s + (end_s - r),
            (Some(r), None) => end_s - r,
            (None, Some(s)) => s,
            (None, None) => 0,
        },
    };
    Ok(Events {
        kind,
        window_start,
        sunrise,
        transit,
        transit_zenith_deg: limit - transit_v,
        sunset,
        daylight_s: daylight_s.clamp(0, end_s) as u32,
    })
}

/// Precise events of the local solar day of date `(y, m, d)` at `site` with
/// `algorithm`. Positions are geometric (any atmosphere in `options` is
/// ignored): the horizon limit already holds the standard refraction.
pub fn for_algorithm<T: Float>(
    algorithm: Algorithm,
    ymd: (i32, u8, u8),
    site: &Site<T>,
    options: &Options<T>,
) -> Result<Events<T>, GeometryError> {
    let start = solar_day_start(ymd.0, ymd.1, ymd.2, site.longitude_deg())?;
    let opts = Options {
        atmosphere: None,
        ..*options
    };
    find(start, |t| algorithm.position(t, site, &opts))
}

/// Precise events of the UT day of `(y, m, d)` from NREL SPA's own
/// closed-form routine (Reda & Andreas 2004, appendix A.2, via
/// [`crate::spa::rise_transit_set`]; h0′ = −0.8333°, accuracy tested against
/// NREL's worked example in the SPA module's tests). The window is that UT
/// day; events may fall slightly outside it, as SPA reports them.
pub fn spa<T: Float>(
    ymd: (i32, u8, u8),
    site: &Site<T>,
    options: &Options<T>,
) -> Result<Events<T>, GeometryError> {
    use crate::spa::RiseSet;
    let day = UtcTime::from_ymd_hms(ymd.0, ymd.1, ymd.2, 0, 0, 0)?;
    let rts = crate::spa::rise_transit_set(&day, site, options)?;
    let transit = at_hours(&day, rts.transit_h)?;
    let opts = Options {
        atmosphere: None,
        ..*options
    };
    let transit_zenith_deg = Algorithm::Spa.position(&transit, site, &opts)?.zenith_deg;
    let (kind, sunrise, sunset) = match rts.rise_set {
        RiseSet::Both {
            sunrise_h,
            sunset_h,
        } => (
            DayKind::Normal,
            Some(at_hours(&day, sunrise_h)?),
            Some(at_hours(&day, sunset_h)?),
        ),
        RiseSet::AlwaysAbove => (DayKind::PolarDay, None, None),
        RiseSet::AlwaysBelow => (DayKind::PolarNight, None, None),
    };
    let daylight_s = match (kind, sunrise, sunset) {
        (DayKind::PolarDay, _, _) => 86_400,
        (_, Some(r), Some(s)) => (s.unix_seconds() - r.unix_seconds()).clamp(0, 86_400) as u32,
        _ => 0,
    };
    Ok(Events {
        kind,
        window_start: day,
        sunrise,
        transit,
        transit_zenith_deg,
        sunset,
        daylight_s,
    })
}

/// `day` plus `hours` (either sign), to the millisecond.
fn at_hours<T: Float>(day: &UtcTime, hours: T) -> Result<UtcTime, GeometryError> {
    if !hours.is_finite() || hours.abs() > T::from_f64(48.0) {
        return Err(GeometryError::NotFinite);
    }
    let ms = libm::round(hours.to_f64() * 3_600_000.0) as i64;
    let days = i64::from(day.days_since_2000()) + ms.div_euclid(86_400_000);
    let days =
        i32::try_from(days).map_err(|_| GeometryError::Position(crate::Error::InvalidDate))?;
    Ok(UtcTime::from_days_ms(
        days,
        ms.rem_euclid(86_400_000) as u32,
    )?)
}

/// Bisects a crossing inside `[t0, t0 + STEP_S]` to 1 s. `rising`: the
/// height goes from ≤ 0 to > 0.
fn bisect<T: Float>(
    up: &mut impl FnMut(&UtcTime) -> Result<T, GeometryError>,
    t0: &UtcTime,
    rising: bool,
) -> Result<UtcTime, GeometryError> {
    let (mut a, mut b) = (0i64, STEP_S);
    while b - a > 1 {
        let m = (a + b) / 2;
        let above = up(&t0.add_seconds(m)?)? > T::ZERO;
        if above == rising {
            b = m;
        } else {
            a = m;
        }
    }
    // The nearer whole second to the crossing.
    let va = up(&t0.add_seconds(a)?)?.abs();
    let vb = up(&t0.add_seconds(b)?)?.abs();
    Ok(t0.add_seconds(if va < vb { a } else { b })?)
}

/// Golden-section search for the maximum of `up` on `[lo, hi]` seconds
/// after `t0`, to 1 s; returns the second and the value there.
fn golden_max<T: Float>(
    up: &mut impl FnMut(&UtcTime) -> Result<T, GeometryError>,
    t0: &UtcTime,
    lo: i64,
    hi: i64,
) -> Result<(i64, T), GeometryError> {
    const INV_PHI: f64 = 0.618_033_988_749_895;
    let (mut a, mut b) = (lo as f64, hi as f64);
    let mut f =
        |s: f64| -> Result<T, GeometryError> { up(&t0.add_seconds(libm::round(s) as i64)?) };
    let mut c = b - INV_PHI * (b - a);
    let mut d = a + INV_PHI * (b - a);
    let mut fc = f(c)?;
    let mut fd = f(d)?;
    while b - a > 1.0 {
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - INV_PHI * (b - a);
            fc = f(c)?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + INV_PHI * (b - a);
            fd = f(d)?;
        }
    }
    let s = libm::round((a + b) / 2.0) as i64;
    let v = f(s as f64)?;
    Ok((s, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equator_equinox_has_twelve_hours() {
        // φ = 0: −tan φ tan δ = 0 → ω_s = 90°, N = 12 h (eq 9, 12).
        let e = simple(0.0f64, 80).unwrap();
        assert_eq!(e.kind, DayKind::Normal);
        assert!((e.daylight_h - 12.0).abs() < 1e-9);
    }

    #[test]
    fn poles_follow_the_seed_rules() {
        // 21 June: δ ≈ +23.45°. North pole: polar day, solar 0 h and 24 h.
        let n = simple(90.0f64, 172).unwrap();
        assert_eq!(n.kind, DayKind::PolarDay);
        assert_eq!((n.sunrise_solar_h, n.sunset_solar_h), (0.0, 24.0));
        // South pole: polar night, both at solar 12 h.
        let s = simple(-90.0f64, 172).unwrap();
        assert_eq!(s.kind, DayKind::PolarNight);
        assert_eq!((s.sunrise_solar_h, s.sunset_solar_h), (12.0, 12.0));
        assert_eq!(s.daylight_h, 0.0);
    }
}
