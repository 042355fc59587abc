//! suntracker — firmware for dual-axis solar trackers.
//!
//! This library is `no_std`: it runs on the tracker's microcontroller
//! (Cortex-M4F, 8-bit AVR) and on a PC for tests, simulations and tools.
#![no_std]
// No unsafe code: the chip code is in the board crates (boards/), the one
// read of program memory in the progmem crate.
#![forbid(unsafe_code)]

/// Name and version of the firmware, printed by every image at boot.
pub const BANNER: &str = concat!("suntracker ", env!("CARGO_PKG_VERSION"));

pub mod attitude;
mod bytes;
pub mod config;
pub mod console;
pub mod controller;
pub mod firmware;
pub mod hw;
pub mod log;
pub mod mechanics;
pub mod motion;
pub mod panel;
pub mod persist;
pub mod plan;
pub mod ports;
pub mod safety;
pub mod servo_tracker;
pub mod site;
pub mod sun;
pub mod sunspec;
pub mod time;

/// Constant text and tables kept in program memory on AVR (the progmem
/// crate), so that every module names them in one place.
pub mod text {
    pub use progmem::{ascii_str, FlashStr, FlashStrs, ProgMem};
}

pub use progmem::{flash_str, flash_strs, progmem};
