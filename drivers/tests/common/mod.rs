//! Test doubles of our own for `embedded-io` serial ports (embedded-hal-mock
//! does not cover `embedded-io`), shared by the gps_* and tilt_* tests, and
//! a scripted ADC channel for the crate's own `adc::AdcChannel` trait.
#![allow(dead_code)]

use std::cell::RefCell;
use std::collections::VecDeque;
use std::convert::Infallible;
use std::rc::Rc;

/// One thing that happened on the mocked serial line or its DE pin, in order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Event {
    /// Driver-enable pin driven high (transmit).
    DeHigh,
    /// Driver-enable pin driven low (receive).
    DeLow,
    /// Bytes written.
    Write(Vec<u8>),
    /// `flush` called.
    Flush,
}

/// Error injected into the mock serial port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SerialError;

impl embedded_io::Error for SerialError {
    fn kind(&self) -> embedded_io::ErrorKind {
        embedded_io::ErrorKind::Other
    }
}

/// A scripted serial port: `read` returns the queued bytes at most `chunk`
/// at a time (0 = end of stream when empty), `write`/`flush` are logged.
#[derive(Debug, Clone)]
pub struct MockSerial {
    rx: VecDeque<u8>,
    chunk: usize,
    log: Rc<RefCell<Vec<Event>>>,
    fail_reads: bool,
    fail_writes: bool,
}

impl MockSerial {
    pub fn new(rx: &[u8], chunk: usize) -> Self {
        Self {
            rx: rx.iter().copied().collect(),
            chunk: chunk.max(1),
            log: Rc::new(RefCell::new(Vec::new())),
            fail_reads: false,
            fail_writes: false,
        }
    }
    /// Every read fails.
    pub fn failing_reads(mut self) -> Self {
        self.fail_reads = true;
        self
    }
    /// Every write fails.
    pub fn failing_writes(mut self) -> Self {
        self.fail_writes = true;
        self
    }
    /// The shared event log (give it to a [`MockDePin`] too).
    pub fn log(&self) -> Rc<RefCell<Vec<Event>>> {
        Rc::clone(&self.log)
    }
    /// Bytes not yet read.
    pub fn remaining(&self) -> usize {
        self.rx.len()
    }
}

impl embedded_io::ErrorType for MockSerial {
    type Error = SerialError;
}

impl embedded_io::Read for MockSerial {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, SerialError> {
        if self.fail_reads {
            return Err(SerialError);
        }
        let n = buf.len().min(self.chunk).min(self.rx.len());
        for slot in buf.iter_mut().take(n) {
            *slot = self.rx.pop_front().unwrap();
        }
        Ok(n)
    }
}

impl embedded_io::ReadReady for MockSerial {
    fn read_ready(&mut self) -> Result<bool, SerialError> {
        if self.fail_reads {
            return Err(SerialError);
        }
        Ok(!self.rx.is_empty())
    }
}

impl embedded_io::Write for MockSerial {
    fn write(&mut self, buf: &[u8]) -> Result<usize, SerialError> {
        if self.fail_writes {
            return Err(SerialError);
        }
        self.log.borrow_mut().push(Event::Write(buf.to_vec()));
        Ok(buf.len())
    }
    fn flush(&mut self) -> Result<(), SerialError> {
        self.log.borrow_mut().push(Event::Flush);
        Ok(())
    }
}

/// An RS-485 driver-enable pin that writes into the serial port's log, so
/// that tests see the exact order of DE changes and bytes sent.
#[derive(Debug, Clone)]
pub struct MockDePin {
    log: Rc<RefCell<Vec<Event>>>,
}

impl MockDePin {
    pub fn new(log: Rc<RefCell<Vec<Event>>>) -> Self {
        Self { log }
    }
}

impl embedded_hal::digital::ErrorType for MockDePin {
    type Error = Infallible;
}

impl embedded_hal::digital::OutputPin for MockDePin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.log.borrow_mut().push(Event::DeLow);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Infallible> {
        self.log.borrow_mut().push(Event::DeHigh);
        Ok(())
    }
}

/// Independent NMEA checksum check used by the tests: the two characters after
/// the last '*' must be the upper- or lower-case hex XOR of the characters
/// between the leading '$' and that '*'.
pub fn checksum_is_right(sentence: &str) -> bool {
    let Some(body_and_sum) = sentence.strip_prefix('$') else {
        return false;
    };
    let Some((body, sum)) = body_and_sum.rsplit_once('*') else {
        return false;
    };
    let Ok(expected) = u8::from_str_radix(sum, 16) else {
        return false;
    };
    sum.len() == 2
        && sum.bytes().all(|c| c.is_ascii_hexdigit())
        && body.bytes().fold(0u8, |a, b| a ^ b) == expected
}

/// Error injected into [`ScriptedAdc`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AdcError;

/// A scripted `drivers::adc::AdcChannel`: each `read_raw` takes the next
/// queued result (clones share the queue, like embedded-hal-mock's mocks);
/// reading past the end panics, and `done` asserts every queued reading was
/// taken.
#[derive(Debug, Clone)]
pub struct ScriptedAdc {
    readings: Rc<RefCell<VecDeque<Result<u16, AdcError>>>>,
    full_scale: u16,
}

impl ScriptedAdc {
    pub fn new(full_scale: u16, readings: &[Result<u16, AdcError>]) -> Self {
        Self {
            readings: Rc::new(RefCell::new(readings.iter().copied().collect())),
            full_scale,
        }
    }

    pub fn done(&self) {
        assert!(
            self.readings.borrow().is_empty(),
            "ADC readings left unread: {:?}",
            self.readings.borrow()
        );
    }
}

impl drivers::adc::AdcChannel for ScriptedAdc {
    type Error = AdcError;

    fn read_raw(&mut self) -> Result<u16, AdcError> {
        self.readings
            .borrow_mut()
            .pop_front()
            .expect("ScriptedAdc: no reading queued")
    }

    fn full_scale(&self) -> u16 {
        self.full_scale
    }
}
