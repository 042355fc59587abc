//! DS3231 over I2C, wrapped around eldruin's `ds323x` crate (0.7,
//! embedded-hal 1.0), which already drives it well; this adds the conversion
//! to our [`DateTime`], the [`Clock`] trait and our error type.
//!
//! Lost power is the oscillator-stop flag (OSF, bit 7 of the status register
//! 0x0F), which the chip sets when it first powers up or when the oscillator
//! stopped; [`Clock::set_datetime`] clears it after writing the time.

use ds323x::{ic, interface::I2cInterface, DateTimeAccess, Ds323x, NaiveDate};

use super::Clock;
use crate::time::DateTime;

/// DS3231 errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error<E> {
    /// I2C error (e.g. NACK).
    Comm(E),
    /// The registers hold no valid date-time (e.g. never set).
    InvalidDeviceState,
    /// The date is outside what the chip stores (2000-01-01..=2100-12-31 as
    /// handled by `ds323x`).
    OutOfRange,
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "DS3231 I2C error: {e:?}"),
            Error::InvalidDeviceState => f.write_str("DS3231 registers hold no valid date-time"),
            Error::OutOfRange => f.write_str("date outside what the DS3231 stores"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

impl<E> From<ds323x::Error<E>> for Error<E> {
    fn from(e: ds323x::Error<E>) -> Self {
        match e {
            ds323x::Error::Comm(e) => Error::Comm(e),
            ds323x::Error::InvalidInputData => Error::OutOfRange,
            ds323x::Error::InvalidDeviceState => Error::InvalidDeviceState,
        }
    }
}

/// A DS3231 real-time clock.
pub struct Ds3231<I2C> {
    dev: Ds323x<I2cInterface<I2C>, ic::DS3231>,
}

impl<I2C, E> Ds3231<I2C>
where
    I2C: embedded_hal::i2c::I2c<Error = E>,
{
    /// Wraps the bus; no bus traffic.
    pub fn new(i2c: I2C) -> Self {
        Self {
            dev: Ds323x::new_ds3231(i2c),
        }
    }

    /// Gives the bus back.
    pub fn destroy(self) -> I2C {
        self.dev.destroy_ds3231()
    }

    /// Die temperature in degrees Celsius (0.25 °C steps, updated by the chip
    /// every 64 s).
    pub fn temperature_c(&mut self) -> Result<f32, Error<E>> {
        Ok(self.dev.temperature()?)
    }

    /// Clears the oscillator-stop flag.
    pub fn clear_lost_power(&mut self) -> Result<(), Error<E>> {
        Ok(self.dev.clear_has_been_stopped_flag()?)
    }
}

impl<I2C, E> Clock for Ds3231<I2C>
where
    I2C: embedded_hal::i2c::I2c<Error = E>,
{
    type Error = Error<E>;

    fn datetime(&mut self) -> Result<DateTime, Error<E>> {
        use chrono::{Datelike, Timelike};
        let t = self.dev.datetime()?;
        let year = u16::try_from(t.year()).map_err(|_| Error::InvalidDeviceState)?;
        // chrono guarantees month 1..=12, day 1..=31, hour < 24, minute and second < 60.
        DateTime::new(
            year,
            t.month() as u8,
            t.day() as u8,
            t.hour() as u8,
            t.minute() as u8,
            t.second() as u8,
        )
        .map_err(|_| Error::InvalidDeviceState)
    }

    fn set_datetime(&mut self, utc: &DateTime) -> Result<(), Error<E>> {
        let t = NaiveDate::from_ymd_opt(
            i32::from(utc.year()),
            u32::from(utc.month()),
            u32::from(utc.day()),
        )
        .and_then(|d| {
            d.and_hms_opt(
                u32::from(utc.hour()),
                u32::from(utc.minute()),
                u32::from(utc.second()),
            )
        })
        .ok_or(Error::OutOfRange)?;
        self.dev.set_datetime(&t)?;
        self.clear_lost_power()
    }

    fn lost_power(&mut self) -> Result<bool, Error<E>> {
        Ok(self.dev.has_been_stopped()?)
    }
}
