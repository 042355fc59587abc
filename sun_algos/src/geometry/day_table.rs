//! The day table: set-points every N minutes from sunrise to sunset.
//!
//! Jimoh & Aliyu (2019, §2.2.4, steps 7–8) compute the optimum slope and
//! azimuth every 4 minutes between sunrise and sunset once a day and keeps
//! them in the microcontroller; the scheduler then looks the current time up.
//!
//! Layout, chosen for 8-bit boards: entry times are implicit (first instant
//! plus k × interval, aligned to whole multiples of the interval since UTC
//! midnight so an RTC minute matches), and each [`Entry`] is 4 bytes, slope
//! and surface azimuth in centidegrees. The capacity `N` is a const generic
//! chosen per board; the worst case is a polar day, 24 h, which needs
//! [`capacity_for_interval`] entries: 361 at 4 minutes.
//!
//! RAM of `DayTable<N>` = 4·N + 14 bytes (4-byte entries, 8-byte first
//! instant, 2-byte interval, 2-byte length, 2-byte length once complete; no
//! padding on AVR, 2 bytes of it on 32- and 64-bit targets; checked on the
//! host by `size_of` in `tests/geometry_day_table.rs`):
//! - `DayTable<361>` (4 min, polar day): 1458 B — fits an ATmega328P's
//!   2048 B only with ~590 B left for stack and the rest of the firmware;
//! - `DayTable<181>` (8 min, polar day) 738 B, or `DayTable<211>` (4 min, up
//!   to 14 h of daylight: |φ| ≲ 30°, e.g. Kano's longest day is 12 h 50 min)
//!   858 B — the sizes we suggest for the ATmega328P; a longer day gives
//!   [`GeometryError::CapacityExceeded`], never a truncated table;
//! - Cortex-M boards: `DayTable<361>` (or `<1441>` at 1 minute, 5776 B).
//!
//! # Example
//!
//! ```
//! use sun_algos::geometry::day_table::{capacity_for_interval, DayTable};
//! use sun_algos::geometry::{events, Limits};
//! use sun_algos::{Algorithm, Options, Site};
//!
//! // Kano (11.9683° N) on the June solstice, every 4 minutes in f32: about
//! // 12 h 50 min of daylight (the module text above), so a 211-entry table
//! // suffices and a 361-entry one covers any day.
//! const N: usize = capacity_for_interval(4);
//! let site = Site::new(11.9683f32, 8.4261)?;
//! let sun = |t: &_| Algorithm::Michalsky.position(t, &site, &Options::default());
//! let ev = events::find(events::solar_day_start(2026, 6, 21, 8.4261f32)?, sun)?;
//! let table: DayTable<N> = DayTable::compute(&ev, 4, &Limits::upward(), sun)?;
//! assert!(table.len() > 180 && table.len() <= 211, "{}", table.len());
//! assert_eq!(core::mem::size_of::<DayTable<N>>(), 4 * N + 16);
//! # Ok::<(), sun_algos::geometry::GeometryError>(())
//! ```

use heapless::Vec;

use crate::float::Float;
use crate::position::SunPosition;
use crate::time::UtcTime;

use super::events::Events;
use super::incidence::Surface;
use super::optimum::{best_surface_within, Limits};
use super::GeometryError;

/// One set-point: slope and surface azimuth (east of north) in 0.01°.
///
/// ```
/// use sun_algos::geometry::{day_table::Entry, Surface};
///
/// // Four bytes: slope and azimuth in centidegrees.
/// let e = Entry::from_surface(&Surface::new(49.049_237f64, 179.319_573)?);
/// assert_eq!((e.slope_cdeg(), e.azimuth_cdeg()), (4905, 17932));
/// assert_eq!(core::mem::size_of::<Entry>(), 4);
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Entry {
    slope_cdeg: i16,
    azimuth_cdeg: u16,
}

