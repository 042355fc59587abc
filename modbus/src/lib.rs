//! A Modbus RTU server for the suntracker firmware, `no_std`, without
//! allocation, floats or 64-bit arithmetic. This first part: the RTU frame
//! layer (CRC-16 and frame timing).
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod crc;
pub mod rtu;

pub use rtu::{Push, RtuReceiver, RtuTiming};
