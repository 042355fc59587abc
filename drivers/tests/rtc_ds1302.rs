//! DS1302 three-wire protocol, transaction-exact against pin mocks.
//!
//! The expected pin sequences are written from the Maxim DS1302 datasheet
//! (19-5420), "Data Transfer Summary": SCLK low before CE rises; command byte
//! then data, LSB first, each bit set up before a rising SCLK edge; on reads
//! the chip drives bit 0 after the falling edge of the 8th command clock and
//! each further bit after each following falling edge. Command bytes: 0x81
//! read seconds, 0x8E write control, 0xBE/0xBF clock burst write/read.
//! Registers in burst order: seconds (bit 7 CH), minutes, hours (bit 7 12-hour
//! mode, bit 5 PM), date, month, day of week, year, control (bit 7 WP).

use drivers::rtc::{sync_from_gps, Clock, Ds1302, Ds1302Error};
use drivers::time::DateTime;
use embedded_hal_mock::eh1::delay::NoopDelay;
use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
use embedded_hal_mock::eh1::MockError;

#[derive(Default)]
struct Wire {
    ce: Vec<T>,
    clk: Vec<T>,
    io: Vec<T>,
}

fn level(bit: bool) -> State {
    if bit {
        State::High
    } else {
        State::Low
    }
}

impl Wire {
    fn start(&mut self) {
        self.clk.push(T::set(State::Low));
        self.ce.push(T::set(State::High));
    }
    fn stop(&mut self) {
        self.ce.push(T::set(State::Low));
    }
    fn send(&mut self, byte: u8, release_last: bool) {
        for bit in 0..8 {
            self.io.push(T::set(level(byte >> bit & 1 == 1)));
            self.clk.push(T::set(State::High));
            if bit == 7 && release_last {
                // Open-drain release so that the chip can drive I/O.
                self.io.push(T::set(State::High));
            }
            self.clk.push(T::set(State::Low));
        }
    }
    fn receive(&mut self, byte: u8) {
        for bit in 0..8 {
            self.io.push(T::get(level(byte >> bit & 1 == 1)));
            self.clk.push(T::set(State::High));
            self.clk.push(T::set(State::Low));
        }
    }
    fn write(&mut self, cmd: u8, data: &[u8]) {
        self.start();
        self.send(cmd, false);
        for &b in data {
            self.send(b, false);
        }
        self.stop();
    }
    fn read(&mut self, cmd: u8, data: &[u8]) {
        self.start();
        self.send(cmd, true);
        for &b in data {
            self.receive(b);
        }
        self.stop();
    }
    fn rtc(&self) -> Ds1302<Pin, Pin, Pin, NoopDelay> {
        Ds1302::new(
            Pin::new(&self.ce),
            Pin::new(&self.clk),
            Pin::new(&self.io),
            NoopDelay::new(),
        )
    }
}

fn done(rtc: Ds1302<Pin, Pin, Pin, NoopDelay>) {
    let (mut ce, mut clk, mut io, _) = rtc.destroy();
    ce.done();
    clk.done();
    io.done();
}

fn dt(y: u16, mo: u8, d: u8, h: u8, mi: u8, s: u8) -> DateTime {
    DateTime::new(y, mo, d, h, mi, s).unwrap()
}

/// 2024-03-10 12:34:56, a Sunday (day 1), burst order.
const REGS_2024_03_10: [u8; 7] = [0x56, 0x34, 0x12, 0x10, 0x03, 0x01, 0x24];

#[test]
fn burst_read_of_the_clock() {
    let mut w = Wire::default();
    w.read(0xBF, &REGS_2024_03_10);
    let mut rtc = w.rtc();
    assert_eq!(rtc.datetime(), Ok(dt(2024, 3, 10, 12, 34, 56)));
    done(rtc);
}

