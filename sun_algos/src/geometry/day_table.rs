//! The day table: set-points every N minutes from sunrise to sunset.
//!
//! Seed jimoh-2019 (§2.2.4, steps 7–8) computes the optimum slope and
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

use heapless::Vec;

use crate::float::Float;
use crate::position::SunPosition;
use crate::time::UtcTime;

use super::events::{DayKind, Events};
use super::incidence::Surface;
use super::optimum::{best_within, Limits};
use super::GeometryError;

/// One set-point: slope and surface azimuth (east of north) in 0.01°.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Entry {
    slope_cdeg: i16,
    azimuth_cdeg: u16,
}

impl Entry {
    /// Rounds a surface to centidegrees (slope clamped to ±180°, azimuth
    /// folded into 0…359.99°). Never panics; NaN becomes 0.
    pub fn from_surface<T: Float>(surface: &Surface<T>) -> Self {
        let s = surface.slope_deg.to_f64().clamp(-180.0, 180.0) * 100.0;
        let a = surface.azimuth_deg.to_f64().rem_euclid(360.0) * 100.0;
        let slope_cdeg = round_i64(s) as i16;
        let az = round_i64(a);
        let azimuth_cdeg = if az >= 36_000 { 0 } else { az as u16 };
        Entry {
            slope_cdeg,
            azimuth_cdeg,
        }
    }

    /// Slope in centidegrees.
    pub fn slope_cdeg(&self) -> i16 {
        self.slope_cdeg
    }
    /// Surface azimuth east of north in centidegrees, 0…35 999.
    pub fn azimuth_cdeg(&self) -> u16 {
        self.azimuth_cdeg
    }
    /// The set-point as a surface in degrees.
    pub fn surface<T: Float>(&self) -> Surface<T> {
        Surface {
            slope_deg: T::from_i32(i32::from(self.slope_cdeg)) / T::from_f64(100.0),
            azimuth_deg: T::from_u32(u32::from(self.azimuth_cdeg)) / T::from_f64(100.0),
        }
    }
}

fn round_i64(v: f64) -> i64 {
    if !v.is_finite() {
        return 0;
    }
    if v >= 0.0 {
        (v + 0.5) as i64
    } else {
        (v - 0.5) as i64
    }
}

/// Entries a table needs for a 24-hour day (polar day) at `interval_min`:
/// 1440 / interval + 1.
pub const fn capacity_for_interval(interval_min: u16) -> usize {
    if interval_min == 0 {
        0
    } else {
        1440 / interval_min as usize + 1
    }
}

/// Set-points of one day at a fixed interval.
#[derive(Debug, Clone, PartialEq)]
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
    pub fn begin<T: Float>(
        &mut self,
        events: &Events<T>,
        interval_min: u16,
    ) -> Result<(), GeometryError> {
        self.entries.clear();
        self.needed = 0;
        if interval_min == 0 || interval_min > 720 || 1440 % interval_min != 0 {
            return Err(GeometryError::InvalidInterval);
        }
        let step = i64::from(interval_min) * 60;
        let w0 = events.window_start.unix_seconds();
        let w1 = w0 + 86_400;
        let (from, to) = match (events.kind, events.sunrise, events.sunset) {
            (DayKind::PolarNight, _, _) => (w0, w0 - 1),
            (DayKind::PolarDay, _, _) => (w0, w1),
            (_, Some(r), Some(s)) if s > r => (r.unix_seconds(), s.unix_seconds()),
            (_, Some(r), None) => (r.unix_seconds(), w1),
            (_, None, Some(s)) => (w0, s.unix_seconds()),
            _ => (w0, w1),
        };
        let first_s =
            from.div_euclid(step) * step + if from.rem_euclid(step) == 0 { 0 } else { step };
        let last_s = to.div_euclid(step) * step;
        let needed = if last_s >= first_s {
            ((last_s - first_s) / step + 1) as usize
        } else {
            0
        };
        if needed > N {
            return Err(GeometryError::CapacityExceeded {
                needed,
                capacity: N,
            });
        }
        self.first = UtcTime::from_unix_seconds(first_s)?;
        self.interval_min = interval_min;
        // needed ≤ N ≤ u16::MAX (the entries' length type).
        self.needed = u16::try_from(needed).unwrap_or(u16::MAX);
        Ok(())
    }

    /// Computes up to `budget` more entries (at least one) of the table
    /// [`DayTable::begin`] set up; true once it is complete. On an error
    /// the table is left empty (and complete: call `begin` again).
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
        let result = self.fill_some(limits, sun, budget.max(1));
        if result.is_err() {
            self.entries.clear();
            self.needed = 0;
        }
        result
    }

    fn fill_some<T, F>(
        &mut self,
        limits: &Limits<T>,
        sun: &mut F,
        budget: usize,
    ) -> Result<bool, GeometryError>
    where
        T: Float,
        F: FnMut(&UtcTime) -> Result<SunPosition<T>, crate::Error>,
    {
        let step = i64::from(self.interval_min) * 60;
        let needed = usize::from(self.needed);
        for _ in 0..budget {
            let k = self.entries.len();
            if k >= needed {
                break;
            }
            let t = self.first.add_seconds(k as i64 * step)?;
            let p = sun(&t)?;
            let sp = best_within(&p, limits)?;
            self.entries
                .push(Entry::from_surface(&sp.surface))
                .map_err(|_| GeometryError::CapacityExceeded {
                    needed,
                    capacity: N,
                })?;
        }
        Ok(self.entries.len() >= needed)
    }

    /// True once every entry [`DayTable::begin`] set up is computed.
    pub fn is_complete(&self) -> bool {
        self.entries.len() >= usize::from(self.needed)
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.entries.len()
    }
    /// True for a polar night (no entries).
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
    /// Interval between entries, minutes.
    pub fn interval_min(&self) -> u16 {
        self.interval_min
    }
    /// Instant of the first entry.
    pub fn first_time(&self) -> UtcTime {
        self.first
    }

    /// Entry `i` with its instant, `None` past the end.
    pub fn get(&self, i: usize) -> Option<(UtcTime, Entry)> {
        let e = *self.entries.get(i)?;
        let t = self
            .first
            .add_seconds(i as i64 * i64::from(self.interval_min) * 60)
            .ok()?;
        Some((t, e))
    }

    /// The entry in force at `time`: the last one at or before it; `None`
    /// before the first entry or from one interval after the last on.
    pub fn at(&self, time: &UtcTime) -> Option<(UtcTime, Entry)> {
        let dt = time.unix_seconds() - self.first.unix_seconds();
        if dt < 0 {
            return None;
        }
        let step = i64::from(self.interval_min) * 60;
        let i = usize::try_from(dt / step).ok()?;
        self.get(i)
    }

    /// Entries with their instants, in time order.
    pub fn iter(&self) -> impl Iterator<Item = (UtcTime, Entry)> + '_ {
        (0..self.entries.len()).filter_map(move |i| self.get(i))
    }
}
