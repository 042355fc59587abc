#![doc = include_str!("../README.md")]
#![no_std]
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod algorithm;
#[cfg(all(target_arch = "avr", feature = "avr-libc-math"))]
#[allow(unsafe_code)]
mod avr_libc;
#[cfg(feature = "compact-f32")]
pub mod compact;
pub mod delta_t;
pub mod error;
pub mod float;
pub mod geometry;
pub mod grena2008;
pub mod grena2012;
pub mod michalsky;
pub mod position;
pub mod psa;
pub mod refraction;
pub mod site;
pub mod spa;
pub mod textbook;
pub mod time;
#[cfg(feature = "chrono")]
mod with_chrono;
#[cfg(feature = "defmt")]
mod with_defmt;
#[cfg(feature = "serde")]
mod with_serde;

pub use algorithm::Algorithm;
pub use error::Error;
pub use float::Float;
pub use position::SunPosition;
pub use site::{Atmosphere, Options, Site};
pub use time::UtcTime;