impl Entry {
    /// Rounds a surface to centidegrees (slope clamped to ±180°, azimuth
    /// folded into 0…359.99°). Never panics; NaN becomes 0.
    ///
    /// ```
    /// use sun_algos::geometry::{day_table::Entry, Surface};
    ///
    /// // Rounded to the nearest 0.01°; the azimuth folded into 0…359.99°.
    /// let e = Entry::from_surface(&Surface { slope_deg: 45.126f64, azimuth_deg: -10.0 });
    /// assert_eq!((e.slope_cdeg(), e.azimuth_cdeg()), (4513, 35000));
    /// let e = Entry::from_surface(&Surface { slope_deg: f32::NAN, azimuth_deg: 359.999 });
    /// assert_eq!((e.slope_cdeg(), e.azimuth_cdeg()), (0, 0));
    /// ```
    pub fn from_surface<T: Float>(surface: &Surface<T>) -> Self {
        // Rounded exactly from the value's own bits (in T, never through
        // f64): ⌊|s|·100 + ½⌋ with the sign put back, halves away from 0.
        let s = surface
            .slope_deg
            .clamp(T::from_f64(-180.0), T::from_f64(180.0));
        // |s| ≤ 180°: at most 18 000, below the turn it is reduced by.
        let c = s.abs().centi_round_mod_turn() as i16;
        let slope_cdeg = if s < T::ZERO { -c } else { c };
        // ⌊a·100 + ½⌋ taken modulo a turn equals folding a into 0…360°
        // first and rounding its hundredfold halves up.
        let azimuth_cdeg = surface.azimuth_deg.centi_round_mod_turn() as u16;
        Entry {
            slope_cdeg,
            azimuth_cdeg,
        }
    }

    /// An entry from its centidegrees, `None` outside what
    /// [`Entry::from_surface`] gives (slope −18 000…18 000, azimuth
    /// 0…35 999).
    #[cfg(feature = "serde")]
    pub(crate) fn from_cdeg(slope_cdeg: i16, azimuth_cdeg: u16) -> Option<Self> {
        if slope_cdeg.unsigned_abs() > 18_000 || azimuth_cdeg >= 36_000 {
            return None;
        }
        Some(Entry {
            slope_cdeg,
            azimuth_cdeg,
        })
    }

    /// Slope in centidegrees.
    ///
    /// ```
    /// use sun_algos::geometry::{day_table::Entry, Surface};
    ///
    /// assert_eq!(Entry::from_surface(&Surface::new(-12.344f64, 0.0)?).slope_cdeg(), -1234);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn slope_cdeg(&self) -> i16 {
        self.slope_cdeg
    }
    /// Surface azimuth east of north in centidegrees, 0…35 999.
    ///
    /// ```
    /// use sun_algos::geometry::{day_table::Entry, Surface};
    ///
    /// assert_eq!(Entry::from_surface(&Surface::new(30.0f64, 194.340_241)?).azimuth_cdeg(), 19434);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn azimuth_cdeg(&self) -> u16 {
        self.azimuth_cdeg
    }
    /// The set-point as a surface in degrees.
    ///
    /// ```
    /// use sun_algos::geometry::{day_table::Entry, Surface};
    ///
    /// let e = Entry::from_surface(&Surface::new(30.004f64, 170.0)?);
    /// let s: Surface<f32> = e.surface();
    /// assert_eq!((s.slope_deg, s.azimuth_deg), (30.0, 170.0));
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn surface<T: Float>(&self) -> Surface<T> {
        Surface {
            slope_deg: T::from_i32(i32::from(self.slope_cdeg)) / T::from_f64(100.0),
            azimuth_deg: T::from_u32(u32::from(self.azimuth_cdeg)) / T::from_f64(100.0),
        }
    }
}

/// How [`DayTable::fill`] and [`DayTable::fill_facing`] turn a sun position
/// into an entry's surface.
type SurfaceOf<'a, T> = dyn Fn(&SunPosition<T>) -> Result<Surface<T>, GeometryError> + 'a;

