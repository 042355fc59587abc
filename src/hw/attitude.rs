//! [`AttitudeSensor`] over a tilt sensor and a magnetometer (Choi et al.,
//! portable tracker, §III): the inclinometer gives the angles θx, θy between
//! the vertical and the tracker's x and y axes (eq. 4), the mount's tilt α0,
//! β0 follows (eq. 7), and the magnetometer's field with that tilt removed
//! gives the heading (eq. 8–11).

use drivers::compass::calibration::Calibration;
use drivers::compass::heading::{true_heading_deg, HeadingError};
use drivers::compass::Magnetometer;
use drivers::tilt::{
    axis_angles_from_gravity, axis_angles_from_inclination, mount_tilt, Adxl345, MountTiltError,
    WitInclinometer,
};
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::OutputPin;
use embedded_hal::i2c::I2c;
use embedded_io::{Read, ReadReady, Write};

use sun_algos::Float;

use crate::ports::{AttitudeReading, AttitudeSensor};

/// A sensor giving the angles between the vertical and the tracker's x and
/// y axes, degrees (θx, θy of Choi et al. (portable tracker) eq. 6; both 90° on a
/// level mount).
pub trait AxisAngles {
    /// Why no reading was obtained.
    type Error;
    /// θx, θy in degrees.
    fn axis_angles_deg(&mut self) -> Result<(f32, f32), Self::Error>;
}

/// Errors of an accelerometer used as a tilt sensor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelTiltError<E> {
    /// The driver failed.
    Driver(E),
    /// Under 0.1 g: the sensor is falling or broken, no "down" to measure.
    NoGravity,
}

impl<I2C: I2c> AxisAngles for Adxl345<I2C> {
    type Error = AccelTiltError<drivers::tilt::adxl345::Error<I2C::Error>>;

    /// From the gravity vector directly: cos θ = component / |g|.
    fn axis_angles_deg(&mut self) -> Result<(f32, f32), Self::Error> {
        let a = self.read_acceleration().map_err(AccelTiltError::Driver)?;
        axis_angles_from_gravity(&a).ok_or(AccelTiltError::NoGravity)
    }
}

impl<S, DE, D> AxisAngles for WitInclinometer<S, DE, D>
where
    S: Read + Write + ReadReady,
    DE: OutputPin,
    D: DelayNs,
{
    type Error = drivers::tilt::modbus::Error<S::Error, DE::Error>;

    /// From the roll/pitch pair (Z-Y-X convention) the sensor reports.
    fn axis_angles_deg(&mut self) -> Result<(f32, f32), Self::Error> {
        self.read().map(|i| axis_angles_from_inclination(&i))
    }
}

/// One of two kinds of tilt sensor, chosen at power-on by probing (a board
/// that takes either a WitMotion inclinometer or an ADXL345 has one sensor
/// type for its [`MountSensorsHw`] either way).
#[derive(Debug)]
pub enum EitherTilt<A, B> {
    /// The first kind (e.g. the RS-485 inclinometer).
    First(A),
    /// The second kind (e.g. the accelerometer).
    Second(B),
}

/// The error of whichever sensor [`EitherTilt`] holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EitherTiltError<EA, EB> {
    /// The first kind failed.
    First(EA),
    /// The second kind failed.
    Second(EB),
}

impl<A: AxisAngles, B: AxisAngles> AxisAngles for EitherTilt<A, B> {
    type Error = EitherTiltError<A::Error, B::Error>;

    fn axis_angles_deg(&mut self) -> Result<(f32, f32), Self::Error> {
        match self {
            EitherTilt::First(a) => a.axis_angles_deg().map_err(EitherTiltError::First),
            EitherTilt::Second(b) => b.axis_angles_deg().map_err(EitherTiltError::Second),
        }
    }
}

/// Why an attitude reading failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MountSensorError<EI, EM> {
    /// The tilt sensor failed.
    Tilt(EI),
    /// The magnetometer failed.
    Compass(EM),
    /// The two axis angles describe no tilt (eq. 7 has no solution).
    Geometry(MountTiltError),
    /// The field has no horizontal part, or a value was not finite.
    Heading(HeadingError),
}

/// The mount's attitude sensors: a tilt sensor and a magnetometer whose axes
/// are the tracker's (x west, y south, z up on a level mount at home).
#[derive(Debug)]
pub struct MountSensorsHw<I, M> {
    tilt: I,
    compass: M,
    calibration: Calibration,
    declination_deg: f32,
}

impl<I: AxisAngles, M: Magnetometer> MountSensorsHw<I, M> {
    /// The sensors, with the magnetometer's hard/soft-iron `calibration`
    /// (from a rotation sweep) and the `declination_deg` (east positive)
    /// this adapter applies.
    ///
    /// The controller adds `Config::calibration.declination_deg` to the
    /// heading as well: set the declination in exactly one of the two places
    /// (0 here when the configuration holds it; here when it comes from
    /// WMM2025 for the GPS site).
    pub fn new(tilt: I, compass: M, calibration: Calibration, declination_deg: f32) -> Self {
        MountSensorsHw {
            tilt,
            compass,
            calibration,
            declination_deg,
        }
    }

    /// Changes the declination (e.g. WMM2025 once GPS gives the site).
    pub fn set_declination_deg(&mut self, declination_deg: f32) {
        self.declination_deg = declination_deg;
    }

    /// Gives the two sensors back.
    pub fn destroy(self) -> (I, M) {
        (self.tilt, self.compass)
    }
}

impl<T: Float, I: AxisAngles, M: Magnetometer> AttitudeSensor<T> for MountSensorsHw<I, M> {
    type Error = MountSensorError<I::Error, M::Error>;

    fn set_declination_deg(&mut self, declination_deg: f32) {
        self.declination_deg = declination_deg;
    }

    fn is_not_ready(error: &Self::Error) -> bool {
        matches!(error, MountSensorError::Compass(e) if M::is_not_ready(e))
    }

    #[cfg_attr(target_arch = "avr", inline(never))]
    fn read(&mut self) -> Result<AttitudeReading<T>, Self::Error> {
        let (theta_x_deg, theta_y_deg) = self
            .tilt
            .axis_angles_deg()
            .map_err(MountSensorError::Tilt)?;
        let tilt = mount_tilt(theta_x_deg, theta_y_deg).map_err(MountSensorError::Geometry)?;
        let raw = self
            .compass
            .read_gauss()
            .map_err(MountSensorError::Compass)?;
        let field = self.calibration.apply(raw);
        let heading_deg = true_heading_deg(
            field,
            tilt.alpha0_deg.to_radians(),
            tilt.beta0_deg.to_radians(),
            self.declination_deg,
        )
        .map_err(MountSensorError::Heading)?;
        Ok(AttitudeReading {
            theta_x_deg: T::from_f32(theta_x_deg),
            theta_y_deg: T::from_f32(theta_y_deg),
            heading_deg: T::from_f32(heading_deg),
        })
    }
}
