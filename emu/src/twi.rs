//! The TWI (I²C) bus the device models hang on, and an `embedded-hal` I²C
//! adapter over the same bus so that the repository's drivers can be run
//! against the models on the host.
//!
//! simavr's master-side messages (`avr_twi.c`, the TWI of simavr 1.7 as
//! vendored by `simavr-ffi` 1.2): `START` with the address byte
//! (7-bit address << 1 | R/W) after START or repeated START, to which an
//! addressed slave answers `ACK` with data bit 0 = 1; `WRITE` with a data
//! byte (slave answers `ACK`); `READ` (with `ACK` set when the master will
//! acknowledge the byte), to which the slave answers `READ` with the byte;
//! `STOP`. No answer means NACK.

use std::cell::{Cell, RefCell};
use std::rc::Rc;

/// simavr `TWI_COND_*` bits (`avr_twi.h`).
pub mod cond {
    /// START or repeated START with the address byte.
    pub const START: u8 = 1 << 0;
    /// STOP.
    pub const STOP: u8 = 1 << 1;
    /// Address phase.
    pub const ADDR: u8 = 1 << 2;
    /// Acknowledge.
    pub const ACK: u8 = 1 << 3;
    /// Master writes a byte.
    pub const WRITE: u8 = 1 << 4;
    /// Master reads a byte.
    pub const READ: u8 = 1 << 5;
}

/// Emulated time shared by the bus and the models: seconds of emulated time
/// since power-on (CPU time × timescale).
#[derive(Debug, Clone, Default)]
pub struct EmuClock(Rc<Cell<f64>>);

impl EmuClock {
    /// A clock at 0 s.
    pub fn new() -> Self {
        Self::default()
    }
    /// Emulated seconds since power-on.
    pub fn now_s(&self) -> f64 {
        self.0.get()
    }
    /// Sets the emulated time.
    pub fn set_s(&self, t: f64) {
        self.0.set(t)
    }
}

/// A slave device on the bus.
pub trait I2cDevice {
    /// Seven-bit address.
    fn address(&self) -> u8;
    /// START (or repeated START) addressed to this device; `read` is the R/W
    /// bit. Returns whether the device acknowledges.
    fn start(&mut self, read: bool, now_s: f64) -> bool;
    /// The master wrote `byte`; returns ACK.
    fn write(&mut self, byte: u8, now_s: f64) -> bool;
    /// The master reads one byte.
    fn read(&mut self, now_s: f64) -> u8;
    /// STOP.
    fn stop(&mut self, _now_s: f64) {}
}

/// A device shared with the harness (to inspect it during and after a run).
impl<T: I2cDevice> I2cDevice for Rc<RefCell<T>> {
    fn address(&self) -> u8 {
        self.borrow().address()
    }
    fn start(&mut self, read: bool, now_s: f64) -> bool {
        self.borrow_mut().start(read, now_s)
    }
    fn write(&mut self, byte: u8, now_s: f64) -> bool {
        self.borrow_mut().write(byte, now_s)
    }
    fn read(&mut self, now_s: f64) -> u8 {
        self.borrow_mut().read(now_s)
    }
    fn stop(&mut self, now_s: f64) {
        self.borrow_mut().stop(now_s)
    }
}

/// The bus: routes simavr's messages to the addressed device.
pub struct TwiBus {
    devices: Vec<Box<dyn I2cDevice>>,
    active: Option<usize>,
    clock: EmuClock,
    /// Transactions (START with address) seen, per 7-bit address.
    pub starts: [u32; 128],
}

impl TwiBus {
    /// An empty bus reading time from `clock`.
    pub fn new(clock: EmuClock) -> Self {
        TwiBus {
            devices: Vec::new(),
            active: None,
            clock,
            starts: [0; 128],
        }
    }

    /// Adds a device.
    pub fn attach(&mut self, dev: Box<dyn I2cDevice>) {
        self.devices.push(dev);
    }

    /// The device at `address`, to inspect it.
    pub fn device_mut(&mut self, address: u8) -> Option<&mut Box<dyn I2cDevice>> {
        self.devices.iter_mut().find(|d| d.address() == address)
    }