/// Entries a table needs for a 24-hour day (polar day) at `interval_min`:
/// 1440 / interval + 1.
///
/// ```
/// use sun_algos::geometry::day_table::{capacity_for_interval, DayTable};
///
/// // 24 h every 4 minutes: 1440 / 4 + 1 = 361 entries; every minute 1441.
/// assert_eq!(capacity_for_interval(4), 361);
/// assert_eq!(capacity_for_interval(1), 1441);
/// assert_eq!(capacity_for_interval(0), 0);
/// // Sized at compile time.
/// const N: usize = capacity_for_interval(8);
/// let _table: DayTable<N> = DayTable::empty(sun_algos::UtcTime::MIDNIGHT_2000);
/// assert_eq!(N, 181);
/// ```
pub const fn capacity_for_interval(interval_min: u16) -> usize {
    if interval_min == 0 {
        0
    } else {
        1440 / interval_min as usize + 1
    }
}

/// True for a table interval of 1…720 minutes that divides a day.
pub(crate) const fn interval_is_valid(interval_min: u16) -> bool {
    interval_min != 0 && interval_min <= 720 && 1440 % interval_min == 0
}

/// Set-points of one day at a fixed interval.
///
/// ```
/// use sun_algos::geometry::day_table::DayTable;
/// use sun_algos::geometry::{events, Limits};
/// use sun_algos::{Algorithm, Options, Site, UtcTime};
///
/// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
/// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
/// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
/// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
/// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
/// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
/// let table: DayTable<361> = DayTable::compute(&ev, 4, &Limits::upward(), sun)?;
/// // Sunrise 13:12:43 UT (the report's 6.212067 h local) and sunset
/// // 00:18:51 UT (see events::find): the 4-minute grid runs from 13:16 to
/// // 00:16, 660 min / 4 + 1 = 166 entries (hand count).
/// assert_eq!(table.len(), 166);
/// assert_eq!(table.first_time().to_string(), "2003-10-17T13:16:00Z");
/// // The entry of 18:44 UT is the sun's direction then: pvlib 0.16.1's
/// // spa_python (geometric) gives zenith 49.049237°, azimuth 179.319573°.
/// let t: UtcTime = "2003-10-17T18:45:30Z".parse()?;
/// let (at, entry) = table.at(&t).expect("in the day");
/// assert_eq!(at.to_string(), "2003-10-17T18:44:00Z");
/// assert_eq!((entry.slope_cdeg(), entry.azimuth_cdeg()), (4905, 17932));
/// # Ok::<(), sun_algos::geometry::GeometryError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DayTable<const N: usize> {
    first: UtcTime,
    interval_min: u16,
    entries: Vec<Entry, N, u16>,
    /// Entries the table will hold once complete ([`DayTable::begin`]).
    needed: u16,
}

impl<const N: usize> DayTable<N> {
    /// Computes the table from sunrise to sunset of `events` (whole day for
    /// a polar day, empty for a polar night) every `interval_min` minutes
    /// (1…720, dividing 1440), each entry the best set-point within
    /// `limits` for the position `sun` gives (any algorithm, f32 or f64).
    ///
    /// When the sun sets and rises again inside the window (only near the
    /// polar circles), the table covers the whole window.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let table: DayTable<361> = DayTable::compute(&ev, 4, &Limits::upward(), sun)?;
    /// // Sunrise 13:12:43 UT (the report's 6.212067 h local) and sunset
    /// // 00:18:51 UT (see events::find): the 4-minute grid runs from 13:16 to
    /// // 00:16, 660 min / 4 + 1 = 166 entries (hand count).
    /// assert_eq!(table.len(), 166);
    /// assert!(table.is_complete());
    /// // Too small a table is an error, not a truncated day.
    /// let small = DayTable::<100>::compute(&ev, 4, &Limits::upward(), sun);
    /// assert_eq!(
    ///     small.err(),
    ///     Some(sun_algos::geometry::GeometryError::CapacityExceeded { needed: 166, capacity: 100 })
    /// );
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn compute<T, F>(
        events: &Events<T>,
        interval_min: u16,
        limits: &Limits<T>,
        sun: F,
    ) -> Result<Self, GeometryError>
    where
        T: Float,
        F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
    {
        let mut table = DayTable::empty(events.window_start);
        table.recompute(events, interval_min, limits, sun)?;
        Ok(table)
    }

