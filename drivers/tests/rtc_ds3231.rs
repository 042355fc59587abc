//! DS3231 driver, transaction-exact against the I2C mock.
//!
//! Expected bytes from the Maxim DS3231 datasheet (19-5170): 7-bit address
//! 0x68; timekeeping registers 0x00..=0x06 = seconds, minutes, hours
//! (bit 6 = 12-hour mode, bit 5 = PM there), day of week (1..7), date,
//! month (bit 7 = century), year, all BCD, register pointer auto-incrementing;
//! control register 0x0E (bit 7 = EOSC; power-on value 0x1C); status register
//! 0x0F (bit 7 = OSF, bit 3 = EN32kHz, bits 1/0 = A2F/A1F, which writing 1
//! leaves unchanged; power-on value 0x88); temperature 0x11 (integer, two's
//! complement) and 0x12 (bits 7:6 = quarter degrees), e.g. 0x19 0x40 = +25.25 °C.
//! Weekdays (1 = Sunday) checked with Python's `date.isoweekday() % 7 + 1`.

use drivers::rtc::{sync_from_gps, Clock, Ds3231, Ds3231Error};
use drivers::time::DateTime;
use embedded_hal::i2c::{ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as I2c};

const ADDR: u8 = 0x68;
const REG_SECONDS: u8 = 0x00;
const REG_CONTROL: u8 = 0x0E;
const REG_STATUS: u8 = 0x0F;
const REG_TEMP_MSB: u8 = 0x11;
/// Control at power-on: EOSC 0, BBSQW 0, CONV 0, RS2/RS1 1, INTCN 1, alarms off.
const CONTROL_POWER_ON: u8 = 0x1C;
/// Status at power-on: OSF and EN32kHz set.
const STATUS_POWER_ON: u8 = 0x88;
/// Status of a running clock: EN32kHz only.
const STATUS_RUNNING: u8 = 0x08;
/// Status written to clear OSF from 0x88: EN32kHz kept, A2F/A1F written 1 (no change).
const STATUS_CLEAR_OSF: u8 = 0x0B;

/// 2026-06-21 (a Sunday, day 1) 12:34:56, registers 0x00..=0x06.
const JUNE_21: [u8; 7] = [0x56, 0x34, 0x12, 0x01, 0x21, 0x06, 0x26];

fn nack() -> ErrorKind {
    ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
}

fn dt(y: u16, mo: u8, d: u8, h: u8, mi: u8, s: u8) -> DateTime {
    DateTime::new(y, mo, d, h, mi, s).unwrap()
}

fn read_time(regs: [u8; 7]) -> I2c {
    I2c::write_read(ADDR, vec![REG_SECONDS], regs.to_vec())
}

fn write_time(regs: [u8; 7]) -> I2c {
    let mut w = vec![REG_SECONDS];
    w.extend(regs);
    I2c::write(ADDR, w)
}

fn read_control_status(control: u8, status: u8) -> I2c {
    I2c::write_read(ADDR, vec![REG_CONTROL], vec![control, status])
}

fn read_status(status: u8) -> I2c {
    I2c::write_read(ADDR, vec![REG_STATUS], vec![status])
}

/// Reads `regs` and returns what the driver made of them.
fn decode(regs: [u8; 7]) -> Result<DateTime, Ds3231Error<ErrorKind>> {
    let tx = [read_time(regs)];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    let r = rtc.datetime();
    rtc.destroy().done();
    r
}

#[test]
fn reads_a_known_time_in_24_hour_mode() {
    assert_eq!(decode(JUNE_21), Ok(dt(2026, 6, 21, 12, 34, 56)));
    // Hours 0x23: bit 5 is the 20-hour digit in 24-hour mode.
    assert_eq!(
        decode([0x59, 0x59, 0x23, 0x04, 0x31, 0x12, 0x99]),
        Ok(dt(2099, 12, 31, 23, 59, 59))
    );
}

#[test]
fn reads_12_hour_mode_by_converting_it() {
    // 0x61 = 12-hour mode, PM, 1 o'clock -> 13 h.
    let pm1 = [0x00, 0x00, 0x61, 0x01, 0x21, 0x06, 0x26];
    assert_eq!(decode(pm1), Ok(dt(2026, 6, 21, 13, 0, 0)));
    // 0x52 = 12 AM -> 0 h; 0x72 = 12 PM -> 12 h; 0x51 = 11 AM -> 11 h.
    let am12 = [0x00, 0x00, 0x52, 0x01, 0x21, 0x06, 0x26];
    assert_eq!(decode(am12), Ok(dt(2026, 6, 21, 0, 0, 0)));
    let pm12 = [0x00, 0x00, 0x72, 0x01, 0x21, 0x06, 0x26];
    assert_eq!(decode(pm12), Ok(dt(2026, 6, 21, 12, 0, 0)));
    let am11 = [0x00, 0x00, 0x51, 0x01, 0x21, 0x06, 0x26];
    assert_eq!(decode(am11), Ok(dt(2026, 6, 21, 11, 0, 0)));
}

