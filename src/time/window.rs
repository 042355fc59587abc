//! Plausible dates: the 1024-week window that a GPS date or an RTC date
//! must fall in.
//!
//! GPS transmits the week number in 10 bits (IS-GPS-200, §20.3.3.3.1.1:
//! "the 10 MSBs of the 29-bit Z-count … modulo 1024"), so a receiver must
//! guess the 1024-week era. A receiver that guesses from its firmware's
//! build date reports a date 1024 weeks (19.6 years) early once that build
//! date is more than 1024 weeks old: the week-rollover bug (e.g. 2006 for
//! 2025). The tracker resolves the same ambiguity the same way, from its
//! own floor: a date is plausible only inside the 1024 weeks that start at
//! the floor compiled into this firmware ([`FIRMWARE_DATE_FLOOR`]), which
//! is no later than its release. A date outside the window is the rollover
//! bug (or a corrupt clock) and is never trusted.

use sun_algos::UtcTime;

/// Weeks in one GPS week-number era (10-bit week count).
pub const GPS_WEEK_ERA: i64 = 1024;

/// The first day of this firmware's window: year, month, day. Set to a day
/// no later than the release, so that every real date of the product's
/// life (until [`DateWindow::last_day`], 1024 weeks later) is inside.
pub const FIRMWARE_DATE_FLOOR: (i32, u8, u8) = (2026, 1, 1);

/// A window of [`GPS_WEEK_ERA`] weeks starting at a floor day.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DateWindow {
    /// First day of the window, days since 2000-01-01.
    first_day: i32,
}

impl DateWindow {
    /// Days in the window (1024 × 7 = 7168).
    pub const DAYS: i32 = (GPS_WEEK_ERA * 7) as i32;

    /// The window compiled into this firmware (from
    /// [`FIRMWARE_DATE_FLOOR`]).
    pub fn firmware() -> Self {
        // Evaluated at compile time (the calendar functions are `const`):
        // no date arithmetic in the image.
        const FLOOR: Result<UtcTime, sun_algos::Error> = {
            let (y, m, d) = FIRMWARE_DATE_FLOOR;
            match sun_algos::time::Date::new(y, m, d) {
                Ok(date) => UtcTime::from_date_ms(date, 0),
                Err(_) => Err(sun_algos::Error::InvalidDate),
            }
        };
        match FLOOR {
            Ok(t) => Self::starting(&t),
            // The constant is a valid date; this arm is never taken.
            Err(_) => DateWindow { first_day: 0 },
        }
    }

    /// The window starting on the day of `floor` (simulations and tests of
    /// other epochs).
    pub fn starting(floor: &UtcTime) -> Self {
        DateWindow {
            first_day: floor.days_since_2000(),
        }
    }

    /// The first day (midnight UTC).
    pub fn first_day(&self) -> Result<UtcTime, sun_algos::Error> {
        UtcTime::from_days_ms(self.first_day, 0)
    }

    /// The last day inside the window (midnight UTC).
    pub fn last_day(&self) -> Result<UtcTime, sun_algos::Error> {
        UtcTime::from_days_ms(self.first_day.saturating_add(Self::DAYS - 1), 0)
    }

    /// True when `t` falls inside the window.
    pub fn contains(&self, t: &UtcTime) -> bool {
        let d = t.days_since_2000();
        d >= self.first_day && d - self.first_day < Self::DAYS
    }
}

impl Default for DateWindow {
    fn default() -> Self {
        Self::firmware()
    }
}
