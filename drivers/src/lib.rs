#![doc = include_str!("../README.md")]
#![no_std]

pub mod adc;
pub mod compass;
pub mod counter;
pub mod dc_motor;
pub mod encoder;
mod fmath;
pub mod gps;
pub mod hall;
pub mod linear;
pub mod rtc;
pub mod servo;
pub mod stepper;
pub mod tilt;
pub mod time;