#[test]
fn century_bit_is_21xx() {
    // Month 0x81 = century + January, year 00.
    assert_eq!(
        decode([0x00, 0x00, 0x00, 0x06, 0x01, 0x81, 0x00]),
        Ok(dt(2100, 1, 1, 0, 0, 0))
    );
    assert_eq!(
        decode([0x59, 0x59, 0x23, 0x03, 0x31, 0x92, 0x99]),
        Ok(dt(2199, 12, 31, 23, 59, 59))
    );
}

#[test]
fn impossible_register_contents_are_invalid_device_state() {
    let bad: [[u8; 7]; 10] = [
        // Never set / date 0.
        [0; 7],
        // Seconds digit 0x5A.
        [0x5A, 0x34, 0x12, 0x01, 0x21, 0x06, 0x26],
        // Year digit 0xA0.
        [0x56, 0x34, 0x12, 0x01, 0x21, 0x06, 0xA0],
        // Month 0 and month 13.
        [0x56, 0x34, 0x12, 0x01, 0x21, 0x00, 0x26],
        [0x56, 0x34, 0x12, 0x01, 0x21, 0x13, 0x26],
        // Hour 25 in 24-hour mode.
        [0x56, 0x34, 0x25, 0x01, 0x21, 0x06, 0x26],
        // 12-hour mode with hour 0 and hour 13.
        [0x56, 0x34, 0x40, 0x01, 0x21, 0x06, 0x26],
        [0x56, 0x34, 0x73, 0x01, 0x21, 0x06, 0x26],
        // 31 June.
        [0x56, 0x34, 0x12, 0x01, 0x31, 0x06, 0x26],
        // 2100-02-29: the chip counts 2100 as a leap year; the calendar does not.
        [0x00, 0x00, 0x00, 0x02, 0x29, 0x82, 0x00],
    ];
    for regs in bad {
        assert_eq!(
            decode(regs),
            Err(Ds3231Error::InvalidDeviceState),
            "{regs:02X?}"
        );
    }
    // An absent chip on a bus with pull-ups reads all ones.
    assert_eq!(decode([0xFF; 7]), Err(Ds3231Error::InvalidDeviceState));
}

#[test]
fn oscillator_stop_flag_is_lost_power() {
    let tx = [read_status(STATUS_POWER_ON), read_status(STATUS_RUNNING)];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.lost_power(), Ok(true));
    assert_eq!(rtc.lost_power(), Ok(false));
    rtc.destroy().done();
}

#[test]
fn set_writes_the_time_then_clears_eosc_and_osf() {
    let tx = [
        write_time(JUNE_21),
        // EOSC set (0x9C) and OSF set: both cleared, other bits kept.
        read_control_status(0x9C, STATUS_POWER_ON),
        I2c::write(ADDR, vec![REG_CONTROL, CONTROL_POWER_ON]),
        I2c::write(ADDR, vec![REG_STATUS, STATUS_CLEAR_OSF]),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    // Milliseconds are dropped.
    let t = dt(2026, 6, 21, 12, 34, 56).with_millis(999).unwrap();
    assert_eq!(rtc.set_datetime(&t), Ok(()));
    rtc.destroy().done();
}

#[test]
fn set_keeps_the_other_status_bits() {
    let tx = [
        write_time(JUNE_21),
        // Power-on control (EOSC clear: not written); OSF + BSY + A1F set,
        // EN32kHz off: OSF cleared, BSY as read, A2F/A1F written 1 (no change).
        read_control_status(CONTROL_POWER_ON, 0x85),
        I2c::write(ADDR, vec![REG_STATUS, 0x07]),
        // A running clock: nothing to clear, nothing written.
        write_time(JUNE_21),
        read_control_status(CONTROL_POWER_ON, STATUS_RUNNING),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    let t = dt(2026, 6, 21, 12, 34, 56);
    assert_eq!(rtc.set_datetime(&t), Ok(()));
    assert_eq!(rtc.set_datetime(&t), Ok(()));
    rtc.destroy().done();
}

#[test]
fn set_in_the_22nd_century_sets_the_century_bit() {
    // 2150-07-04 is a Saturday (7); 2100-01-01 a Friday (6).
    let tx = [
        write_time([0x05, 0x04, 0x03, 0x07, 0x04, 0x87, 0x50]),
        read_control_status(CONTROL_POWER_ON, STATUS_RUNNING),
        write_time([0x00, 0x00, 0x00, 0x06, 0x01, 0x81, 0x00]),
        read_control_status(CONTROL_POWER_ON, STATUS_RUNNING),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.set_datetime(&dt(2150, 7, 4, 3, 4, 5)), Ok(()));
    assert_eq!(rtc.set_datetime(&dt(2100, 1, 1, 0, 0, 0)), Ok(()));
    rtc.destroy().done();
}

#[test]
fn set_outside_2000_2199_is_refused_without_bus_traffic() {
    let mut rtc = Ds3231::new(I2cMock::new(&[]));
    for t in [dt(2200, 1, 1, 0, 0, 0), dt(1999, 12, 31, 23, 59, 59)] {
        assert_eq!(rtc.set_datetime(&t), Err(Ds3231Error::OutOfRange));
    }
    rtc.destroy().done();
}

#[test]
fn clear_lost_power_is_a_read_modify_write_of_the_status() {
    let tx = [
        read_status(STATUS_POWER_ON),
        I2c::write(ADDR, vec![REG_STATUS, STATUS_CLEAR_OSF]),
        // OSF already clear: no write.
        read_status(STATUS_RUNNING),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.clear_lost_power(), Ok(()));
    assert_eq!(rtc.clear_lost_power(), Ok(()));
    rtc.destroy().done();
}

#[test]
fn temperature_is_ten_bit_twos_complement() {
    let tx = [
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0x19, 0x40]),
        // +25.75 °C: 25 and three quarters.
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0x19, 0xC0]),
        // -25 °C: 0xE7 is -25 in two's complement, fraction 0.
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0xE7, 0x00]),
        // -0.25 °C: 10-bit two's complement 0x3FF.
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0xFF, 0xC0]),
        // The low six bits of 0x12 are not part of the value.
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0x00, 0x3F]),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(rtc.temperature_c(), Ok(25.25));
    assert_eq!(rtc.temperature_c(), Ok(25.75));
    assert_eq!(rtc.temperature_c(), Ok(-25.0));
    assert_eq!(rtc.temperature_c(), Ok(-0.25));
    assert_eq!(rtc.temperature_c(), Ok(0.0));
    rtc.destroy().done();
}

