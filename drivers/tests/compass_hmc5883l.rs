//! HMC5883L transactions, written from the Honeywell datasheet
//! (address 0x1E; ID "H43" at 0Ah; CRA 00h, CRB 01h, mode 02h; data 03h..08h
//! in X, Z, Y order, MSB first; status 09h RDY/LOCK; overflow reads -4096).

use drivers::compass::hmc5883l::{Averaging, Config, DataRate, Error, Gain, Hmc5883l};
use drivers::compass::Magnetometer;
use embedded_hal::i2c::{ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as T};

const ADDR: u8 = 0x1E;

fn init_transactions(cra: u8, crb: u8) -> Vec<T> {
    vec![
        T::write_read(ADDR, vec![0x0A], b"H43".to_vec()),
        T::write(ADDR, vec![0x00, cra]),
        T::write(ADDR, vec![0x01, crb]),
        T::write(ADDR, vec![0x02, 0x00]),
    ]
}

#[test]
fn init_default_is_datasheet_example() {
    // Datasheet: CRA 0x70 (8-average, 15 Hz, normal), gain 1.3 Ga -> CRB 0x20, mode 0x00.
    let mut i2c = I2cMock::new(&init_transactions(0x70, 0x20));
    Hmc5883l::new(i2c.clone(), Config::default())
        .unwrap()
        .destroy();
    i2c.done();
}

#[test]
fn init_custom_config_bits() {
    // MA 1 (00), DO 75 Hz (110), MS 00 -> 0b0001_1000 = 0x18; GN 8.1 Ga (111) -> 0xE0.
    let cfg = Config {
        averaging: Averaging::X1,
        rate: DataRate::Hz75,
        gain: Gain::Ga8_1,
    };
    let mut i2c = I2cMock::new(&init_transactions(0x18, 0xE0));
    Hmc5883l::new(i2c.clone(), cfg).unwrap().destroy();
    i2c.done();
}

#[test]
fn wrong_id_and_nack() {
    let mut i2c = I2cMock::new(&[T::write_read(ADDR, vec![0x0A], vec![0x48, 0x34, 0x34])]);
    assert_eq!(
        Hmc5883l::new(i2c.clone(), Config::default()).err(),
        Some(Error::WrongChip([0x48, 0x34, 0x34]))
    );
    i2c.done();

    let nack = ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address);
    let mut ex = vec![T::write_read(ADDR, vec![0x0A], b"H43".to_vec())];
    ex.push(T::write(ADDR, vec![0x00, 0x70]).with_error(nack));
    let mut i2c = I2cMock::new(&ex);
    assert_eq!(
        Hmc5883l::new(i2c.clone(), Config::default()).err(),
        Some(Error::Comm(nack))
    );
    i2c.done();
}

#[test]
fn read_sample_xzy_order_big_endian() {
    let mut ex = init_transactions(0x70, 0x20);
    // X = 1090 = 0x0442 (1 Ga at gain 1.3), Z = -545 = 0xFDDF, Y = 218 = 0x00DA.
    ex.push(T::write_read(ADDR, vec![0x09], vec![0x01]));
    ex.push(T::write_read(
        ADDR,
        vec![0x03],
        vec![0x04, 0x42, 0xFD, 0xDF, 0x00, 0xDA],
    ));
    let mut i2c = I2cMock::new(&ex);
    let mut dev = Hmc5883l::new(i2c.clone(), Config::default()).unwrap();
    let g = dev.read_gauss().unwrap();
    assert_eq!((g.x, g.y, g.z), (1.0, 0.2, -0.5));
    dev.destroy();
    i2c.done();
}

#[test]
fn not_ready_then_overflow_then_idle() {
    let mut ex = init_transactions(0x70, 0x20);
    ex.push(T::write_read(ADDR, vec![0x09], vec![0x02])); // LOCK only
    ex.push(T::write_read(ADDR, vec![0x09], vec![0x01]));
    // Z = -4096 = 0xF000: ADC overflow on that channel.
    ex.push(T::write_read(
        ADDR,
        vec![0x03],
        vec![0x00, 0x10, 0xF0, 0x00, 0x00, 0x20],
    ));
    ex.push(T::write(ADDR, vec![0x02, 0x03]));
    let mut i2c = I2cMock::new(&ex);
    let mut dev = Hmc5883l::new(i2c.clone(), Config::default()).unwrap();
    assert_eq!(dev.read_raw(), Err(Error::NotReady));
    assert_eq!(dev.read_raw(), Err(Error::Overflow));
    dev.idle().unwrap();
    dev.destroy();
    i2c.done();
}

#[test]
fn nack_on_status_read() {
    let nack = ErrorKind::NoAcknowledge(NoAcknowledgeSource::Data);
    let mut ex = init_transactions(0x70, 0x20);
    ex.push(T::write_read(ADDR, vec![0x09], vec![0x00]).with_error(nack));
    let mut i2c = I2cMock::new(&ex);
    let mut dev = Hmc5883l::new(i2c.clone(), Config::default()).unwrap();
    assert_eq!(dev.read_raw(), Err(Error::Comm(nack)));
    dev.destroy();
    i2c.done();
}
