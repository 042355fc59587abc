//! The small traits that join the tracker to the outside world, so that the
//! same controller runs against mocks, the simulator and real boards.

use sun_algos::{Algorithm, Error as SunError, Float, Options, Site, SunPosition, UtcTime};

/// Where the sun is at an instant, for one site.
pub trait PositionSource<T> {
    /// The site the positions are for (seed jimoh-2019 step 1 reads it).
    fn site(&self) -> Site<T>;
    /// Topocentric sun position at `time`.
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<T>, SunError>;
}

/// A [`PositionSource`] computing with one of `sun_algos`' algorithms.
#[derive(Debug, Clone, Copy)]
pub struct AlgorithmSource<T> {
    /// The algorithm (`psa-2020` on boards, any on hosts).
    pub algorithm: Algorithm,
    /// The site.
    pub site: Site<T>,
    /// ΔT, refraction and validity options.
    pub options: Options<T>,
}

impl<T: Float> PositionSource<T> for AlgorithmSource<T> {
    fn site(&self) -> Site<T> {
        self.site
    }
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<T>, SunError> {
        self.algorithm.position(time, &self.site, &self.options)
    }
}

/// A clock giving UTC (an RTC disciplined by GPS on boards).
pub trait Clock {
    /// Why the time cannot be read.
    type Error;
    /// The current instant, or why it is not known.
    fn now(&mut self) -> Result<UtcTime, Self::Error>;
}

/// Byte storage for the configuration (EEPROM, flash, a file or memory).
pub trait Storage {
    /// Why an access failed.
    type Error;
    /// Total bytes available.
    fn capacity(&self) -> usize;
    /// Reads `buf.len()` bytes from `offset`.
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), Self::Error>;
    /// Writes `data` at `offset`.
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), Self::Error>;
}

/// One reading of the mount's attitude sensors (seed portable-tracker §III).
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