#[test]
fn nack_is_comm_error() {
    let t = dt(2026, 6, 21, 12, 34, 56);
    let tx = [
        I2c::write_read(ADDR, vec![REG_SECONDS], vec![0; 7]).with_error(nack()),
        write_time(JUNE_21).with_error(nack()),
        // The time written, the control/status read fails.
        write_time(JUNE_21),
        I2c::write_read(ADDR, vec![REG_CONTROL], vec![0, 0]).with_error(nack()),
        // The OSF clear fails.
        write_time(JUNE_21),
        read_control_status(CONTROL_POWER_ON, STATUS_POWER_ON),
        I2c::write(ADDR, vec![REG_STATUS, STATUS_CLEAR_OSF]).with_error(nack()),
        read_status(0).with_error(nack()),
        read_status(0).with_error(nack()),
        I2c::write_read(ADDR, vec![REG_TEMP_MSB], vec![0, 0]).with_error(nack()),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    let err = Ds3231Error::Comm(nack());
    assert_eq!(rtc.datetime(), Err(err));
    assert_eq!(rtc.set_datetime(&t), Err(err));
    assert_eq!(rtc.set_datetime(&t), Err(err));
    assert_eq!(rtc.set_datetime(&t), Err(err));
    assert_eq!(rtc.lost_power(), Err(err));
    assert_eq!(rtc.clear_lost_power(), Err(err));
    assert_eq!(rtc.temperature_c(), Err(err));
    rtc.destroy().done();
}

#[test]
fn sync_sets_only_past_the_drift_limit() {
    let gps = dt(2026, 6, 21, 12, 34, 56);
    let behind_2s = [0x54, 0x34, 0x12, 0x01, 0x21, 0x06, 0x26];
    let ahead_3s = [0x59, 0x34, 0x12, 0x01, 0x21, 0x06, 0x26];
    let tx = [
        // 1: powered, RTC 2 s behind, limit 2 s: not set.
        read_status(STATUS_RUNNING),
        read_time(behind_2s),
        // 2: powered, RTC 3 s ahead: set (nothing to clear).
        read_status(STATUS_RUNNING),
        read_time(ahead_3s),
        write_time(JUNE_21),
        read_control_status(CONTROL_POWER_ON, STATUS_RUNNING),
        // 3: OSF set: set without reading the time, then OSF cleared.
        read_status(STATUS_POWER_ON),
        write_time(JUNE_21),
        read_control_status(CONTROL_POWER_ON, STATUS_POWER_ON),
        I2c::write(ADDR, vec![REG_STATUS, STATUS_CLEAR_OSF]),
    ];
    let mut rtc = Ds3231::new(I2cMock::new(&tx));
    assert_eq!(sync_from_gps(&mut rtc, &gps, 2), Ok(false));
    assert_eq!(sync_from_gps(&mut rtc, &gps, 2), Ok(true));
    assert_eq!(sync_from_gps(&mut rtc, &gps, 2), Ok(true));
    rtc.destroy().done();
}