    /// A table without entries whose first instant is `first`.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::UtcTime;
    ///
    /// let t = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    /// assert!(t.is_empty() && t.is_complete());
    /// assert_eq!(t.at(&UtcTime::MIDNIGHT_2000), None);
    /// ```
    pub fn empty(first: UtcTime) -> Self {
        DayTable {
            first,
            interval_min: 1,
            entries: Vec::new(),
            needed: 0,
        }
    }

    /// [`DayTable::compute`] into this table's storage, in place: no second
    /// table on the stack (1.4 KB at 360 entries, which an 8-bit board's
    /// RAM cannot spare). On an error the table is left empty.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// // One table, refilled in place each day.
    /// let mut table = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    /// table.recompute(&ev, 4, &Limits::upward(), sun)?;
    /// // Sunrise 13:12:43 UT (the report's 6.212067 h local) and sunset
    /// // 00:18:51 UT (see events::find): the 4-minute grid runs from 13:16 to
    /// // 00:16, 660 min / 4 + 1 = 166 entries (hand count).
    /// assert_eq!(table.len(), 166);
    /// // An interval that does not divide the day leaves it empty.
    /// assert!(table.recompute(&ev, 7, &Limits::upward(), sun).is_err());
    /// assert!(table.is_empty());
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn recompute<T, F>(
        &mut self,
        events: &Events<T>,
        interval_min: u16,
        limits: &Limits<T>,
        mut sun: F,
    ) -> Result<(), GeometryError>
    where
        T: Float,
        F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
    {
        self.begin(events, interval_min)?;
        while !self.fill(limits, &mut sun, usize::MAX)? {}
        Ok(())
    }

    /// Empties the table and sets it up for `events` every `interval_min`
    /// minutes (as [`DayTable::compute`]) without computing an entry:
    /// [`DayTable::fill`] then computes them a few at a time. Errors (and
    /// leaves the table empty) for an interval that does not divide a day or
    /// a daylight longer than the capacity.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let mut table = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    /// table.begin(&ev, 4)?;
    /// // Set up, nothing computed yet.
    /// assert_eq!((table.len(), table.is_complete()), (0, false));
    /// assert_eq!(table.first_time().to_string(), "2003-10-17T13:16:00Z");
    /// assert_eq!(
    ///     table.begin(&ev, 0),
    ///     Err(sun_algos::geometry::GeometryError::InvalidInterval)
    /// );
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn begin<T: Float>(
        &mut self,
        events: &Events<T>,
        interval_min: u16,
    ) -> Result<(), GeometryError> {
        self.begin_daylight(events.window_start, &events.daylight(), interval_min)
    }

    /// [`DayTable::begin`] for the daylight `daylight` of the window
    /// starting at `window_start`, as [`Events::daylight`] gives it (its
    /// error returned after the interval's): for a caller that has the
    /// daylight already.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::events;
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let mut table = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    /// table.begin_daylight(ev.window_start, &ev.daylight(), 4)?;
    /// // The first 4-minute mark after sunrise (13:12:43 UT), as `begin`.
    /// assert_eq!(table.first_time().to_string(), "2003-10-17T13:16:00Z");
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn begin_daylight(
        &mut self,
        window_start: UtcTime,
        daylight: &Result<Option<(UtcTime, UtcTime)>, GeometryError>,
        interval_min: u16,
    ) -> Result<(), GeometryError> {
        self.entries.clear();
        self.needed = 0;
        if !interval_is_valid(interval_min) {
            return Err(GeometryError::InvalidInterval);
        }
        // A valid interval is at most 720 min: the step fits an i32.
        let step = i32::from(interval_min) * 60;
        // Seconds from the UTC midnight the window starts in: whole steps
        // from there are whole steps of the UTC (and Unix) time scale, as
        // a step divides a day. In 32-bit arithmetic: the events lie within
        // two days of it.
        let midnight = window_start.start_of_day();
        let rel = |t: UtcTime| t.seconds_since(&midnight).ok_or(crate::Error::InvalidDate);
        let (from, to) = match *daylight {
            Ok(Some((from, to))) => (rel(from)?, rel(to)?),
            // Polar night: no step from `from` to `to`.
            Ok(None) => {
                let w0 = rel(window_start)?;
                (w0, w0 - 1)
            }
            Err(e) => return Err(e),
        };
        // The first whole step at or after `from`, the last at or before
        // `to` (|from|, |to| < 2^31 − step: no overflow).
        // Checked, though the step is not 0 here: the divisions then carry
        // no divide-by-zero panic where the optimiser does not see that
        // (opt-level "z").
        let (Some(from_k), Some(from_r), Some(last_k)) = (
            from.checked_div_euclid(step),
            from.checked_rem_euclid(step),
            to.checked_div_euclid(step),
        ) else {
            return Err(GeometryError::InvalidInterval);
        };
        let first_k = from_k + i32::from(from_r != 0);
        // Steps from the first to the last, both included (none if negative).
        let count = last_k - first_k + 1;
        let needed = usize::try_from(count).unwrap_or(0);
        if needed > N {
            return Err(GeometryError::CapacityExceeded {
                needed,
                capacity: N,
            });
        }
        self.first = midnight.add_seconds_i32(first_k * step)?;
        self.interval_min = interval_min;
        // needed ≤ N ≤ u16::MAX (the entries' length type).
        self.needed = u16::try_from(needed).unwrap_or(u16::MAX);
        Ok(())
    }

