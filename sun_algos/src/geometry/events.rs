//! Sunrise, transit, sunset and daylight hours.
//!
//! Two models:
//! - [`simple()`]: Jimoh & Aliyu (2019), eq (9)–(12), on the paper's
//!   declination and equation of time, with polar day and night exactly as
//!   the paper states:
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
//!
//! # Example
//!
//! ```
//! use sun_algos::geometry::events::{self, DayKind};
//! use sun_algos::{Algorithm, Options, Site, UtcTime};
//!
//! // The NREL SPA report's site (39.742476° N, 105.1786° W, 1830.14 m, ΔT
//! // 67 s) on its example day, 2003-10-17 (local time UTC−7).
//! let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
//! let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
//! let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
//! assert_eq!(ev.kind, DayKind::Normal);
//! // Sunrise: the report's 6.212067 h local, 13:12:43.44 UT, to ±1 s.
//! let want_rise: UtcTime = "2003-10-17T13:12:43.440Z".parse()?;
//! let rise = ev.sunrise.expect("a sunrise");
//! assert!((rise.unix_seconds() - want_rise.unix_seconds()).abs() <= 1);
//! // Sunset of that local day: pvlib 0.16.1's spa_python puts the zenith at
//! // 90.8335° at 2003-10-18T00:18:51Z, on the horizon limit 90.8333°.
//! let want_set: UtcTime = "2003-10-18T00:18:51Z".parse()?;
//! let set = ev.sunset.expect("a sunset");
//! assert!((set.unix_seconds() - want_set.unix_seconds()).abs() <= 1);
//! // Jimoh & Aliyu's simple model: 12 h of daylight on the equator at the equinox.
//! assert!((events::simple(0.0f64, 80)?.daylight_h - 12.0).abs() < 1e-9);
//! # Ok::<(), sun_algos::geometry::GeometryError>(())
//! ```

use crate::algorithm::Algorithm;
use crate::float::Float;
use crate::position::SunPosition;
use crate::refraction::SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG;
use crate::site::{Options, Site};
use crate::time::UtcTime;

use super::simple;
use super::GeometryError;

/// Whether the sun rises and sets on a day.
///
/// ```
/// use sun_algos::geometry::events::{simple, DayKind};
///
/// // 21 June (n = 172), δ ≈ +23.45°: above the arctic circle the sun does not
/// // set; below the antarctic circle it does not rise.
/// assert_eq!(simple(80.0f64, 172)?.kind, DayKind::PolarDay);
/// assert_eq!(simple(-80.0f64, 172)?.kind, DayKind::PolarNight);
/// assert_eq!(simple(52.0f64, 172)?.kind, DayKind::Normal);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DayKind {
    /// The sun rises and sets (or at least one of the two happens).
    Normal,
    /// Above the horizon all day: no sunrise, no sunset.
    PolarDay,
    /// Below the horizon all day.
    PolarNight,
}

/// Jimoh & Aliyu's simple events in local apparent solar time (eq 9–12).
///
/// ```
/// use sun_algos::geometry::events::simple;
///
/// // 52° N on 21 June: pvlib 0.16.1's sun_rise_set_transit_geometric with the
/// // same declination (23.448902°) gives 16.496394 h of daylight, sunrise at
/// // 03:45:06.49 and sunset at 20:14:53.51 solar time.
/// let e = simple(52.0f64, 172)?;
/// assert!((e.daylight_h - 16.496_394).abs() < 1e-6);
/// assert!((e.sunrise_solar_h - (3.0 + 45.0 / 60.0 + 6.49 / 3600.0)).abs() < 1e-5);
/// assert!((e.sunset_solar_h - (20.0 + 14.0 / 60.0 + 53.51 / 3600.0)).abs() < 1e-5);
/// assert!((e.sunset_hour_angle_deg - 15.0 * e.daylight_h / 2.0).abs() < 1e-9);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    ///
    /// ```
    /// use sun_algos::geometry::events::simple;
    ///
    /// // Solar noon 15° east of Greenwich is one hour earlier in UTC, less the
    /// // equation of time (UTC = ST − λ/15 − ET).
    /// let e = simple(52.0f64, 172)?;
    /// let utc = e.solar_to_utc_h(12.0, 15.0);
    /// assert!((utc - (11.0 - e.equation_of_time_h)).abs() < 1e-12);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn solar_to_utc_h(&self, solar_h: T, longitude_deg: T) -> T {
        solar_h - longitude_deg / T::from_f64(15.0) - self.equation_of_time_h
    }
}

