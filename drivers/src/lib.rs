//! Device drivers for solar trackers over embedded-hal 1.0, `no_std`.
//!
//! Serial devices (GPS, RS-485 inclinometer) use `embedded-io` `Read`/`Write`
//! throughout the crate; I2C, GPIO, PWM and delays use `embedded-hal` 1.0.
#![no_std]

pub mod compass;
pub mod encoder;
pub mod gps;
pub mod rtc;
pub mod servo;
pub mod stepper;
pub mod tilt;
pub mod time;
