//! Adapters from the real drivers (`drivers` crate) to the tracker's traits,
//! so that [`crate::controller::Controller`] runs on a board's peripherals
//! exactly as it runs against the simulator.
//!
//! | adapter | tracker trait | driver |
//! |---|---|---|
//! | [`RtcClock`] | [`crate::traits::Clock`] | any [`drivers::rtc::Clock`] (DS3231, DS1302) |
//! | [`GpsPort`] | — (feeds [`crate::sources`]) | [`drivers::gps::GpsReader`] |
//! | [`MountSensorsHw`] | [`crate::traits::AttitudeSensor`] | a tilt sensor ([`AxisAngles`]: ADXL345, WitMotion inclinometer) + any [`drivers::compass::Magnetometer`] |
//! | [`ServoAxis`] | [`crate::axis::AxisDrive`] | [`drivers::servo::ContinuousServo`] + a quadrature encoder ([`EncoderCount`]) + home switch |
//! | [`StepperAxis`] | [`crate::axis::AxisDrive`] | [`drivers::stepper::hbridge::HBridgeStepper`] + home switch |
//!
//! Time and site fallbacks (GPS, then RTC, then the stored site or a postal
//! code) are in [`crate::sources`].

mod attitude;
mod axis;
mod clock;
mod gps;
mod servo_axis;
mod time;

pub use attitude::{
    AccelTiltError, AxisAngles, EitherTilt, EitherTiltError, MountSensorError, MountSensorsHw,
};
pub use axis::{StepperAxis, StepperAxisError};
pub use clock::{ClockError, RtcClock};
pub use gps::GpsPort;
pub use servo_axis::{EncoderCount, ServoAxis, ServoAxisError};
pub use time::{datetime_from_utc, utc_from_datetime, TimeConversionError};