/// Jimoh & Aliyu (2019), eq (9)–(12), for `latitude_deg` on `day_of_year`.
/// Never NaN: the acos argument −tan φ tan δ is formed as a ratio only
/// after the polar cases are taken out.
///
/// ```
/// use sun_algos::geometry::events::{simple, DayKind};
/// use sun_algos::geometry::GeometryError;
///
/// // Equator at the March equinox (δ ≈ 0): 12 h (eq. 9 and 12).
/// let e = simple(0.0f32, 80)?;
/// assert_eq!(e.kind, DayKind::Normal);
/// assert!((e.daylight_h - 12.0).abs() < 1e-4);
/// // North pole in June: polar day, the paper's solar 0 h and 24 h.
/// let n = simple(90.0f64, 172)?;
/// assert_eq!((n.kind, n.sunrise_solar_h, n.sunset_solar_h), (DayKind::PolarDay, 0.0, 24.0));
/// assert_eq!(simple(f64::NAN, 172), Err(GeometryError::NotFinite));
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
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
///
/// ```
/// use sun_algos::geometry::events;
/// use sun_algos::{Algorithm, Options, Site};
///
/// let site = Site::new(11.9683f64, 8.4261)?; // Kano
/// let ev = events::for_algorithm(Algorithm::Spa, (2026, 6, 21), &site, &Options::default())?;
/// let (rise, set) = (ev.sunrise.expect("sunrise"), ev.sunset.expect("sunset"));
/// assert!(rise < ev.transit && ev.transit < set);
/// assert_eq!(i64::from(ev.daylight_s), set.unix_seconds() - rise.unix_seconds());
/// // At 12° N in June the noon sun stands about 11.5° from the zenith
/// // (latitude minus the solstice declination 23.44°).
/// assert!((ev.transit_zenith_deg - (23.44 - 11.9683)).abs() < 0.1);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

impl<T> Events<T> {
    /// The daylight of the window, `[from, to]`: sunrise to sunset; the
    /// window's start or end (24 h on) where one of them is missing; the
    /// whole window for a polar day, and when the sun sets and rises again
    /// inside it (only near the polar circles); `None` in a polar night.
    /// Errors only at the end of the calendar.
    ///
    /// ```
    /// use sun_algos::geometry::events::{find, solar_day_start};
    /// use sun_algos::{Algorithm, Options, Site};
    ///
    /// // 80° N: polar day on the June solstice, polar night in December.
    /// let site = Site::new(80.0f64, 15.0)?;
    /// let sun = |t: &_| Algorithm::Spa.position(t, &site, &Options::default());
    /// let start = solar_day_start(2026, 6, 21, 15.0)?;
    /// let end = start.add_seconds_i32(86_400)?;
    /// assert_eq!(find(start, sun)?.daylight()?, Some((start, end)));
    /// let start = solar_day_start(2026, 12, 21, 15.0)?;
    /// assert_eq!(find(start, sun)?.daylight()?, None);
    /// // Kano: sunrise to sunset.
    /// let site = Site::new(11.9683f64, 8.4261)?;
    /// let sun = |t: &_| Algorithm::Spa.position(t, &site, &Options::default());
    /// let ev = find(solar_day_start(2026, 6, 21, 8.4261)?, sun)?;
    /// assert_eq!(ev.daylight()?, Some((ev.sunrise.unwrap(), ev.sunset.unwrap())));
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn daylight(&self) -> Result<Option<(UtcTime, UtcTime)>, GeometryError> {
        let start = self.window_start;
        let end = start.add_seconds_i32(86_400)?;
        if self.kind == DayKind::PolarNight {
            return Ok(None);
        }
        let mut span = (start, end);
        if self.kind == DayKind::Normal {
            match (self.sunrise, self.sunset) {
                // Set and rose again inside the window: the whole window.
                (Some(rise), Some(set)) if set <= rise => {}
                (rise, set) => span = (rise.unwrap_or(start), set.unwrap_or(end)),
            }
        }
        Ok(Some(span))
    }
}

