//! Real-time clocks behind one [`Clock`] trait: the DS3231 (I2C) and the
//! DS1302 (three-wire), both our own register-level drivers, plus
//! [`sync_from_gps`] to set a clock that has drifted from GPS time.

mod ds1302;
mod ds3231;

pub use ds1302::{Ds1302, Error as Ds1302Error};
pub use ds3231::{Ds3231, Error as Ds3231Error};

use crate::time::DateTime;

/// A battery-backed clock that keeps UTC.
pub trait Clock {
    /// Bus or device error.
    type Error;

    /// Reads the current UTC date-time (whole seconds).
    fn datetime(&mut self) -> Result<DateTime, Self::Error>;

    /// Sets the UTC date-time (milliseconds are dropped) and starts the
    /// oscillator, which also clears the lost-power indication.
    fn set_datetime(&mut self, utc: &DateTime) -> Result<(), Self::Error>;

    /// Whether the clock lost power or its oscillator stopped since it was
    /// last set, so that its time cannot be trusted.
    fn lost_power(&mut self) -> Result<bool, Self::Error>;
}

/// Sets `clock` to `gps_utc` when the clock lost power or when it differs from
/// `gps_utc` by more than `max_drift_s` seconds. Returns whether it set it.
///
/// `gps_utc` should be fresh (from the current epoch): the caller decides
/// what it trusts, e.g. only RMC time with a valid fix.
pub fn sync_from_gps<C: Clock>(
    clock: &mut C,
    gps_utc: &DateTime,
    max_drift_s: u32,
) -> Result<bool, C::Error> {
    let must_set = if clock.lost_power()? {
        true
    } else {
        let rtc = clock.datetime()?;
        gps_utc.seconds_since(&rtc).unsigned_abs() > u64::from(max_drift_s)
    };
    if must_set {
        clock.set_datetime(gps_utc)?;
    }
    Ok(must_set)
}
