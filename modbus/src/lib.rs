//! A Modbus RTU server with the SunSpec register map of a dual-axis solar
//! tracker, `no_std`, without allocation, floats or 64-bit arithmetic.
//! (Documentation filled in below.)
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod crc;
pub mod pdu;
pub mod rtu;
pub mod sunspec;

pub use pdu::{Exception, RegisterMap, Server};
pub use rtu::{Push, RtuReceiver, RtuTiming};
pub use sunspec::{SunSpecMap, TrackerData};