    /// One simavr master message; returns the slave's answer (msg, addr, data).
    pub fn message(&mut self, msg: u8, addr: u8, data: u8) -> Option<(u8, u8, u8)> {
        let now = self.clock.now_s();
        if msg & cond::STOP != 0 {
            if let Some(i) = self.active.take() {
                if let Some(d) = self.devices.get_mut(i) {
                    d.stop(now);
                }
            }
            return None;
        }
        if msg & cond::START != 0 {
            let seven = addr >> 1;
            let read = addr & 1 != 0;
            if let Some(n) = self.starts.get_mut(usize::from(seven & 0x7F)) {
                *n += 1;
            }
            self.active = self.devices.iter().position(|d| d.address() == seven);
            let i = self.active?;
            let ack = self.devices.get_mut(i)?.start(read, now);
            if !ack {
                self.active = None;
                return None;
            }
            return Some((cond::ACK, addr, 1));
        }
        let dev = self.devices.get_mut(self.active?)?;
        if msg & cond::WRITE != 0 {
            return dev.write(data, now).then_some((cond::ACK, addr, 1));
        }
        if msg & cond::READ != 0 {
            let byte = dev.read(now);
            return Some((cond::READ, addr, byte));
        }
        None
    }
}

/// Error of [`HostI2c`]: the addressed device did not acknowledge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Nack;

impl embedded_hal::i2c::Error for Nack {
    fn kind(&self) -> embedded_hal::i2c::ErrorKind {
        embedded_hal::i2c::ErrorKind::NoAcknowledge(embedded_hal::i2c::NoAcknowledgeSource::Unknown)
    }
}

/// `embedded-hal` I²C master over a [`TwiBus`] on the host: the drivers of
/// the repository talk to the models through the same message state machine
/// that simavr drives.
#[derive(Clone)]
pub struct HostI2c {
    /// The bus.
    pub bus: Rc<RefCell<TwiBus>>,
}

impl embedded_hal::i2c::ErrorType for HostI2c {
    type Error = Nack;
}

impl embedded_hal::i2c::I2c for HostI2c {
    fn transaction(
        &mut self,
        address: u8,
        operations: &mut [embedded_hal::i2c::Operation<'_>],
    ) -> Result<(), Nack> {
        use embedded_hal::i2c::Operation;
        let mut bus = self.bus.borrow_mut();
        let mut result = Ok(());
        for op in operations.iter_mut() {
            match op {
                Operation::Write(bytes) => {
                    if bus.message(cond::START, address << 1, 0).is_none() {
                        result = Err(Nack);
                        break;
                    }
                    for &b in bytes.iter() {
                        if bus.message(cond::WRITE, address << 1, b).is_none() {
                            result = Err(Nack);
                            break;
                        }
                    }
                }
                Operation::Read(buf) => {
                    if bus.message(cond::START, address << 1 | 1, 0).is_none() {
                        result = Err(Nack);
                        break;
                    }
                    let n = buf.len();
                    for (i, b) in buf.iter_mut().enumerate() {
                        let ack = if i + 1 < n { cond::ACK } else { 0 };
                        match bus.message(cond::READ | ack, address << 1 | 1, 0) {
                            Some((_, _, d)) => *b = d,
                            None => {
                                result = Err(Nack);
                                break;
                            }
                        }
                    }
                }
            }
            if result.is_err() {
                break;
            }
        }
        bus.message(cond::STOP, address << 1, 0);
        result
    }
}

/// A register-file device: the first byte written after a START-write sets
/// the register pointer, later bytes write registers; reads return
/// registers; the pointer auto-increments and wraps at `len` (the usual
/// scheme of the DS3231, QMC5883L and ADXL345 datasheets).
#[derive(Debug, Clone, Default)]
pub struct RegisterPointer {
    /// Current register address.
    pub pointer: u8,
    expect_pointer: bool,
}

impl RegisterPointer {
    /// On START: a write begins with the pointer byte.
    pub fn start(&mut self, read: bool) {
        self.expect_pointer = !read;
    }

    /// On a written byte: `None` when it was the pointer, else the register
    /// to write (and the pointer advances).
    pub fn write(&mut self, byte: u8, len: u8) -> Option<u8> {
        if self.expect_pointer {
            self.expect_pointer = false;
            self.pointer = byte;
            return None;
        }
        let r = self.pointer;
        self.pointer = next(r, len);
        Some(r)
    }

    /// On a read: the register to read (and the pointer advances).
    pub fn read(&mut self, len: u8) -> u8 {
        let r = self.pointer;
        self.pointer = next(r, len);
        r
    }
}

fn next(r: u8, len: u8) -> u8 {
    if r.wrapping_add(1) >= len {
        0
    } else {
        r + 1
    }
}
