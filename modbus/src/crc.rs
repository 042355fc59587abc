//! The Modbus RTU CRC-16.
//!
//! Modbus over Serial Line Specification and Implementation Guide V1.02
//! (modbus.org, 2006), §6.2.2 and Appendix B: polynomial 0xA001 (0x8005
//! reflected), initial value 0xFFFF, no final XOR, appended to the frame low
//! byte first. Computed bit by bit (no 512-byte table: on the 8-bit AVR a
//! table costs more flash than the loop, and frames are short).

/// The CRC's initial value.
pub const CRC_INIT: u16 = 0xFFFF;

/// The CRC register after one more byte. Not inlined: one copy serves the
/// receiver and the reply (206 B less on the ATmega2560,
/// `modbus/avr_size.sh`).
#[inline(never)]
pub fn crc16_update(crc: u16, byte: u8) -> u16 {
    let mut crc = crc ^ u16::from(byte);
    for _ in 0..8 {
        let lsb = crc & 1;
        crc >>= 1;
        if lsb != 0 {
            crc ^= 0xA001;
        }
    }
    crc
}

/// The CRC of `bytes` (low byte first on the wire:
/// `[crc as u8, (crc >> 8) as u8]`).
pub fn crc16(bytes: &[u8]) -> u16 {
    bytes.iter().fold(CRC_INIT, |crc, &b| crc16_update(crc, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A read of ten holding registers from 0 at server 1, as every Modbus
    /// tool shows it: `01 03 00 00 00 0A C5 CD`.
    #[test]
    fn read_request_vector() {
        let crc = crc16(&[0x01, 0x03, 0x00, 0x00, 0x00, 0x0A]);
        assert_eq!(crc.to_le_bytes(), [0xC5, 0xCD]);
    }

    /// The specification's own example (Modbus over Serial Line V1.02,
    /// §6.2.2): the frame `02 07` carries the CRC bytes `41 12`.
    #[test]
    fn spec_example() {
        assert_eq!(crc16(&[0x02, 0x07]).to_le_bytes(), [0x41, 0x12]);
    }

    /// The CRC-16/MODBUS check value of the CRC catalogue: "123456789"
    /// gives 0x4B37.
    #[test]
    fn catalogue_check_value() {
        assert_eq!(crc16(b"123456789"), 0x4B37);
    }

    /// A whole frame with its CRC appended leaves a zero register.
    #[test]
    fn residue_is_zero() {
        let mut frame = [0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0, 0];
        let crc = crc16(&frame[..6]);
        frame[6..].copy_from_slice(&crc.to_le_bytes());
        assert_eq!(crc16(&frame), 0);
    }
}
