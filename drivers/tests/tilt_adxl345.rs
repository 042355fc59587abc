//! ADXL345 over I2C, transaction-exact. Register bytes from the ADXL345
//! datasheet (Rev. G): address 0x53 (ALT low), DEVID 0x00 = 0xE5,
//! DATA_FORMAT 0x31 <- 0x08 (FULL_RES, ±2 g), BW_RATE 0x2C <- 0x0A (100 Hz),
//! POWER_CTL 0x2D <- 0x08 (Measure), data 0x32..0x37 little-endian.

use drivers::tilt::adxl345::{Error, ADDRESS_ALT_LOW};
use drivers::tilt::Adxl345;
use embedded_hal::i2c::{ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};

const A: u8 = ADDRESS_ALT_LOW;

fn nack() -> ErrorKind {
    ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
}

fn init_tx() -> Vec<I2c> {
    vec![
        I2c::write_read(A, vec![0x00], vec![0xE5]),
        I2c::write(A, vec![0x31, 0x08]),
        I2c::write(A, vec![0x2C, 0x0A]),
        I2c::write(A, vec![0x2D, 0x08]),
    ]
}

#[test]
fn init_sequence() {
    let mut acc = Adxl345::new(I2cMock::new(&init_tx()), A);
    assert_eq!(acc.init(), Ok(()));
    acc.destroy().done();
}

#[test]
fn wrong_device_id_stops_init() {
    let tx = [I2c::write_read(A, vec![0x00], vec![0x00])];
    let mut acc = Adxl345::new(I2cMock::new(&tx), A);
    assert_eq!(acc.init(), Err(Error::WrongDeviceId(0x00)));
    acc.destroy().done();
}

#[test]
fn nack_in_init_and_read() {
    let tx = [
        I2c::write_read(A, vec![0x00], vec![0xE5]).with_error(nack()),
        I2c::write_read(A, vec![0x00], vec![0xE5]),
        I2c::write(A, vec![0x31, 0x08]).with_error(nack()),
        I2c::write_read(A, vec![0x32], vec![0; 6]).with_error(nack()),
    ];
    let mut acc = Adxl345::new(I2cMock::new(&tx), A);
    assert_eq!(acc.init(), Err(Error::Comm(nack())));
    assert_eq!(acc.init(), Err(Error::Comm(nack())));
    assert_eq!(acc.read_raw(), Err(Error::Comm(nack())));
    acc.destroy().done();
}

#[test]
fn reads_data_registers_little_endian() {
    // x = 0xFF00 = -256, y = 0x0080 = 128, z = 0x00DE = 222.
    let tx = [I2c::write_read(
        A,
        vec![0x32],
        vec![0x00, 0xFF, 0x80, 0x00, 0xDE, 0x00],
    )];
    let mut acc = Adxl345::new(I2cMock::new(&tx), A);
    assert_eq!(acc.read_raw(), Ok([-256, 128, 222]));
    acc.destroy().done();
}

#[test]
fn roll_and_pitch_from_gravity() {
    // Level: (0, 0, 256) -> 0°, 0°.
    // Rolled 30° about X: y = 256 sin 30° = 128, z = 256 cos 30° = 221.7 ≈ 222
    //   -> roll = atan2(128, 222) = 29.97° (hand calculation), pitch 0.
    // Pitched: x = -128, z = 222 -> pitch = atan2(128, 222) = 29.97°, roll 0.
    let tx = [
        I2c::write_read(A, vec![0x32], vec![0, 0, 0, 0, 0x00, 0x01]),
        I2c::write_read(A, vec![0x32], vec![0, 0, 0x80, 0x00, 0xDE, 0x00]),
        I2c::write_read(A, vec![0x32], vec![0x80, 0xFF, 0, 0, 0xDE, 0x00]),
        // Free fall: all zero.
        I2c::write_read(A, vec![0x32], vec![0; 6]),
    ];
    let mut acc = Adxl345::new(I2cMock::new(&tx), A);
    let level = acc.read_inclination().unwrap();
    assert!(level.roll_deg.abs() < 1e-6 && level.pitch_deg.abs() < 1e-6);
    let rolled = acc.read_inclination().unwrap();
    assert!((rolled.roll_deg - 29.966).abs() < 0.01, "{rolled:?}");
    assert!(rolled.pitch_deg.abs() < 1e-6);
    let pitched = acc.read_inclination().unwrap();
    assert!((pitched.pitch_deg - 29.966).abs() < 0.01, "{pitched:?}");
    assert!(pitched.roll_deg.abs() < 1e-6);
    assert_eq!(acc.read_inclination(), Err(Error::NoGravity));
    acc.destroy().done();
}
