//! A DS3231-like real-time clock model for simulations, with fault injection.
//!
//! The simulation tells the model the true UTC at every tick
//! ([`SimRtc::advance`]); the clock reads the true time plus an offset in
//! whole seconds (a DS3231 keeps no fractions of a second). The offset starts
//! at 0 and changes only through the injected faults and through
//! [`Clock::set_datetime`]:
//!
//! - [`SimRtc::step_s`]: the clock jumps by a number of seconds (a technician
//!   or a bad synchronisation set it wrong);
//! - [`SimRtc::power_loss`]: the oscillator stopped and the registers were
//!   reset; the clock counts on from [`POWER_LOSS_RESET_UNIX_S`]
//!   (2000-01-01T00:00:00Z, what a DS3231 holds after a cold start) and
//!   [`Clock::lost_power`] reports `true` until the clock is set again;
//! - [`SimRtc::bus_error`]: every [`Clock`] call fails with
//!   [`SimRtcError::Bus`], as with a disconnected or stuck I2C bus.
//!
//! All arithmetic is checked or saturating: the model never panics; a
//! reading outside the calendar of [`DateTime`] is
//! [`SimRtcError::OutOfRange`].

use core::fmt;

use drivers::rtc::Clock;
use drivers::time::DateTime;
use sun_algos::UtcTime;

/// What the clock reads right after a power loss: 2000-01-01T00:00:00Z in
/// seconds since 1970-01-01T00:00:00Z (the DS3231's reset value).
pub const POWER_LOSS_RESET_UNIX_S: i64 = 946_684_800;

/// Errors of the simulated clock.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SimRtcError {
    /// Injected bus error (the chip did not answer).
    Bus,
    /// The clock's time (true time plus offset) or the time given to
    /// `set_datetime` lies outside what the model can represent.
    OutOfRange,
}

impl fmt::Display for SimRtcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimRtcError::Bus => f.write_str("RTC bus error"),
            SimRtcError::OutOfRange => f.write_str("RTC time out of range"),
        }
    }
}

/// A simulated battery-backed clock; see the module docs.
#[derive(Debug, Clone)]
pub struct SimRtc {
    /// True UTC of the last [`SimRtc::advance`], whole seconds since
    /// 1970-01-01T00:00:00Z.
    true_unix_s: i64,
    /// What the clock reads minus the true time, seconds.
    offset_s: i64,
    /// Oscillator-stopped flag (the DS3231's OSF bit).
    lost_power: bool,
    /// Injected: every [`Clock`] call fails with [`SimRtcError::Bus`].
    pub bus_error: bool,
    /// How many times [`Clock::set_datetime`] succeeded.
    pub sets: u32,
}

impl SimRtc {
    /// A clock that reads `true_now` exactly (offset 0), powered and on a
    /// working bus.
    pub fn new(true_now: UtcTime) -> Self {
        SimRtc {
            true_unix_s: true_now.unix_seconds(),
            offset_s: 0,
            lost_power: false,
            bus_error: false,
            sets: 0,
        }
    }

    /// Moves the clock on to the true UTC `true_now` (called by the
    /// simulation every tick); the offset is kept.
    pub fn advance(&mut self, true_now: UtcTime) {
        self.true_unix_s = true_now.unix_seconds();
    }

    /// Injected: the clock jumps by `step_s` seconds (either sign). The
    /// offset saturates at the limits of `i64`; such a clock then reads
    /// [`SimRtcError::OutOfRange`].
    pub fn step_s(&mut self, step_s: i64) {
        self.offset_s = self.offset_s.saturating_add(step_s);
    }

    /// Injected: the oscillator stopped and the time registers were reset.
    /// From now on the clock counts from [`POWER_LOSS_RESET_UNIX_S`] and
    /// [`Clock::lost_power`] is `true` until the clock is set.
    pub fn power_loss(&mut self) {
        self.offset_s = POWER_LOSS_RESET_UNIX_S.saturating_sub(self.true_unix_s);
        self.lost_power = true;
    }

    /// What the clock reads minus the true time, seconds.
    pub fn offset_s(&self) -> i64 {
        self.offset_s
    }

    /// Whether the oscillator-stopped flag is set (without the bus: for the
    /// simulation's own bookkeeping).
    pub fn oscillator_stopped(&self) -> bool {
        self.lost_power
    }

    /// What the clock holds now, in seconds since 1970-01-01T00:00:00Z
    /// (without the bus), or `None` if that overflows.
    pub fn reading_unix_s(&self) -> Option<i64> {
        self.true_unix_s.checked_add(self.offset_s)
    }

    fn check_bus(&self) -> Result<(), SimRtcError> {
        if self.bus_error {
            Err(SimRtcError::Bus)
        } else {
            Ok(())
        }
    }
}

impl Clock for SimRtc {
    type Error = SimRtcError;

    fn datetime(&mut self) -> Result<DateTime, SimRtcError> {
        self.check_bus()?;
        let unix_s = self.reading_unix_s().ok_or(SimRtcError::OutOfRange)?;
        DateTime::from_unix_seconds(unix_s).map_err(|_| SimRtcError::OutOfRange)
    }

    /// Sets the offset so that the clock reads `utc` now (milliseconds
    /// dropped), clears the lost-power flag and counts the set.
    fn set_datetime(&mut self, utc: &DateTime) -> Result<(), SimRtcError> {
        self.check_bus()?;
        self.offset_s = utc
            .unix_seconds()
            .checked_sub(self.true_unix_s)
            .ok_or(SimRtcError::OutOfRange)?;
        self.lost_power = false;
        self.sets = self.sets.saturating_add(1);
        Ok(())
    }

    fn lost_power(&mut self) -> Result<bool, SimRtcError> {
        self.check_bus()?;
        Ok(self.lost_power)
    }
}
