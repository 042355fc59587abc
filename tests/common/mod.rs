//! Shared pieces of the whole-tracker tests on mocked buses (`hw_*`,
//! `time_site_*`, `firmware_*`, `servo_tracker`): an in-memory serial port for
//! NMEA, GPS epochs from the receiver model of the simulations, and DS3231
//! transactions written from the datasheet.
#![allow(dead_code)]

use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

use embedded_hal_mock::eh1::i2c::Transaction as I2c;
use sim::gps::{GpsReceiverModel, EPOCH_BUF_LEN};

/// DS3231 (Maxim 19-5170): 7-bit address 0x68; time registers 0x00..=0x06
/// (seconds, minutes, hours [bit 6 = 12 h mode], day of week 1..7, date,
/// month [bit 7 = century], year), all BCD; status register 0x0F, bit 7 =
/// OSF (oscillator stopped), bit 3 = EN32kHz (1 at power-on); control
/// register 0x0E (bit 7 = EOSC; 0x1C at power-on), read together with the
/// status register after setting the time.
pub const RTC_ADDR: u8 = 0x68;
pub const REG_SECONDS: u8 = 0x00;
pub const REG_CONTROL: u8 = 0x0E;
pub const REG_STATUS: u8 = 0x0F;
/// Control register at power-on (EOSC clear: the oscillator runs on battery).
pub const CONTROL_POWER_ON: u8 = 0x1C;
/// Status with OSF set (power-on value 0x88).
pub const STATUS_OSF: u8 = 0x88;
/// Status of a running clock (EN32kHz only).
pub const STATUS_RUNNING: u8 = 0x08;
/// What the driver writes back to clear OSF from 0x88: EN32kHz kept, A2F/A1F
/// written 1 (writing 1 leaves those alarm flags unchanged).
pub const STATUS_CLEAR_OSF: u8 = 0x0B;

/// Binary-coded decimal of 0..=99.
pub fn bcd(n: u32) -> u8 {
    assert!(n < 100);
    ((n / 10) << 4 | (n % 10)) as u8
}

/// A calendar instant of 2026-03-20 (a Friday: day-of-week register 6 when
/// Sunday is 1, as the driver numbers it), `secs` seconds after midnight UTC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DayTime {
    pub secs: u32,
}

impl DayTime {
    pub fn hms(&self) -> (u32, u32, u32) {
        (self.secs / 3600, self.secs / 60 % 60, self.secs % 60)
    }
}

/// The seven time registers of 2026-03-20 at `t`, 24-hour mode.
pub fn rtc_registers(t: DayTime) -> Vec<u8> {
    let (h, m, s) = t.hms();
    vec![bcd(s), bcd(m), bcd(h), 6, bcd(20), bcd(3), bcd(26)]
}

/// Status register read.
pub fn read_status(status: u8) -> I2c {
    I2c::write_read(RTC_ADDR, vec![REG_STATUS], vec![status])
}

/// Time register burst read returning `t`.
pub fn read_time(t: DayTime) -> I2c {
    I2c::write_read(RTC_ADDR, vec![REG_SECONDS], rtc_registers(t))
}

/// Setting the time to `t` on a chip whose status register reads `status`
/// (`STATUS_OSF` or `STATUS_RUNNING`): burst write from register 0, control
/// and status read, then the OSF clear only if OSF was set.
pub fn set_time(t: DayTime, status: u8) -> Vec<I2c> {
    let mut w = vec![REG_SECONDS];
    w.extend(rtc_registers(t));
    let mut tx = vec![
        I2c::write(RTC_ADDR, w),
        I2c::write_read(RTC_ADDR, vec![REG_CONTROL], vec![CONTROL_POWER_ON, status]),
    ];
    match status {
        STATUS_OSF => tx.push(I2c::write(RTC_ADDR, vec![REG_STATUS, STATUS_CLEAR_OSF])),
        STATUS_RUNNING => {}
        _ => panic!("set_time: status {status:#04x} not modelled"),
    }
    tx
}

/// Kano, where the GPS receiver of these tests is: 11.9683° N, 8.4261° E,
/// 480 m.
pub const KANO: (f64, f64, f64) = (11.9683, 8.4261, 480.0);

/// RMC + GGA of one epoch at 2026-03-20 `t`, with a fix (`valid`) or
/// without (status V, quality 0, no position), as the GPS receiver model
/// of the simulations (`sim::gps`) writes them for Kano.
pub fn gps_epoch(t: DayTime, valid: bool) -> String {
    let mut gps = GpsReceiverModel::new(KANO.0, KANO.1, KANO.2);
    gps.fix = valid;
    let mut buf = [0u8; EPOCH_BUF_LEN];
    let n = gps.epoch(motor::utc_at(t.secs), &mut buf).unwrap();
    String::from_utf8(buf[..n].to_vec()).unwrap()
}

/// A serial port reading from a shared in-memory buffer (the test writes
/// into the other handle).
#[derive(Debug, Clone, Default)]
pub struct MemSerial {
    pub rx: Rc<RefCell<VecDeque<u8>>>,
}

impl MemSerial {
    pub fn push(&self, s: &str) {
        self.rx.borrow_mut().extend(s.bytes());
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SerialError;

impl embedded_io::Error for SerialError {
    fn kind(&self) -> embedded_io::ErrorKind {
        embedded_io::ErrorKind::Other
    }
}

impl embedded_io::ErrorType for MemSerial {
    type Error = SerialError;
}

impl embedded_io::Read for MemSerial {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, SerialError> {
        let mut rx = self.rx.borrow_mut();
        let n = buf.len().min(rx.len());
        for slot in buf.iter_mut().take(n) {
            *slot = rx.pop_front().ok_or(SerialError)?;
        }
        Ok(n)
    }
}

impl embedded_io::ReadReady for MemSerial {
    fn read_ready(&mut self) -> Result<bool, SerialError> {
        Ok(!self.rx.borrow().is_empty())
    }
}

pub mod host_io;
pub mod motor;
pub mod mount;
pub mod servo;