/// Sampling step of [`find`], seconds.
const STEP_S: i32 = 600;
/// Samples per window (24 h / 10 min + 1).
const SAMPLES: i32 = 86_400 / STEP_S + 1;

/// Start of the local mean solar day containing local date `(y, m, d)` at
/// `longitude_deg`: 00:00 UTC − λ/15 h, rounded to the second.
///
/// ```
/// use sun_algos::geometry::events::solar_day_start;
///
/// // Kano, 8.4261° E: mean solar midnight is 8.4261 × 240 s = 33 min 42 s
/// // before 00:00 UTC (hand computation).
/// assert_eq!(solar_day_start(2026, 6, 21, 8.4261f64)?.to_string(), "2026-06-20T23:26:18Z");
/// assert!(solar_day_start(2026, 6, 21, 181.0f64).is_err());
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
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
        (shift_s + 0.5) as i32
    } else {
        (shift_s - 0.5) as i32
    };
    Ok(midnight.add_seconds_i32(shift_s)?)
}

/// Precise events in the 24 h from `window_start`, from any position
/// source `sun` (method in the module documentation; about 190 calls).
/// All at once: [`EventSearch`] does the same search a few positions at a
/// time.
///
/// ```
/// use sun_algos::geometry::events::{find, solar_day_start};
/// use sun_algos::{Algorithm, Options, Site, UtcTime};
///
/// // The NREL SPA report's site (39.742476° N, 105.1786° W, 1830.14 m, ΔT
/// // 67 s) on its example day, 2003-10-17 (local time UTC−7).
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
/// let start = solar_day_start(2003, 10, 17, site.longitude_deg())?;
/// let ev = find(start, |t| Algorithm::Spa.position(t, &site, &opts))?;
/// // Sunrise: the report's 6.212067 h local, 13:12:43.44 UT, to ±1 s.
/// let want_rise: UtcTime = "2003-10-17T13:12:43.440Z".parse()?;
/// let rise = ev.sunrise.expect("a sunrise");
/// assert!((rise.unix_seconds() - want_rise.unix_seconds()).abs() <= 1);
/// // Sunset of that local day: pvlib 0.16.1's spa_python puts the zenith at
/// // 90.8335° at 2003-10-18T00:18:51Z, on the horizon limit 90.8333°.
/// let want_set: UtcTime = "2003-10-18T00:18:51Z".parse()?;
/// let set = ev.sunset.expect("a sunset");
/// assert!((set.unix_seconds() - want_set.unix_seconds()).abs() <= 1);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
pub fn find<T, F>(window_start: UtcTime, mut sun: F) -> Result<Events<T>, GeometryError>
where
    T: Float,
    F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
{
    let mut search = EventSearch::new(window_start);
    loop {
        if let Some(events) = search.step(&mut sun, u32::MAX)? {
            return Ok(events);
        }
    }
}

/// Where an [`EventSearch`] is.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Stage<T> {
    /// The first sample (window start).
    Start,
    /// The 10-minute samples; `i` is the next one.
    Sample { i: i32 },
    /// Bisecting a crossing between `a` and `b` seconds after the window
    /// start; then the two ends are compared (`va` once the first is
    /// known). The samples continue at `resume`. (Every instant of the
    /// search is a whole number of seconds after the window start: one
    /// time computation, and no instant stored, in the loop.)
    Bisect {
        rising: bool,
        a: i32,
        b: i32,
        va: Option<T>,
        resume: i32,
    },
    /// Golden-section search for the transit on `[a, b]` seconds with the
    /// interior points `c`, `d` (their heights once known), in the float
    /// type of the positions (no software `f64` on an 8-bit board).
    Golden {
        a: T,
        b: T,
        c: T,
        d: T,
        fc: Option<T>,
        fd: Option<T>,
    },
}

