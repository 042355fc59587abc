//! Modbus RTU master and the WitMotion inclinometer, transaction-exact.
//!
//! CRC values were computed independently with a Python bit-loop
//! implementation of CRC-16/MODBUS (poly 0xA001 reflected, init 0xFFFF),
//! which itself gives the catalogue check value 0x4B37 for "123456789".
//! Response angles: raw 0x071C = 1820 -> 1820/32768*180 = 9.99755859375°,
//! raw 0xFC17 = -1001 -> -5.4986572265625°.

mod common;

use common::{Event, MockDePin, MockSerial};
use drivers::tilt::modbus::{crc16_modbus, read_holding_request, Error, Exception, Timeout};
use drivers::tilt::witmotion::DEFAULT_ADDRESS;
use drivers::tilt::WitInclinometer;
use embedded_hal::delay::DelayNs;

/// Counts the time asked of it.
#[derive(Debug, Default)]
struct CountingDelay {
    total_ns: u64,
}

impl DelayNs for CountingDelay {
    fn delay_ns(&mut self, ns: u32) {
        self.total_ns += u64::from(ns);
    }
}

/// 0x50 0x03 0x003D 0x0002 + CRC 0x4658 (low byte first).
const REQUEST: [u8; 8] = [0x50, 0x03, 0x00, 0x3D, 0x00, 0x02, 0x58, 0x46];
const RESPONSE: [u8; 9] = [0x50, 0x03, 0x04, 0x07, 0x1C, 0xFC, 0x17, 0x7B, 0x4A];
/// Exception 0x02, illegal data address.
const EXCEPTION: [u8; 5] = [0x50, 0x83, 0x02, 0x91, 0x20];

const TIMEOUT: Timeout = Timeout {
    timeout_us: 1_000,
    poll_us: 100,
};

fn sensor(rx: &[u8], chunk: usize) -> WitInclinometer<MockSerial, MockDePin, CountingDelay> {
    let serial = MockSerial::new(rx, chunk);
    let de = MockDePin::new(serial.log());
    WitInclinometer::new(
        serial,
        de,
        CountingDelay::default(),
        DEFAULT_ADDRESS,
        TIMEOUT,
    )
}

fn sent_request() -> Vec<Event> {
    vec![
        Event::DeHigh,
        Event::Write(REQUEST.to_vec()),
        Event::Flush,
        Event::DeLow,
    ]
}

#[test]
fn crc_known_vectors() {
    assert_eq!(crc16_modbus(b"123456789"), 0x4B37);
    // Modbus over Serial Line spec example and a common textbook frame.
    assert_eq!(crc16_modbus(&[0x11, 0x03, 0x00, 0x6B, 0x00, 0x03]), 0x8776);
    assert_eq!(crc16_modbus(&[0x01, 0x03, 0x00, 0x00, 0x00, 0x0A]), 0xCDC5);
    assert_eq!(
        read_holding_request(0x11, 0x006B, 3),
        [0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87]
    );
    assert_eq!(read_holding_request(0x50, 0x3D, 2), REQUEST);
    // A frame with its CRC appended has CRC 0.
    assert_eq!(crc16_modbus(&RESPONSE), 0);
}

#[test]
fn reads_roll_and_pitch() {
    for chunk in [1, 3, 64] {
        let mut s = sensor(&RESPONSE, chunk);
        let incl = s.read().unwrap();
        assert_eq!(f64::from(incl.roll_deg), 9.997_558_593_75);
        assert_eq!(f64::from(incl.pitch_deg), -5.498_657_226_562_5);
        let (serial, _, delay) = s.destroy();
        assert_eq!(*serial.log().borrow(), sent_request());
        assert_eq!(serial.remaining(), 0);
        assert_eq!(delay.total_ns, 0, "bytes were ready: no waiting");
    }
}

#[test]
fn exception_response() {
    let mut s = sensor(&EXCEPTION, 2);
    assert_eq!(
        s.read(),
        Err(Error::Exception(Exception::IllegalDataAddress))
    );
    let (serial, _, _) = s.destroy();
    assert_eq!(*serial.log().borrow(), sent_request());
}

