//! QMC5883L transactions, written from the QST datasheet register map
//! (address 0x0D; 06h status DRDY/OVL/DOR; 09h control 1; 0Bh SET/RESET = 0x01;
//! 0Dh chip ID = 0xFF; data 00h..05h little-endian).

use drivers::compass::qmc5883l::{Config, DataRate, Error, OverSampling, Qmc5883l, Range};
use drivers::compass::Magnetometer;
use embedded_hal::i2c::{ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as T};

const ADDR: u8 = 0x0D;

fn init_transactions(control1: u8) -> Vec<T> {
    vec![
        T::write_read(ADDR, vec![0x0D], vec![0xFF]),
        T::write(ADDR, vec![0x0B, 0x01]),
        T::write(ADDR, vec![0x09, control1]),
    ]
}

#[test]
fn init_default_config_writes_0x11() {
    // OSR 512 (00), RNG 8 G (01), ODR 10 Hz (00), MODE continuous (01) -> 0b0001_0001.
    let mut i2c = I2cMock::new(&init_transactions(0x11));
    let dev = Qmc5883l::new(i2c.clone(), Config::default()).unwrap();
    dev.destroy();
    i2c.done();
}

#[test]
fn init_custom_config_bits() {
    // OSR 64 (11), RNG 2 G (00), ODR 200 Hz (11), continuous (01) -> 0b1100_1101 = 0xCD.
    let cfg = Config {
        rate: DataRate::Hz200,
        range: Range::Gauss2,
        oversampling: OverSampling::X64,
    };
    let mut i2c = I2cMock::new(&init_transactions(0xCD));
    Qmc5883l::new(i2c.clone(), cfg).unwrap().destroy();
    i2c.done();
}

#[test]
fn wrong_chip_id_is_reported() {
    let mut i2c = I2cMock::new(&[T::write_read(ADDR, vec![0x0D], vec![0x3C])]);
    assert_eq!(
        Qmc5883l::new(i2c.clone(), Config::default()).err(),
        Some(Error::WrongChip(0x3C))
    );
    i2c.done();
}

#[test]
fn nack_during_init_is_comm_error() {
    let nack = ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address);
    let mut i2c = I2cMock::new(&[T::write_read(ADDR, vec![0x0D], vec![0xFF]).with_error(nack)]);
    assert_eq!(
        Qmc5883l::new(i2c.clone(), Config::default()).err(),
        Some(Error::Comm(nack))
    );
    i2c.done();
}

#[test]
fn read_sample_little_endian_and_scaled() {
    let mut ex = init_transactions(0x11);
    // Status: DRDY only. X = 0x0BB8 = 3000 (1 G at 8 G range), Y = -1500 = 0xFA24, Z = 0x0001.
    ex.push(T::write_read(ADDR, vec![0x06], vec![0b001]));
    ex.push(T::write_read(
        ADDR,
        vec![0x00],
        vec![0xB8, 0x0B, 0x24, 0xFA, 0x01, 0x00],
    ));
    let mut i2c = I2cMock::new(&ex);
    let mut dev = Qmc5883l::new(i2c.clone(), Config::default()).unwrap();
    let g = dev.read_gauss().unwrap();
    assert_eq!((g.x, g.y, g.z), (1.0, -0.5, 1.0 / 3000.0));
    dev.destroy();
    i2c.done();
}

#[test]
fn not_ready_reads_only_status() {
    let mut ex = init_transactions(0x11);
    ex.push(T::write_read(ADDR, vec![0x06], vec![0b100])); // DOR set, DRDY clear
    ex.push(T::write_read(ADDR, vec![0x06], vec![0b100]));
    let mut i2c = I2cMock::new(&ex);
    let mut dev = Qmc5883l::new(i2c.clone(), Config::default()).unwrap();
    let s = dev.status().unwrap();
    assert!(!s.data_ready && !s.overflow && s.data_skipped);
    assert_eq!(dev.read_raw(), Err(Error::NotReady));
    dev.destroy();
    i2c.done();
}

#[test]
fn overflow_flag_is_an_error_after_data_read() {
    let mut ex = init_transactions(0x11);
    ex.push(T::write_read(ADDR, vec![0x06], vec![0b011])); // DRDY + OVL
    ex.push(T::write_read(
        ADDR,
        vec![0x00],
        vec![0xFF, 0x7F, 0, 0, 0, 0],
    ));
    let mut i2c = I2cMock::new(&ex);
    let mut dev = Qmc5883l::new(i2c.clone(), Config::default()).unwrap();
    assert_eq!(dev.read_raw(), Err(Error::Overflow));
    dev.destroy();
    i2c.done();
}

#[test]
fn nack_on_data_read_and_standby() {
    let nack = ErrorKind::NoAcknowledge(NoAcknowledgeSource::Data);
    let mut ex = init_transactions(0x11);
    ex.push(T::write_read(ADDR, vec![0x06], vec![0b001]));
    ex.push(T::write_read(ADDR, vec![0x00], vec![0; 6]).with_error(nack));
    ex.push(T::write(ADDR, vec![0x09, 0x10])); // standby keeps OSR/RNG/ODR, MODE = 00
    ex.push(T::write(ADDR, vec![0x0A, 0x80])); // soft reset
    let mut i2c = I2cMock::new(&ex);
    let mut dev = Qmc5883l::new(i2c.clone(), Config::default()).unwrap();
    assert_eq!(dev.read_raw(), Err(Error::Comm(nack)));
    dev.standby().unwrap();
    dev.soft_reset().unwrap();
    dev.destroy();
    i2c.done();
}