/// [`find`] as a resumable search: [`EventSearch::step`] evaluates at most
/// a given number of positions and returns, so that a main loop on a slow
/// microcontroller (a position costs about 45,000 cycles on an ATmega) is
/// never blocked for the whole search. Same samples, same order, same
/// result as [`find`].
///
/// ```
/// use sun_algos::geometry::events::{find, solar_day_start, EventSearch};
/// use sun_algos::{Algorithm, Options, Site};
///
/// let site = Site::new(11.9683f32, 8.4261)?;
/// let sun = |t: &_| Algorithm::Michalsky.position(t, &site, &Options::default());
/// let start = solar_day_start(2026, 6, 21, site.longitude_deg())?;
/// // Eight positions per call, as a slow main loop would run it.
/// let mut search = EventSearch::new(start);
/// let (mut calls, mut source) = (0, sun);
/// let ev = loop {
///     calls += 1;
///     if let Some(ev) = search.step(&mut source, 8)? {
///         break ev;
///     }
/// };
/// assert!(calls > 10);
/// assert_eq!(ev, find(start, sun)?);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EventSearch<T> {
    window_start: UtcTime,
    stage: Stage<T>,
    prev: T,
    any_up: bool,
    best_i: i32,
    best_v: T,
    /// Sunrise and sunset once found, seconds after the window start.
    sunrise_s: Option<i32>,
    sunset_s: Option<i32>,
}

impl<T: Float> EventSearch<T> {
    /// A search over the 24 h from `window_start`; nothing evaluated yet.
    ///
    /// ```
    /// use sun_algos::geometry::events::EventSearch;
    /// use sun_algos::UtcTime;
    ///
    /// let s = EventSearch::<f64>::new(UtcTime::MIDNIGHT_2000);
    /// assert_eq!(s.window_start(), UtcTime::MIDNIGHT_2000);
    /// ```
    pub fn new(window_start: UtcTime) -> Self {
        EventSearch {
            window_start,
            stage: Stage::Start,
            prev: T::ZERO,
            any_up: false,
            best_i: 0,
            best_v: T::ZERO,
            sunrise_s: None,
            sunset_s: None,
        }
    }

