//! A Modbus RTU server for the suntracker firmware, `no_std`, without
//! allocation, floats or 64-bit arithmetic: the RTU frame layer (CRC-16 and
//! frame timing) and the server of function codes 03, 06 and 16.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod crc;
pub mod pdu;
pub mod rtu;

pub use pdu::{Exception, RegisterMap, Server};
pub use rtu::{Push, RtuReceiver, RtuTiming};
