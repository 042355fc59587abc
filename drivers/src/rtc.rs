//! Real-time clocks behind one [`Clock`] trait: the DS3231 (I2C) and the
//! DS1302 (three-wire), both our own register-level drivers, plus
//! [`sync_from_gps`] to set a clock that has drifted from GPS time.
//!
//! The examples run against `embedded-hal-mock` buses whose expected
//! transactions are written from the chips' datasheets.

mod ds1302;
mod ds3231;

pub use ds1302::{Ds1302, Error as Ds1302Error};
pub use ds3231::{Ds3231, Error as Ds3231Error};

use crate::time::DateTime;

/// A battery-backed clock that keeps UTC.
///
/// Code written against the trait runs on either chip:
///
/// ```
/// use drivers::rtc::{Clock, Ds3231};
/// use drivers::time::DateTime;
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// /// The clock's time, or `None` when it cannot be trusted.
/// fn trusted_time<C: Clock>(clock: &mut C) -> Result<Option<DateTime>, C::Error> {
///     if clock.lost_power()? {
///         return Ok(None);
///     }
///     clock.datetime().map(Some)
/// }
///
/// // DS3231 datasheet (Maxim 19-5170): address 0x68, status 0Fh (0x08:
/// // OSF clear), then the time registers 00h..06h in BCD.
/// let expectations = [
///     Transaction::write_read(0x68, vec![0x0F], vec![0x08]),
///     Transaction::write_read(0x68, vec![0x00], vec![0x00, 0x00, 0x00, 0x07, 0x01, 0x01, 0x00]),
/// ];
/// let mut rtc = Ds3231::new(Mock::new(&expectations));
/// assert_eq!(trusted_time(&mut rtc)?, Some(DateTime::new(2000, 1, 1, 0, 0, 0)?));
/// rtc.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub trait Clock {
    /// Bus or device error.
    type Error;

    /// Reads the current UTC date-time (whole seconds).
    ///
    /// ```
    /// use drivers::rtc::{Clock, Ds3231};
    /// use drivers::time::DateTime;
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // DS3231 datasheet: registers 00h..06h = 59 s, 59 min, 23 h, day 5,
    /// // date 31, month 12, year 99 (BCD).
    /// let expectations = [Transaction::write_read(
    ///     0x68,
    ///     vec![0x00],
    ///     vec![0x59, 0x59, 0x23, 0x05, 0x31, 0x12, 0x99],
    /// )];
    /// let mut clock = Ds3231::new(Mock::new(&expectations));
    /// assert_eq!(clock.datetime()?, DateTime::new(2099, 12, 31, 23, 59, 59)?);
    /// clock.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn datetime(&mut self) -> Result<DateTime, Self::Error>;

    /// Sets the UTC date-time (milliseconds are dropped) and starts the
    /// oscillator, which also clears the lost-power indication.
    ///
    /// ```
    /// use drivers::rtc::{Clock, Ds3231};
    /// use drivers::time::DateTime;
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // DS3231 datasheet: the seven time registers from 00h (the 250 ms
    /// // are dropped; 2024-02-29 is a Thursday, day of week 5), then
    /// // control/status 0Eh..0Fh: control 0x9C has EOSC (bit 7) set and is
    /// // written back as 0x1C; status 0x08 has OSF clear.
    /// let expectations = [
    ///     Transaction::write(0x68, vec![0x00, 0x00, 0x30, 0x08, 0x05, 0x29, 0x02, 0x24]),
    ///     Transaction::write_read(0x68, vec![0x0E], vec![0x9C, 0x08]),
    ///     Transaction::write(0x68, vec![0x0E, 0x1C]),
    /// ];
    /// let mut clock = Ds3231::new(Mock::new(&expectations));
    /// let t = DateTime::new(2024, 2, 29, 8, 30, 0)?.with_millis(250)?;
    /// clock.set_datetime(&t)?;
    /// clock.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn set_datetime(&mut self, utc: &DateTime) -> Result<(), Self::Error>;

    /// Whether the clock lost power or its oscillator stopped since it was
    /// last set, so that its time cannot be trusted.
    ///
    /// ```
    /// use drivers::rtc::{Clock, Ds3231};
    /// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
    ///
    /// // DS3231 datasheet: status 0Fh at power-on is 0x88, OSF (bit 7) set.
    /// let expectations = [Transaction::write_read(0x68, vec![0x0F], vec![0x88])];
    /// let mut clock = Ds3231::new(Mock::new(&expectations));
    /// assert!(clock.lost_power()?);
    /// clock.destroy().done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn lost_power(&mut self) -> Result<bool, Self::Error>;
}

/// Sets `clock` to `gps_utc` when the clock lost power or when it differs from
/// `gps_utc` by more than `max_drift_s` seconds. Returns whether it set it.
///
/// `gps_utc` should be fresh (from the current epoch): the caller decides
/// what it trusts, e.g. only RMC time with a valid fix.
///
/// ```
/// use drivers::rtc::{sync_from_gps, Ds3231};
/// use drivers::time::DateTime;
/// use embedded_hal_mock::eh1::i2c::{Mock, Transaction};
///
/// let gps = DateTime::new(2026, 6, 21, 12, 34, 56)?;
/// // DS3231 datasheet (Maxim 19-5170): status 0Fh 0x08 (OSF clear), then
/// // the time registers from 00h: 12:34:53, 3 s behind the GPS.
/// let expectations = [
///     Transaction::write_read(0x68, vec![0x0F], vec![0x08]),
///     Transaction::write_read(0x68, vec![0x00], vec![0x53, 0x34, 0x12, 0x01, 0x21, 0x06, 0x26]),
/// ];
/// let mut rtc = Ds3231::new(Mock::new(&expectations));
/// // 3 s is within a 5 s tolerance: the clock is left alone.
/// assert!(!sync_from_gps(&mut rtc, &gps, 5)?);
/// rtc.destroy().done();
///
/// // The same clock with a 2 s tolerance is set: the seven registers from
/// // 00h, then control/status 0Eh..0Fh (0x1C, 0x08: nothing to clear).
/// let expectations = [
///     Transaction::write_read(0x68, vec![0x0F], vec![0x08]),
///     Transaction::write_read(0x68, vec![0x00], vec![0x53, 0x34, 0x12, 0x01, 0x21, 0x06, 0x26]),
///     Transaction::write(0x68, vec![0x00, 0x56, 0x34, 0x12, 0x01, 0x21, 0x06, 0x26]),
///     Transaction::write_read(0x68, vec![0x0E], vec![0x1C, 0x08]),
/// ];
/// let mut rtc = Ds3231::new(Mock::new(&expectations));
/// assert!(sync_from_gps(&mut rtc, &gps, 2)?);
/// rtc.destroy().done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
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