    /// The start of the window searched.
    ///
    /// ```
    /// use sun_algos::geometry::events::{solar_day_start, EventSearch};
    ///
    /// let start = solar_day_start(2026, 6, 21, 8.4261f64)?;
    /// assert_eq!(EventSearch::<f64>::new(start).window_start(), start);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn window_start(&self) -> UtcTime {
        self.window_start
    }

    /// Evaluates up to `budget` positions (at least one); `Ok(Some(_))`
    /// when the search is complete, `Ok(None)` when it needs more calls.
    /// After an error the search starts over on the next call.
    ///
    /// ```
    /// use sun_algos::geometry::events::{solar_day_start, DayKind, EventSearch};
    /// use sun_algos::{Algorithm, Options, Site};
    ///
    /// // 80° N in June: the sun never sets (polar day).
    /// let site = Site::new(80.0f64, 15.0)?;
    /// let mut sun = |t: &_| Algorithm::Spa.position(t, &site, &Options::default());
    /// let mut search = EventSearch::new(solar_day_start(2026, 6, 21, 15.0)?);
    /// // One position: not done yet.
    /// assert_eq!(search.step(&mut sun, 1)?, None);
    /// let ev = search.step(&mut sun, u32::MAX)?.expect("done");
    /// assert_eq!((ev.kind, ev.sunrise, ev.sunset, ev.daylight_s), (DayKind::PolarDay, None, None, 86_400));
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn step<F>(&mut self, sun: &mut F, budget: u32) -> Result<Option<Events<T>>, GeometryError>
    where
        F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
    {
        let r = self.advance(sun, budget.max(1));
        if r.is_err() {
            *self = EventSearch::new(self.window_start);
        }
        r
    }

    // Out of line on AVR: inlined into its caller (the scheduler's plan)
    // it costs that caller's frame its registers, and the Mega image
    // 1,740 B more; the Cortex-M images are 144-168 B smaller inlined.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn advance<F>(&mut self, sun: &mut F, budget: u32) -> Result<Option<Events<T>>, GeometryError>
    where
        F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
    {
        let w0 = self.window_start;
        // Each pass samples one position (the first of the transit search
        // none): first the instant it needs, then the one call of the
        // position source, then the stage updated in place. (One call site
        // and no rebuilt stage: on an 8-bit board each inlined call and
        // each copy of the stage cost hundreds of bytes.)
        for _ in 0..budget {
            let Some(s) = self.next_sample() else {
                continue;
            };
            // Height above the limit; positive when the sun is up.
            let v = height_at(sun, &w0.add_seconds_i32(s)?)?;
            if self.record(s, v) {
                return self.finish(s, v);
            }
        }
        Ok(None)
    }

    /// The instant the next pass samples, seconds after the window start;
    /// `None` for the pass that begins the transit search (it samples
    /// nothing). Narrows the transit search's bracket first.
    // Out of line on the AVR, as `record` and `finish`: apart from the
    // position source's closure, the stages keep `advance`'s frame within
    // `ldd`/`std` reach (with seconds after the window start in place of
    // instants, 396 B less in the ATmega2560 image).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn next_sample(&mut self) -> Option<i32> {
        let inv_phi = T::from_f64(INV_PHI);
        if let Stage::Golden { a, b, c, d, fc, fd } = &mut self.stage {
            // Narrow the bracket in place (no rebuilt stage); the new
            // interior point is sampled next.
            if let (Some(vc), Some(vd), true) = (*fc, *fd, *b - *a > T::ONE) {
                let old_c = *c;
                if vc >= vd {
                    // [a, d] with c as its upper point.
                    *b = *d;
                    *c = *b - inv_phi * (*b - *a);
                    *d = old_c;
                    *fd = Some(vc);
                    *fc = None;
                } else {
                    // [c, b] with d as its lower point.
                    *a = old_c;
                    *c = *d;
                    *d = old_c + inv_phi * (*b - old_c);
                    *fc = Some(vd);
                    *fd = None;
                }
            }
        }
        Some(match self.stage {
            Stage::Start => 0,
            Stage::Sample { i } if i < SAMPLES => i * STEP_S,
            Stage::Sample { .. } => {
                // Transit: golden-section search on the height over
                // ±1 step around the highest sample, to 1 s.
                let lo = (self.best_i - 1).max(0) * STEP_S;
                let hi = ((self.best_i + 1) * STEP_S).min(86_400);
                // 0 ≤ lo < hi ≤ 86 400: exact in T.
                let (a, b) = (T::from_i32(lo), T::from_i32(hi));
                self.stage = Stage::Golden {
                    a,
                    b,
                    c: b - inv_phi * (b - a),
                    d: a + inv_phi * (b - a),
                    fc: None,
                    fd: None,
                };
                return None;
            }
            Stage::Bisect { a, b, va, .. } => match va {
                _ if b - a > 1 => (a + b) / 2,
                // Then the two ends, to take the nearer whole second.
                None => a,
                Some(_) => b,
            },
            Stage::Golden { c, fc: None, .. } => round_s(c),
            Stage::Golden { d, fd: None, .. } => round_s(d),
            Stage::Golden { a, b, .. } => round_s((a + b) / T::from_f64(2.0)),
        })
    }

    /// Takes in the height `v` sampled `s` seconds after the window start;
    /// true when it is the transit search's last (the search is done).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn record(&mut self, s: i32, v: T) -> bool {
        // Whether the sun is up, compared once (each comparison is a call
        // of the soft-float library on an 8-bit board). Heights are finite
        // (`height_at`), so not above zero is at or below zero.
        let up = v > T::ZERO;
        match &mut self.stage {
            Stage::Start => {
                self.prev = v;
                self.any_up = up;
                self.best_i = 0;
                self.best_v = v;
                self.stage = Stage::Sample { i: 1 };
            }
            Stage::Sample { i } => {
                let i = *i;
                if v > self.best_v {
                    self.best_v = v;
                    self.best_i = i;
                }
                let was_up = self.prev > T::ZERO;
                let crossed_up = !was_up && up;
                let crossed_down = was_up && !up;
                self.any_up |= up;
                self.prev = v;
                self.stage = if (crossed_up && self.sunrise_s.is_none()) || crossed_down {
                    // Between the last two samples (0 < i < SAMPLES).
                    Stage::Bisect {
                        rising: crossed_up,
                        a: (i - 1) * STEP_S,
                        b: i * STEP_S,
                        va: None,
                        resume: i + 1,
                    }
                } else {
                    Stage::Sample { i: i + 1 }
                };
            }
            Stage::Bisect {
                rising,
                a,
                b,
                va,
                resume,
            } => {
                if *b - *a > 1 {
                    if up == *rising {
                        *b = s;
                    } else {
                        *a = s;
                    }
                } else if let Some(va) = *va {
                    // The nearer whole second to the crossing.
                    let t = Some(if va < v.abs() { *a } else { *b });
                    if *rising {
                        self.sunrise_s = t;
                    } else {
                        self.sunset_s = t;
                    }
                    self.stage = Stage::Sample { i: *resume };
                } else {
                    *va = Some(v.abs());
                }
            }
            Stage::Golden { fc: fc @ None, .. } => *fc = Some(v),
            Stage::Golden { fd: fd @ None, .. } => *fd = Some(v),
            Stage::Golden { .. } => return true,
        }
        false
    }

    /// The events once the transit is at `transit_s` with height
    /// `transit_v`, as [`EventSearch::advance`] returns them (built in its
    /// caller's result: no copy of the events in that caller's frame).
    // Out of line on the AVR: inlined, its events and times put
    // `advance`'s frame slots beyond `ldd`/`std` reach.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn finish(&self, transit_s: i32, transit_v: T) -> Result<Option<Events<T>>, GeometryError> {
        let limit = T::from_f64(90.0 + SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG);
        let window_start = self.window_start;
        let (rise_s, set_s) = (self.sunrise_s, self.sunset_s);
        // Instants already sampled (the additions succeeded then): `ok()`
        // drops no error.
        let at = |s: Option<i32>| s.and_then(|s| window_start.add_seconds_i32(s).ok());
        let transit = window_start.add_seconds_i32(transit_s)?;
        let end_s: i32 = 86_400;
        let (kind, daylight_s) = match (rise_s, set_s) {
            (None, None) if self.any_up => (DayKind::PolarDay, end_s),
            (None, None) => (DayKind::PolarNight, 0),
            (Some(r), Some(s)) if s > r => (DayKind::Normal, s - r),
            // Set then rose again (up at both ends of the window).
            (Some(r), Some(s)) => (DayKind::Normal, s + (end_s - r)),
            (Some(r), None) => (DayKind::Normal, end_s - r),
            (None, Some(s)) => (DayKind::Normal, s),
        };
        Ok(Some(Events {
            kind,
            window_start,
            sunrise: at(rise_s),
            transit,
            transit_zenith_deg: limit - transit_v,
            sunset: at(set_s),
            daylight_s: daylight_s.clamp(0, end_s) as u32,
        }))
    }
}