#[test]
fn crc_error() {
    let mut bad = RESPONSE;
    bad[4] ^= 0x01;
    let mut s = sensor(&bad, 9);
    assert_eq!(s.read(), Err(Error::Crc));
    let mut bad_ex = EXCEPTION;
    bad_ex[4] ^= 0x80;
    let mut s = sensor(&bad_ex, 9);
    assert_eq!(s.read(), Err(Error::Crc));
}

#[test]
fn timeout_without_answer_spends_the_budget() {
    let mut s = sensor(&[], 1);
    assert_eq!(s.read(), Err(Error::Timeout));
    let (serial, _, delay) = s.destroy();
    assert_eq!(*serial.log().borrow(), sent_request());
    // 1000 µs budget polled every 100 µs: 10 waits.
    assert_eq!(delay.total_ns, 1_000_000);
}

#[test]
fn timeout_in_the_middle_of_a_response() {
    let mut s = sensor(&RESPONSE[..5], 1);
    assert_eq!(s.read(), Err(Error::Timeout));
    let (serial, _, delay) = s.destroy();
    assert_eq!(serial.remaining(), 0);
    assert_eq!(delay.total_ns, 1_000_000);
}

#[test]
fn answer_from_another_address_or_function() {
    // Same frame from address 0x51, CRC recomputed so only the address is wrong.
    let mut other = RESPONSE;
    other[0] = 0x51;
    let [lo, hi] = crc16_modbus(&other[..7]).to_le_bytes();
    other[7] = lo;
    other[8] = hi;
    let mut s = sensor(&other, 9);
    assert_eq!(s.read(), Err(Error::UnexpectedResponse));
    // Wrong byte count (2 instead of 4), valid CRC: 9 bytes still expected, so
    // build a 9-byte frame whose count field says 2.
    let mut short = RESPONSE;
    short[2] = 0x02;
    let [lo, hi] = crc16_modbus(&short[..7]).to_le_bytes();
    short[7] = lo;
    short[8] = hi;
    let mut s = sensor(&short, 9);
    assert_eq!(s.read(), Err(Error::UnexpectedResponse));
}

#[test]
fn serial_errors_release_the_bus() {
    let serial = MockSerial::new(&RESPONSE, 9).failing_writes();
    let log = serial.log();
    let mut s = WitInclinometer::new(
        serial,
        MockDePin::new(log.clone()),
        CountingDelay::default(),
        DEFAULT_ADDRESS,
        TIMEOUT,
    );
    assert_eq!(s.read(), Err(Error::Comm(common::SerialError)));
    assert_eq!(*log.borrow(), vec![Event::DeHigh, Event::DeLow]);

    let serial = MockSerial::new(&RESPONSE, 9).failing_reads();
    let log = serial.log();
    let mut s = WitInclinometer::new(
        serial,
        MockDePin::new(log.clone()),
        CountingDelay::default(),
        DEFAULT_ADDRESS,
        TIMEOUT,
    );
    assert_eq!(s.read(), Err(Error::Comm(common::SerialError)));
    assert_eq!(*log.borrow(), sent_request());
}

#[test]
fn de_pin_error() {
    use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    use embedded_hal_mock::eh1::MockError;
    let err = MockError::Io(std::io::ErrorKind::NotConnected);
    // DE fails to go high: nothing is sent.
    let de = Pin::new(&[T::set(State::High).with_error(err.clone())]);
    let serial = MockSerial::new(&RESPONSE, 9);
    let log = serial.log();
    let mut s = WitInclinometer::new(
        serial,
        de,
        CountingDelay::default(),
        DEFAULT_ADDRESS,
        TIMEOUT,
    );
    assert_eq!(s.read(), Err(Error::Pin(err.clone())));
    assert!(log.borrow().is_empty());
    let (_, mut de, _) = s.destroy();
    de.done();
    // DE fails to go low after sending: the request went out, the error is reported.
    let de = Pin::new(&[
        T::set(State::High),
        T::set(State::Low).with_error(err.clone()),
    ]);
    let serial = MockSerial::new(&RESPONSE, 9);
    let log = serial.log();
    let mut s = WitInclinometer::new(
        serial,
        de,
        CountingDelay::default(),
        DEFAULT_ADDRESS,
        TIMEOUT,
    );
    assert_eq!(s.read(), Err(Error::Pin(err)));
    assert_eq!(
        *log.borrow(),
        vec![Event::Write(REQUEST.to_vec()), Event::Flush]
    );
    let (_, mut de, _) = s.destroy();
    de.done();
}