    /// Computes up to `budget` more entries (at least one) of the table
    /// [`DayTable::begin`] set up; true once it is complete. On an error
    /// the table is left empty (and complete: call `begin` again).
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let mut table = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    /// table.begin(&ev, 4)?;
    /// // Ten set-points per call, as a slow main loop would compute them.
    /// let (mut calls, mut source) = (0, sun);
    /// while !table.fill(&Limits::upward(), &mut source, 10)? {
    ///     calls += 1;
    /// }
    /// // Sunrise 13:12:43 UT (the report's 6.212067 h local) and sunset
    /// // 00:18:51 UT (see events::find): the 4-minute grid runs from 13:16 to
    /// // 00:16, 660 min / 4 + 1 = 166 entries (hand count).
    /// assert_eq!((table.len(), calls), (166, 16));
    /// assert_eq!(table, DayTable::compute(&ev, 4, &Limits::upward(), sun)?);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn fill<T, F>(
        &mut self,
        limits: &Limits<T>,
        sun: &mut F,
        budget: usize,
    ) -> Result<bool, GeometryError>
    where
        T: Float,
        F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
    {
        self.fill_with(sun, budget, &|p: &SunPosition<T>| {
            best_surface_within(p, limits)
        })
    }

    /// [`DayTable::fill`] with set-points facing the sun (slope = zenith,
    /// surface azimuth = the sun's: Jimoh & Aliyu 2019, eq. 14 with γ = γs,
    /// whose root is β = θz, see [`super::optimum`]), exactly: what
    /// `fill` with [`Limits::unconstrained`] approximates by its sines,
    /// cosines and arctangent. Errors for a non-finite position.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let mut sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let mut table = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    /// table.begin(&ev, 4)?;
    /// while !table.fill_facing(&mut sun, 10)? {}
    /// // The entry of 18:44 UT is the sun's direction then: pvlib 0.16.1's
    /// // spa_python (geometric) gives zenith 49.049237°, azimuth 179.319573°.
    /// let t: UtcTime = "2003-10-17T18:45:30Z".parse()?;
    /// let (_, entry) = table.at(&t).expect("in the day");
    /// assert_eq!((entry.slope_cdeg(), entry.azimuth_cdeg()), (4905, 17932));
    /// // The same table as the unconstrained optimum's (in f64).
    /// let free: DayTable<361> = DayTable::compute(&ev, 4, &Limits::unconstrained(), sun)?;
    /// assert_eq!(table, free);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn fill_facing<T, F>(&mut self, sun: &mut F, budget: usize) -> Result<bool, GeometryError>
    where
        T: Float,
        F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
    {
        self.fill_with(sun, budget, &|p: &SunPosition<T>| {
            if !p.zenith_deg.is_finite() || !p.azimuth_deg.is_finite() {
                return Err(GeometryError::NotFinite);
            }
            Ok(Surface {
                slope_deg: p.zenith_deg.clamp(T::ZERO, T::from_f64(180.0)),
                azimuth_deg: p.azimuth_deg,
            })
        })
    }

    /// `fill` with each entry's surface given by `surface`. Out of line on
    /// AVR, as `EventSearch`'s loop: inlined into the scheduler's plan it
    /// cost the Mega image 112 B (420 B with `best_surface_within`), while
    /// the Cortex-M images are smaller with it inlined.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn fill_with<T, F>(
        &mut self,
        sun: &mut F,
        budget: usize,
        surface: &SurfaceOf<'_, T>,
    ) -> Result<bool, GeometryError>
    where
        T: Float,
        F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
    {
        let needed = usize::from(self.needed);
        let mut fill_some = || {
            for _ in 0..budget.max(1) {
                let k = self.entries.len();
                if k >= needed {
                    break;
                }
                let t = self.offset(k).ok_or(crate::Error::InvalidDate)?;
                let p = sun(&t)?;
                self.entries
                    .push(Entry::from_surface(&surface(&p)?))
                    .map_err(|_| GeometryError::CapacityExceeded {
                        needed,
                        capacity: N,
                    })?;
            }
            Ok(self.entries.len() >= needed)
        };
        let result = fill_some();
        if result.is_err() {
            self.entries.clear();
            self.needed = 0;
        }
        result
    }

    /// True once every entry [`DayTable::begin`] set up is computed.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let mut table = DayTable::<361>::empty(UtcTime::MIDNIGHT_2000);
    /// table.begin(&ev, 60)?;
    /// let mut source = sun;
    /// assert!(!table.fill(&Limits::upward(), &mut source, 1)? && !table.is_complete());
    /// while !table.fill(&Limits::upward(), &mut source, 1)? {}
    /// assert!(table.is_complete());
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn is_complete(&self) -> bool {
        self.entries.len() >= usize::from(self.needed)
    }

    /// Number of entries.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// // Hourly from 14:00 to 00:00 UT (sunrise 13:12:43, sunset 00:18:51): 11.
    /// let table: DayTable<25> = DayTable::compute(&ev, 60, &Limits::upward(), sun)?;
    /// assert_eq!(table.len(), 11);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn len(&self) -> usize {
        self.entries.len()
    }
    /// True for a polar night (no entries).
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site};
    ///
    /// // 80° S in June: polar night, no set-points.
    /// let site = Site::new(-80.0f64, 0.0)?;
    /// let sun = |t: &_| Algorithm::Spa.position(t, &site, &Options::default());
    /// let ev = events::for_algorithm(Algorithm::Spa, (2026, 6, 21), &site, &Options::default())?;
    /// let table: DayTable<361> = DayTable::compute(&ev, 4, &Limits::upward(), sun)?;
    /// assert!(table.is_empty());
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
    /// Interval between entries, minutes.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let table: DayTable<181> = DayTable::compute(&ev, 8, &Limits::upward(), sun)?;
    /// assert_eq!(table.interval_min(), 8);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn interval_min(&self) -> u16 {
        self.interval_min
    }
    /// Instant of the first entry.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let table: DayTable<361> = DayTable::compute(&ev, 4, &Limits::upward(), sun)?;
    /// // The first 4-minute mark after sunrise (13:12:43 UT).
    /// assert_eq!(table.first_time().to_string(), "2003-10-17T13:16:00Z");
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn first_time(&self) -> UtcTime {
        self.first
    }

    /// Entry `i` with its instant, `None` past the end.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let table: DayTable<361> = DayTable::compute(&ev, 4, &Limits::upward(), sun)?;
    /// // Entry 157 is 13:16 + 157 × 4 min = 23:44 UT.
    /// let (t, _) = table.get(157).expect("inside the day");
    /// assert_eq!(t.to_string(), "2003-10-17T23:44:00Z");
    /// assert_eq!(table.get(166), None);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn get(&self, i: usize) -> Option<(UtcTime, Entry)> {
        let e = *self.entries.get(i)?;
        Some((self.offset(i)?, e))
    }

    /// The time of entry `i`: `i` intervals after the first. `None` when
    /// that is outside the calendar; an `i` of at most `u16::MAX` (a
    /// table's length) times a valid interval (≤ 43 200 s) stays below
    /// 2^32, so the product is computed in 32 bits.
    fn offset(&self, i: usize) -> Option<UtcTime> {
        let i = u32::try_from(i)
            .ok()
            .filter(|&i| i <= u32::from(u16::MAX))?;
        let s = i * (u32::from(self.interval_min.min(720)) * 60);
        self.first.add_seconds_i32(i32::try_from(s).ok()?).ok()
    }

    /// The entry in force at `time`: the last one at or before it; `None`
    /// before the first entry or from one interval after the last on.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let table: DayTable<361> = DayTable::compute(&ev, 4, &Limits::upward(), sun)?;
    /// // At 16:01:59 the 16:00 set-point is in force: pvlib 0.16.1's spa_python
    /// // (geometric) gives zenith 62.274910°, azimuth 132.336086° then.
    /// let (at, e) = table.at(&"2003-10-17T16:01:59Z".parse()?).expect("daytime");
    /// assert_eq!(at.to_string(), "2003-10-17T16:00:00Z");
    /// assert_eq!((e.slope_cdeg(), e.azimuth_cdeg()), (6227, 13234));
    /// // Before sunrise: none.
    /// assert_eq!(table.at(&"2003-10-17T12:00:00Z".parse()?), None);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn at(&self, time: &UtcTime) -> Option<(UtcTime, Entry)> {
        let dt = u32::try_from(time.seconds_since(&self.first)?).ok()?;
        let i = dt.checked_div(u32::from(self.interval_min) * 60)?;
        self.get(usize::try_from(i).ok()?)
    }

    /// The stored fields: first instant, interval, entries needed, entries.
    #[cfg(feature = "serde")]
    pub(crate) fn parts(&self) -> (UtcTime, u16, u16, &Vec<Entry, N, u16>) {
        (self.first, self.interval_min, self.needed, &self.entries)
    }

    /// A table from fields already checked (a valid interval, at most
    /// `needed ≤ N` entries).
    #[cfg(feature = "serde")]
    pub(crate) fn from_parts(
        first: UtcTime,
        interval_min: u16,
        needed: u16,
        entries: Vec<Entry, N, u16>,
    ) -> Self {
        DayTable {
            first,
            interval_min,
            entries,
            needed,
        }
    }

    /// Entries with their instants, in time order.
    ///
    /// ```
    /// use sun_algos::geometry::day_table::DayTable;
    /// use sun_algos::geometry::{events, Limits};
    /// use sun_algos::{Algorithm, Options, Site, UtcTime};
    ///
    /// // The NREL SPA report's site and day (39.742476° N, 105.1786° W, 1830.14 m,
    /// // ΔT 67 s, 2003-10-17), set-points every 4 minutes.
    /// let site = Site::with_elevation(39.742476f64, -105.1786, 1830.14)?;
    /// let opts = Options { delta_t_s: Some(67.0), ..Options::default() };
    /// let sun = |t: &UtcTime| Algorithm::Spa.position(t, &site, &opts);
    /// let ev = events::for_algorithm(Algorithm::Spa, (2003, 10, 17), &site, &opts)?;
    /// let table: DayTable<361> = DayTable::compute(&ev, 4, &Limits::upward(), sun)?;
    /// // The slope follows the zenith: highest sun (smallest slope) near the
    /// // transit, 18:46 UT.
    /// let (noon, _) = table.iter().min_by_key(|(_, e)| e.slope_cdeg()).unwrap();
    /// assert!((noon.unix_seconds() - ev.transit.unix_seconds()).abs() <= 4 * 60);
    /// assert_eq!(table.iter().count(), 166);
    /// # Ok::<(), sun_algos::geometry::GeometryError>(())
    /// ```
    pub fn iter(&self) -> impl Iterator<Item = (UtcTime, Entry)> + '_ {
        (0..self.entries.len()).filter_map(move |i| self.get(i))
    }
}
