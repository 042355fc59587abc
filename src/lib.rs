//! suntracker — firmware for dual-axis solar trackers.
//!
//! This library is `no_std`: it runs on the tracker's microcontroller
//! (Cortex-M4F, 8-bit AVR) and on a PC for tests, simulations and tools.
#![no_std]
// `LPM` for text kept in flash (src/text.rs).
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]
// No unsafe code, except in the AVR board layer (src/board/avr), which
// allows it for raw register writes and its interrupt handlers' register
// access, each with a SAFETY comment.
#![deny(unsafe_code)]

/// Name and version of the firmware, printed by every image at boot.
pub const BANNER: &str = concat!("suntracker ", env!("CARGO_PKG_VERSION"));

pub mod app;
pub mod attitude;
pub mod axis;
pub mod bench;
pub mod board;
pub mod clock;
pub mod config;
pub mod console;
pub mod controller;
pub mod hw;
pub mod log;
pub mod panel;
pub mod safety;
pub mod scheduler;
pub mod sim;
pub mod site;
pub mod sources;
pub mod storage;
pub mod text;
pub mod traits;
