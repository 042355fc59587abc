//! DS3231 through `ds323x`, transaction-exact against the I2C mock.
//!
//! Expected bytes from the Maxim DS3231 datasheet (19-5170): 7-bit address
//! 0x68; timekeeping registers 0x00..=0x06 = seconds, minutes, hours
//! (bit 6 = 12-hour mode, bit 5 = PM), day of week (1..7), date,
//! month (bit 7 = century), year, all BCD; status register 0x0F
//! (bit 7 = OSF, bit 3 = EN32kHz, bits 1/0 = A2F/A1F, which writing 1 leaves
//! unchanged; power-on value 0x88); temperature 0x11 (integer, two's
//! complement) and 0x12 (bits 7:6 = quarter degrees), e.g. 0x19 0x40 = +25.25 °C.

use drivers::rtc::{sync_from_gps, Clock, Ds3231, Ds3231Error};
use drivers::time::DateTime;
use embedded_hal::i2c::{ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};

const ADDR: u8 = 0x68;
const REG_SECONDS: u8 = 0x00;
const REG_STATUS: u8 = 0x0F;
const REG_TEMP_MSB: u8 = 0x11;
/// Status written to clear OSF: EN32kHz (power-on 1) kept, A2F/A1F written 1 (no change).
const STATUS_CLEAR_OSF: u8 = 0b0000_1011;

fn nack() -> ErrorKind {
    ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
}

fn dt(y: u16, mo: u8, d: u8, h: u8, mi: u8, s: u8) -> DateTime {
    DateTime::new(y, mo, d, h, mi, s).unwrap()
}

#[test]
fn reads_datetime_in_24_hour_mode() {
    // 2024-03-10 (a Sunday, day 1) 12:34:56.
    let tx = [I2c::write_read(
        ADDR,
        vec![REG_SECONDS],
        vec![0x56, 0x34, 0x12, 0x01, 0x10, 0x03, 0x24],
    )];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.datetime(), Ok(dt(2024, 3, 10, 12, 34, 56)));
    rtc.destroy().done();
}

#[test]
fn reads_12_hour_mode_and_century() {
    // Hours 0x61 = 12-hour mode, PM, 1 o'clock -> 13 h; month 0x81 = century + January.
    let tx = [I2c::write_read(
        ADDR,
        vec![REG_SECONDS],
        vec![0x00, 0x00, 0x61, 0x06, 0x01, 0x81, 0x00],
    )];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.datetime(), Ok(dt(2100, 1, 1, 13, 0, 0)));
    rtc.destroy().done();
}

#[test]
fn garbage_registers_are_invalid_device_state() {
    // Date 0 does not exist.
    let tx = [I2c::write_read(ADDR, vec![REG_SECONDS], vec![0; 7])];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.datetime(), Err(Ds3231Error::InvalidDeviceState));
    rtc.destroy().done();
}

#[test]
fn sets_datetime_then_clears_osf() {
    let tx = [
        I2c::write(
            ADDR,
            vec![REG_SECONDS, 0x56, 0x34, 0x12, 0x01, 0x10, 0x03, 0x24],
        ),
        I2c::write(ADDR, vec![REG_STATUS, STATUS_CLEAR_OSF]),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    let t = dt(2024, 3, 10, 12, 34, 56).with_millis(999).unwrap();
    assert_eq!(rtc.set_datetime(&t), Ok(()));
    rtc.destroy().done();
}

#[test]
fn set_outside_2000_2100_is_refused_without_bus_traffic() {
    let mut rtc = Ds3231::new(I2cMock::new(&[]));
    assert_eq!(
        rtc.set_datetime(&dt(1999, 12, 31, 0, 0, 0)),
        Err(Ds3231Error::OutOfRange)
    );
    rtc.destroy().done();
}

#[test]
fn oscillator_stop_flag_is_lost_power() {
    let tx = [
        I2c::write_read(ADDR, vec![REG_STATUS], vec![0x88]),
        I2c::write_read(ADDR, vec![REG_STATUS], vec![0x08]),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.lost_power(), Ok(true));
    assert_eq!(rtc.lost_power(), Ok(false));
    rtc.destroy().done();
}

#[test]
fn temperature() {
    let tx = [
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0x19, 0x40]),
        // -25 °C: 0xE7 is -25 in two's complement, fraction 0.
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0xE7, 0x00]),
        // -0.25 °C: 10-bit two's complement 0x3FF.
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0xFF, 0xC0]),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.temperature_c(), Ok(25.25));
    assert_eq!(rtc.temperature_c(), Ok(-25.0));
    assert_eq!(rtc.temperature_c(), Ok(-0.25));
    rtc.destroy().done();
}

#[test]
fn nack_is_comm_error() {
    let tx = [
        I2c::write_read(ADDR, vec![REG_SECONDS], vec![0; 7]).with_error(nack()),
        I2c::write(
            ADDR,
            vec![REG_SECONDS, 0x56, 0x34, 0x12, 0x01, 0x10, 0x03, 0x24],
        )
        .with_error(nack()),
        I2c::write_read(ADDR, vec![REG_STATUS], vec![0]).with_error(nack()),
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0, 0]).with_error(nack()),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.datetime(), Err(Ds3231Error::Comm(nack())));
    assert_eq!(
        rtc.set_datetime(&dt(2024, 3, 10, 12, 34, 56)),
        Err(Ds3231Error::Comm(nack()))
    );
    assert_eq!(rtc.lost_power(), Err(Ds3231Error::Comm(nack())));
    assert_eq!(rtc.temperature_c(), Err(Ds3231Error::Comm(nack())));
    rtc.destroy().done();
}

#[test]
fn sync_sets_only_past_the_drift_limit() {
    let gps = dt(2024, 3, 10, 12, 34, 56);
    let tx = [
        // 1: powered, RTC 2 s behind, limit 2 s: not set.
        I2c::write_read(ADDR, vec![REG_STATUS], vec![0x08]),
        I2c::write_read(
            ADDR,
            vec![REG_SECONDS],
            vec![0x54, 0x34, 0x12, 0x01, 0x10, 0x03, 0x24],
        ),
        // 2: powered, RTC 3 s ahead: set.
        I2c::write_read(ADDR, vec![REG_STATUS], vec![0x08]),
        I2c::write_read(
            ADDR,
            vec![REG_SECONDS],
            vec![0x59, 0x34, 0x12, 0x01, 0x10, 0x03, 0x24],
        ),
        I2c::write(
            ADDR,
            vec![REG_SECONDS, 0x56, 0x34, 0x12, 0x01, 0x10, 0x03, 0x24],
        ),
        I2c::write(ADDR, vec![REG_STATUS, STATUS_CLEAR_OSF]),
        // 3: OSF set: set without reading the time.
        I2c::write_read(ADDR, vec![REG_STATUS], vec![0x88]),
        I2c::write(
            ADDR,
            vec![REG_SECONDS, 0x56, 0x34, 0x12, 0x01, 0x10, 0x03, 0x24],
        ),
        I2c::write(ADDR, vec![REG_STATUS, STATUS_CLEAR_OSF]),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(sync_from_gps(&mut rtc, &gps, 2), Ok(false));
    assert_eq!(sync_from_gps(&mut rtc, &gps, 2), Ok(true));
    assert_eq!(sync_from_gps(&mut rtc, &gps, 2), Ok(true));
    rtc.destroy().done();
}