/// The sun's height above the event limit (90.833° of zenith; degrees,
/// positive when it is up) at `t`. Not inlined: the one call of the
/// position source in [`EventSearch`]'s loop.
#[inline(never)]
fn height_at<T: Float, F>(sun: &mut F, t: &UtcTime) -> Result<T, GeometryError>
where
    F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
{
    let p = sun(t)?;
    if !p.zenith_deg.is_finite() {
        return Err(GeometryError::NotFinite);
    }
    Ok(T::from_f64(90.0 + SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG) - p.zenith_deg)
}

/// 1/φ, the golden-section ratio.
const INV_PHI: f64 = 0.618_033_988_749_895;

/// A second of the window, `0 ≤ s ≤ 86 400`, rounded to the nearest whole
/// one (halves up), through `f32` (exact for these whole numbers).
fn round_s<T: Float>(s: T) -> i32 {
    (s + T::from_f64(0.5)).floor().to_f32() as i32
}

/// Precise events of the local solar day of date `(y, m, d)` at `site` with
/// `algorithm`. Positions are geometric (any atmosphere in `options` is
/// ignored): the horizon limit already holds the standard refraction.
///
/// ```
/// use sun_algos::geometry::events::for_algorithm;
/// use sun_algos::{Algorithm, Options, Site, UtcTime};
///
/// // The NREL SPA report's site (39.742476° N, 105.1786° W, 1830.14 m, ΔT
/// // 67 s) on its example day, 2003-10-17 (local time UTC−7).
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
/// let ev = for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
/// // Sunrise: the report's 6.212067 h local, 13:12:43.44 UT, to ±1 s.
/// let want_rise: UtcTime = "2003-10-17T13:12:43.440Z".parse()?;
/// let rise = ev.sunrise.expect("a sunrise");
/// assert!((rise.unix_seconds() - want_rise.unix_seconds()).abs() <= 1);
/// // Sunset of that local day: pvlib 0.16.1's spa_python puts the zenith at
/// // 90.8335° at 2003-10-18T00:18:51Z, on the horizon limit 90.8333°.
/// let want_set: UtcTime = "2003-10-18T00:18:51Z".parse()?;
/// let set = ev.sunset.expect("a sunset");
/// assert!((set.unix_seconds() - want_set.unix_seconds()).abs() <= 1);
/// // Grena 2008 (ENEA, 0.0027°) agrees to a few seconds.
/// let enea = for_algorithm(Algorithm::Grena2008, (2003, 10, 17), &site, &opts)?;
/// assert!((enea.sunrise.unwrap().unix_seconds() - rise.unix_seconds()).abs() <= 5);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
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
///
/// ```
/// use sun_algos::geometry::events;
/// use sun_algos::{Options, Site, UtcTime};
///
/// // The NREL SPA report's site (39.742476° N, 105.1786° W, 1830.14 m, ΔT
/// // 67 s) on its example day, 2003-10-17 (local time UTC−7).
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
/// let ev = events::spa((2003, 10, 17), &site, &opts)?;
/// // The report's sunrise 6.212067 h and transit 11.768045 h local time are
/// // 13:12:43.441 and 18:46:04.962 UT; its sunset 17.338667 h local is this UT
/// // day's 00:20:19.201 (the evening of 16 October, local time).
/// for (got, want) in [
///     (ev.sunrise.unwrap(), "2003-10-17T13:12:43.441Z"),
///     (ev.transit, "2003-10-17T18:46:04.962Z"),
///     (ev.sunset.unwrap(), "2003-10-17T00:20:19.201Z"),
/// ] {
///     let want: UtcTime = want.parse()?;
///     assert!((got.unix_seconds() * 1000 + i64::from(got.ms_of_day() % 1000)
///         - want.unix_seconds() * 1000 - i64::from(want.ms_of_day() % 1000)).abs() < 100);
/// }
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
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
    fn poles_follow_the_paper_rules() {
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

    /// Kano (the site of Jimoh & Aliyu 2019), Tromsø in polar day and in polar
    /// night, and 66° N in June (the sun grazes the horizon).
    fn days() -> [(f64, f64, (i32, u8, u8)); 4] {
        [
            (11.9683, 8.4261, (2026, 3, 20)),
            (69.6492, 18.9553, (2026, 6, 21)),
            (69.6492, 18.9553, (2026, 12, 21)),
            (66.0, -20.0, (2026, 6, 10)),
        ]
    }

    #[test]
    fn search_in_small_steps_equals_find() {
        for (lat, lon, ymd) in days() {
            for algorithm in [Algorithm::Psa2020, Algorithm::Spa] {
                let site = Site::new(lat, lon).unwrap();
                let opts = Options::default();
                let whole = for_algorithm(algorithm, ymd, &site, &opts).unwrap();
                let start = solar_day_start(ymd.0, ymd.1, ymd.2, lon).unwrap();
                for budget in [1u32, 7] {
                    let mut calls = 0u32;
                    let mut sun = |t: &UtcTime| {
                        calls += 1;
                        algorithm.position(t, &site, &opts)
                    };
                    let mut search = EventSearch::new(start);
                    let mut steps = 0u32;
                    let got = loop {
                        steps += 1;
                        if let Some(e) = search.step(&mut sun, budget).unwrap() {
                            break e;
                        }
                    };
                    assert_eq!(got, whole, "{lat} {lon} {ymd:?} budget {budget}");
                    // Never more than the budget per call, and no call
                    // wasted (one stage change evaluates nothing).
                    assert!(calls <= steps * budget, "{calls} in {steps}");
                    assert!(steps <= calls.div_ceil(budget) + 1, "{calls} in {steps}");
                    // About 190 positions in all (module documentation).
                    assert!((150..=220).contains(&calls), "{calls} positions");
                }
            }
        }
    }

    /// The events stay whole seconds after a window start with a fraction
    /// of a second: a made-up sun whose height above the limit rises and
    /// falls by 1° a minute, 0 at 34 000.4 s and 46 000.4 s after the
    /// start and highest (100°) at 40 000.4 s (hand computation: the
    /// nearer whole seconds are 34 000 and 46 000, 12 000 s of daylight).
    #[test]
    fn events_are_whole_seconds_after_the_window_start() {
        let start: UtcTime = "2026-06-21T00:00:00.500Z".parse().unwrap();
        let limit = 90.0 + SUN_RADIUS_PLUS_HORIZON_REFRACTION_DEG;
        let sun = |t: &UtcTime| {
            let s = f64::from(t.seconds_since(&start).unwrap());
            let height = 100.0 - (s - 40_000.4).abs() / 60.0;
            Ok(SunPosition::new(limit - height, 180.0, false))
        };
        let ev = find(start, sun).unwrap();
        let after = |s| start.add_seconds_i32(s).unwrap();
        assert_eq!(ev.kind, DayKind::Normal);
        assert_eq!(ev.sunrise, Some(after(34_000)));
        assert_eq!(ev.sunset, Some(after(46_000)));
        assert_eq!(ev.daylight_s, 12_000);
        let transit_s = ev.transit.seconds_since(&start).unwrap();
        assert!((transit_s - 40_000).abs() <= 1, "{transit_s}");
        assert_eq!(ev.transit, after(transit_s));
    }

    #[test]
    fn search_starts_over_after_an_error() {
        let (lat, lon, ymd) = days()[0];
        let site = Site::new(lat, lon).unwrap();
        let opts = Options::default();
        let whole = for_algorithm(Algorithm::Psa2020, ymd, &site, &opts).unwrap();
        let start = solar_day_start(ymd.0, ymd.1, ymd.2, lon).unwrap();
        let mut calls = 0u32;
        // The 50th position fails once.
        let mut sun = |t: &UtcTime| {
            calls += 1;
            if calls == 50 {
                Err(crate::Error::InvalidDate)
            } else {
                Algorithm::Psa2020.position(t, &site, &opts)
            }
        };
        let mut search = EventSearch::new(start);
        let mut failed = 0;
        let got = loop {
            match search.step(&mut sun, 10) {
                Ok(Some(e)) => break e,
                Ok(None) => {}
                Err(e) => {
                    assert_eq!(e, GeometryError::Position(crate::Error::InvalidDate));
                    failed += 1;
                }
            }
        };
        assert_eq!((got, failed), (whole, 1));
    }
}