#[test]
fn twelve_hour_mode_is_converted() {
    let mut w = Wire::default();
    // 0xA1 = 12-hour, PM, 1 -> 13 h; 0x92 = 12-hour, AM, 12 -> 0 h; 0xB2 = 12 PM -> 12 h.
    w.read(0xBF, &[0x00, 0x00, 0xA1, 0x01, 0x01, 0x07, 0x00]);
    w.read(0xBF, &[0x00, 0x00, 0x92, 0x01, 0x01, 0x07, 0x00]);
    w.read(0xBF, &[0x00, 0x00, 0xB2, 0x01, 0x01, 0x07, 0x00]);
    let mut rtc = w.rtc();
    assert_eq!(rtc.datetime(), Ok(dt(2000, 1, 1, 13, 0, 0)));
    assert_eq!(rtc.datetime(), Ok(dt(2000, 1, 1, 0, 0, 0)));
    assert_eq!(rtc.datetime(), Ok(dt(2000, 1, 1, 12, 0, 0)));
    done(rtc);
}

#[test]
fn absent_chip_reads_as_invalid_state() {
    let mut w = Wire::default();
    w.read(0xBF, &[0xFF; 7]);
    w.read(0xBF, &[0x00; 7]);
    let mut rtc = w.rtc();
    assert_eq!(rtc.datetime(), Err(Ds1302Error::InvalidDeviceState));
    assert_eq!(rtc.datetime(), Err(Ds1302Error::InvalidDeviceState));
    done(rtc);
}

#[test]
fn clock_halt_is_lost_power() {
    let mut w = Wire::default();
    w.read(0x81, &[0x80]);
    w.read(0x81, &[0x59]);
    let mut rtc = w.rtc();
    assert_eq!(rtc.lost_power(), Ok(true));
    assert_eq!(rtc.lost_power(), Ok(false));
    done(rtc);
}

#[test]
fn set_clears_write_protect_then_burst_writes_with_wp() {
    let mut w = Wire::default();
    w.write(0x8E, &[0x00]);
    let mut regs = REGS_2024_03_10.to_vec();
    regs.push(0x80); // control: WP set again
    w.write(0xBE, &regs);
    let mut rtc = w.rtc();
    assert_eq!(rtc.set_datetime(&dt(2024, 3, 10, 12, 34, 56)), Ok(()));
    done(rtc);
}

#[test]
fn year_outside_2000_2099_is_refused() {
    let w = Wire::default();
    let mut rtc = w.rtc();
    assert_eq!(
        rtc.set_datetime(&dt(2100, 1, 1, 0, 0, 0)),
        Err(Ds1302Error::OutOfRange)
    );
    assert_eq!(
        rtc.set_datetime(&dt(1999, 12, 31, 0, 0, 0)),
        Err(Ds1302Error::OutOfRange)
    );
    done(rtc);
}

#[test]
fn pin_error_at_ce_aborts_the_transfer() {
    let err = MockError::Io(std::io::ErrorKind::NotConnected);
    let w = Wire {
        ce: vec![T::set(State::High).with_error(err.clone())],
        clk: vec![T::set(State::Low)],
        io: vec![],
    };
    let mut rtc = w.rtc();
    assert_eq!(rtc.lost_power(), Err(Ds1302Error::Comm(err)));
    done(rtc);
}

#[test]
fn pin_error_while_reading_still_drops_ce() {
    let err = MockError::Io(std::io::ErrorKind::NotConnected);
    let mut w = Wire::default();
    w.start();
    w.send(0x81, true);
    w.io.push(T::get(State::Low).with_error(err.clone()));
    w.stop();
    let mut rtc = w.rtc();
    assert_eq!(rtc.lost_power(), Err(Ds1302Error::Comm(err)));
    done(rtc);
}

#[test]
fn sync_from_gps_when_drifted() {
    // RTC running (CH = 0) at 12:34:50, GPS 12:34:56, limit 5 s: set.
    let mut w = Wire::default();
    w.read(0x81, &[0x50]);
    w.read(0xBF, &[0x50, 0x34, 0x12, 0x10, 0x03, 0x01, 0x24]);
    w.write(0x8E, &[0x00]);
    let mut regs = REGS_2024_03_10.to_vec();
    regs.push(0x80);
    w.write(0xBE, &regs);
    // Then, 4 s off: left alone.
    w.read(0x81, &[0x52]);
    w.read(0xBF, &[0x52, 0x34, 0x12, 0x10, 0x03, 0x01, 0x24]);
    let mut rtc = w.rtc();
    let gps = dt(2024, 3, 10, 12, 34, 56);
    assert_eq!(sync_from_gps(&mut rtc, &gps, 5), Ok(true));
    assert_eq!(sync_from_gps(&mut rtc, &gps, 5), Ok(false));
    done(rtc);
}
