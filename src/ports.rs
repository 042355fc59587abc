//! The small traits that join the tracker to the outside world, so that the
//! same controller runs against mocks, the simulator and real boards.

use sun_algos::UtcTime;

/// A clock giving UTC (an RTC disciplined by GPS on boards).
pub trait Clock {
    /// Why the time cannot be read.
    type Error;
    /// The current instant, or why it is not known.
    fn now(&mut self) -> Result<UtcTime, Self::Error>;
}

/// Byte storage for the configuration (EEPROM, flash, a file or memory).
///
/// Two ways to write. [`Storage::write`] does the whole write before it
/// returns (hosts, tests, RAM). The stepped methods — [`Storage::erase_step`],
/// [`Storage::write_step`], [`Storage::flush_step`] — never wait: each does
/// what the storage can do now (at most one bounded operation) and says how
/// far it got, so that a main loop that must not stop longer than one tick
/// calls one of them per pass ([`crate::persist::ConfigStore::poll`] does).
/// Their defaults suit storage that is always ready and needs no erase
/// (RAM): nothing to erase, the whole write at once, nothing pending.
///
/// Implementations: [`crate::persist::MemStorage`] (RAM),
/// [`crate::persist::EepromStorage`] (byte EEPROM such as the AVR's, over
/// [`crate::persist::EepromCells`]), [`crate::persist::NorFlashStorage`]
/// (NOR flash through `embedded-storage`).
pub trait Storage {
    /// Why an access failed.
    type Error;
    /// Total bytes available.
    fn capacity(&self) -> usize;
    /// Reads `buf.len()` bytes from `offset`.
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), Self::Error>;
    /// Writes `data` at `offset`, waiting until it is done. On storage that
    /// must be erased before it is written (NOR flash) the range must have
    /// been prepared by [`Storage::erase_step`] since it was last written.
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), Self::Error>;
    /// Prepares the first bytes of `offset..offset + len` for writing
    /// without waiting (a NOR flash erases one erase unit): returns how many
    /// bytes from `offset` are ready now, 0 when the storage is busy (call
    /// again), `len` when all are. The default: nothing to prepare.
    fn erase_step(&mut self, offset: usize, len: usize) -> Result<usize, Self::Error> {
        let _ = offset;
        Ok(len)
    }
    /// Writes the first bytes of `data` at `offset` without waiting: returns
    /// how many bytes of `data` it took, 0 when the storage is busy (call
    /// again). Bytes taken may still be on their way into the storage until
    /// [`Storage::flush_step`] says that nothing is pending. The default:
    /// [`Storage::write`] of all of `data`.
    fn write_step(&mut self, offset: usize, data: &[u8]) -> Result<usize, Self::Error> {
        self.write(offset, data).map(|()| data.len())
    }
    /// Without waiting: `Ok(true)` when every byte taken by
    /// [`Storage::write_step`] is in the storage (and, where the storage
    /// checks, reads back as written), `Ok(false)` while a write is still in
    /// progress. The default: nothing is ever pending.
    fn flush_step(&mut self) -> Result<bool, Self::Error> {
        Ok(true)
    }
    /// The longest an erase or write step stalls the CPU, ms: non-zero for
    /// a microcontroller's own flash, from which its code runs (on the
    /// STM32F411 a 16 KiB sector erase stalls it up to 800 ms, see
    /// [`crate::persist`]). The firmware loop then takes save steps only
    /// while no axis moves and no tick is due for that long. The default:
    /// 0, no stall.
    fn stall_ms(&self) -> u32 {
        0
    }
}

/// One reading of the mount's attitude sensors (Choi et al. (portable tracker) §III).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AttitudeReading<T> {
    /// θx: angle between the vertical and the tracker's x axis, degrees.
    pub theta_x_deg: T,
    /// θy: angle between the vertical and the tracker's y axis, degrees.
    pub theta_y_deg: T,
    /// True azimuth of the tracker's +y axis (tilt-compensated, declination
    /// applied), degrees east of north.
    pub heading_deg: T,
}

/// Inclinometer and compass of the mount.
pub trait AttitudeSensor<T> {
    /// Why a reading failed (bus error, timeout, …).
    type Error;
    /// A fresh reading.
    fn read(&mut self) -> Result<AttitudeReading<T>, Self::Error>;
    /// True when `error` only says that a sensor has no new sample yet (it
    /// measures at its own rate): not a fault, the reading is retried at
    /// the next tick. False for every other error.
    fn is_not_ready(error: &Self::Error) -> bool {
        let _ = error;
        false
    }
    /// Sets the magnetic declination (degrees, east positive) the sensor
    /// applies to its heading, e.g. from WMM2025 once the site is known.
    /// Sensors that report a true heading already ignore it.
    fn set_declination_deg(&mut self, declination_deg: f32) {
        let _ = declination_deg;
    }
}

/// No attitude sensors: the type of a board whose mount attitude is fixed
/// in the configuration (`Option<Infallible>` is always `None`, so the
/// code that reads sensors, and the declination computed for them, is not
/// in its image).
impl<T> AttitudeSensor<T> for core::convert::Infallible {
    type Error = core::convert::Infallible;
    fn read(&mut self) -> Result<AttitudeReading<T>, Self::Error> {
        match *self {}
    }
}
