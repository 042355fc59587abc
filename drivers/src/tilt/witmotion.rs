//! WitMotion RS-485 inclinometers (SINDT02-485 class, the sensor named in
//! seed li-2022) over Modbus RTU.
//!
//! Register map assumed, from WitMotion's public "WIT standard Modbus
//! protocol" (the same map across their Modbus sensors): device address 0x50
//! by default; angle registers 0x3D Roll (about X), 0x3E Pitch (about Y),
//! 0x3F Yaw, each a signed 16-bit value with angle = raw / 32768 × 180°.
//! Roll and pitch are read together with one function-0x03 request of two
//! registers from 0x3D.

use embedded_hal::delay::DelayNs;
use embedded_hal::digital::OutputPin;
use embedded_io::{Read, ReadReady, Write};

use super::modbus::{Error, ModbusMaster, Timeout};
use super::Inclination;

/// WitMotion factory Modbus address.
pub const DEFAULT_ADDRESS: u8 = 0x50;
const REG_ROLL: u16 = 0x3D;
/// Degrees per raw count: 180 / 32768.
const DEG_PER_COUNT: f32 = 180.0 / 32768.0;

/// Raw angle register to degrees.
pub fn raw_to_deg(raw: u16) -> f32 {
    // The register holds a two's-complement i16.
    f32::from(raw as i16) * DEG_PER_COUNT
}

/// A WitMotion Modbus inclinometer.
#[derive(Debug)]
pub struct WitInclinometer<S, DE, D> {
    bus: ModbusMaster<S, DE, D>,
    address: u8,
}

impl<S, DE, D> WitInclinometer<S, DE, D>
where
    S: Read + Write + ReadReady,
    DE: OutputPin,
    D: DelayNs,
{
    /// The sensor at Modbus `address` (usually [`DEFAULT_ADDRESS`]).
    pub fn new(serial: S, de: DE, delay: D, address: u8, timeout: Timeout) -> Self {
        Self {
            bus: ModbusMaster::new(serial, de, delay, timeout),
            address,
        }
    }

    /// Gives the serial port, DE pin and delay back.
    pub fn destroy(self) -> (S, DE, D) {
        self.bus.destroy()
    }

    /// Reads roll (about X) and pitch (about Y) in degrees.
    pub fn read(&mut self) -> Result<Inclination, Error<S::Error, DE::Error>> {
        let mut regs = [0u16; 2];
        self.bus
            .read_holding_registers(self.address, REG_ROLL, &mut regs)?;
        let [roll, pitch] = regs;
        Ok(Inclination {
            roll_deg: raw_to_deg(roll),
            pitch_deg: raw_to_deg(pitch),
        })
    }
}
