//! [`crate::ports::Clock`] over a battery-backed RTC driver.

use drivers::rtc::Clock as RtcDriver;
use sun_algos::UtcTime;

use crate::ports::Clock;
use crate::time::utc_from_datetime;

/// Why the RTC's time is not available.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClockError<E> {
    /// The driver failed (bus error such as an I2C NACK, or registers that
    /// hold no valid date).
    Rtc(E),
    /// The RTC lost power (DS3231 oscillator-stop flag, DS1302 clock-halt):
    /// its time must not be used until GPS sets it.
    LostPower,
    /// The date is outside the range the tracker computes for.
    OutOfRange,
}

/// A tracker [`Clock`] reading an RTC driver. Every [`Clock::now`] checks the
/// lost-power indication first, so a clock that stopped is never trusted.
#[derive(Debug)]
pub struct RtcClock<C> {
    rtc: C,
}

impl<C: RtcDriver> RtcClock<C> {
    /// Wraps the driver; no bus traffic.
    pub fn new(rtc: C) -> Self {
        RtcClock { rtc }
    }

    /// The driver (e.g. to set the time from GPS).
    pub fn driver_mut(&mut self) -> &mut C {
        &mut self.rtc
    }

    /// Gives the driver back.
    pub fn destroy(self) -> C {
        self.rtc
    }
}

impl<C: RtcDriver> Clock for RtcClock<C> {
    type Error = ClockError<C::Error>;

    fn now(&mut self) -> Result<UtcTime, Self::Error> {
        if self.rtc.lost_power().map_err(ClockError::Rtc)? {
            return Err(ClockError::LostPower);
        }
        let t = self.rtc.datetime().map_err(ClockError::Rtc)?;
        utc_from_datetime(&t).map_err(|_| ClockError::OutOfRange)
    }
}
