//! Adapters from the real drivers (`drivers` crate) to the tracker's traits,
//! so that [`crate::controller::Controller`] runs on a board's peripherals
//! exactly as it runs against the simulator.
//!
//! | adapter | tracker trait | driver |
//! |---|---|---|
//! | [`RtcClock`] | [`crate::ports::Clock`] | any [`drivers::rtc::Clock`] (DS3231, DS1302) |
//! | [`GpsPort`] | — (feeds [`crate::time`]) | [`drivers::gps::GpsReader`] |
//! | [`MountSensorsHw`] | [`crate::ports::AttitudeSensor`] | a tilt sensor ([`AxisAngles`]: ADXL345, WitMotion inclinometer) + any [`drivers::compass::Magnetometer`] |
//! | [`ServoAxis`] | [`crate::motion::AxisDrive`] | [`drivers::servo::ContinuousServo`] + a quadrature encoder ([`EncoderCount`]) + home switch |
//! | [`DcAxis`] | [`crate::motion::AxisDrive`] | [`drivers::dc_motor::DcMotor`] (BTS7960, L298N) + a Hall count ([`EncoderCount`]) + home switch + optional current sense ([`MotorCurrent`]) |
//! | [`LinearAxis`] | [`crate::motion::AxisDrive`] | a [`DcAxis`] on a linear actuator between two pivots ([`drivers::linear::ActuatorGeometry`]), Hall pulses ([`HallFeedback`]) or a potentiometer ([`PotFeedback`]) |
//! | [`TimedAxis`] | [`crate::motion::AxisDrive`] | [`drivers::dc_motor::DcMotor`] + home switch + optional current sense, no feedback: runs timed at calibrated speeds |
//! | [`StepperAxis`] | [`crate::motion::AxisDrive`] | [`drivers::stepper::hbridge::HBridgeStepper`] + home switch |
//! | [`AnyAxis`] | [`crate::motion::AxisDrive`] | a stepper, DC, timed or linear actuator axis, the kind chosen by the configuration at power-on |
//!
//! Time and site fallbacks (GPS, then RTC, then the stored site or a postal
//! code) are in [`crate::time`].

mod any_axis;
mod attitude;
mod axis;
mod dc_axis;
mod gps;
mod linear_axis;
mod rtc;
mod servo_axis;
mod timed_axis;

pub use any_axis::{AnyAxis, AnyAxisError};
pub use attitude::{
    AccelTiltError, AxisAngles, EitherTilt, EitherTiltError, MountSensorError, MountSensorsHw,
};
pub use axis::{StepperAxis, StepperAxisError};
pub use dc_axis::{
    DcAxis, DcAxisConfig, DcAxisConfigError, DcAxisError, DcFault, DcState, MotorCurrent,
    NoCurrentSense, MAX_IDLE_COUNTS, MAX_LEAD_MS, MAX_SETTLE_MS, MIN_LEARN_SPEED_CPS,
    SPEED_WINDOW_MS, STOP_LEADS,
};
pub use gps::{GpsInput, GpsPart, GpsPort, GpsState, GpsTrack, NoGps};
pub use linear_axis::{
    HallFeedback, LinearAxis, LinearAxisConfig, LinearAxisConfigError, LinearAxisError,
    LinearFeedback, NoEndSwitch, PotConfig, PotError, PotFeedback, POT_COUNTS_PER_MM,
};
pub use rtc::{ClockError, RtcClock};
pub use servo_axis::{EncoderCount, ServoAxis, ServoAxisError};
pub use timed_axis::{
    TimedAxis, TimedAxisConfig, TimedAxisConfigError, TimedAxisError, MAX_RUN_MS, MAX_SUPPLY_MV,
    MIN_SUPPLY_SHARE, SPEED_RANGE_DEG_S,
};
