//! TWI master at 100 kHz as `embedded_hal::i2c::I2c` (ATmega2560 datasheet
//! §24 / ATmega328P §22 "2-wire Serial Interface": bit-rate formula, TWCR
//! sequencing, status codes of "Master Transmitter Mode" and "Master
//! Receiver Mode"). Polled, 7-bit addresses; every wait for TWINT (and for
//! TWSTO after a STOP) is bounded, so a missing, stuck or stretching device
//! is an error, never a hang.

use core::cell::RefCell;

use embedded_hal::i2c::{ErrorKind, ErrorType, NoAcknowledgeSource, Operation, SevenBitAddress};

use super::{chip, CPU_HZ};

/// SCL frequency.
const SCL_HZ: u32 = 100_000;
/// SCL = CPU / (16 + 2·TWBR·prescaler) with prescaler 1 → TWBR = 72 at 16 MHz.
const TWBR_100KHZ: u8 = ((CPU_HZ / SCL_HZ - 16) / 2) as u8;

/// Polls of TWINT before a transfer step is given up. One byte plus its
/// acknowledge is 9 SCL periods = 90 µs = 1,440 cycles at 100 kHz; one poll
/// (load TWCR, test, loop) takes about 6–8 cycles, so 30,000 polls are about
/// 12–15 ms: over 100 byte times, room for a device that stretches SCL.
const TWINT_POLL_LIMIT: u16 = 30_000;

// Status codes (TWSR & 0xF8).
const BUS_ERROR: u8 = 0x00;
const START: u8 = 0x08;
const REPEATED_START: u8 = 0x10;
const SLA_W_ACK: u8 = 0x18;
const SLA_W_NACK: u8 = 0x20;
const DATA_W_ACK: u8 = 0x28;
const DATA_W_NACK: u8 = 0x30;
const ARBITRATION_LOST: u8 = 0x38;
const SLA_R_ACK: u8 = 0x40;
const SLA_R_NACK: u8 = 0x48;
const DATA_R_ACK: u8 = 0x50;
const DATA_R_NACK: u8 = 0x58;

/// Why a TWI transaction failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TwiError {
    /// The device did not acknowledge its address (0x20, 0x48) or a data
    /// byte (0x30).
    NoAcknowledge(NoAcknowledgeSource),
    /// Another master won the bus (0x38).
    ArbitrationLoss,
    /// Illegal START/STOP on the bus (0x00) or a status the sequence does
    /// not allow; the raw status (TWSR & 0xF8) is kept.
    Bus(u8),
    /// TWINT (or the end of a STOP) did not come within
    /// [`TWINT_POLL_LIMIT`] polls; the TWI was reset.
    Timeout,
    /// A [`SharedI2c`] found the bus borrowed by another device's
    /// transaction (only possible if a driver were called from inside
    /// another's, or from an interrupt); nothing was sent.
    BusInUse,
}

impl embedded_hal::i2c::Error for TwiError {
    fn kind(&self) -> ErrorKind {
        match *self {
            TwiError::NoAcknowledge(source) => ErrorKind::NoAcknowledge(source),
            TwiError::ArbitrationLoss => ErrorKind::ArbitrationLoss,
            TwiError::Bus(_) => ErrorKind::Bus,
            TwiError::Timeout | TwiError::BusInUse => ErrorKind::Other,
        }
    }
}

/// The TWI as an I2C master (SDA/SCL: PD1/PD0 = Mega D20/D21; PC4/PC5 = Uno
/// A4/A5). External pull-ups are expected; the internal ones are not
/// enabled.
pub struct I2c {
    twi: chip::TWI,
}

impl I2c {
    /// Takes the TWI and sets it up for 100 kHz (prescaler 1, TWBR 72).
    pub fn new(twi: chip::TWI) -> Self {
        twi.twsr().write(|w| w.twps().prescaler_1());
        twi.twbr().write(|w| w.set(TWBR_100KHZ));
        twi.twcr().write(|w| w.twen().set_bit());
        I2c { twi }
    }

    /// Gives the TWI back (still enabled).
    pub fn release(self) -> chip::TWI {
        self.twi
    }

    /// Waits for TWINT; the status (TWSR & 0xF8).
    fn wait(&mut self) -> Result<u8, TwiError> {
        for _ in 0..TWINT_POLL_LIMIT {
            if self.twi.twcr().read().twint().bit_is_set() {
                return Ok(self.twi.twsr().read().bits() & 0xF8);
            }
        }
        Err(TwiError::Timeout)
    }

    /// (Repeated) START, then SLA+R/W; checks both statuses.
    fn address(&mut self, address: u8, read: bool) -> Result<(), TwiError> {
        self.twi
            .twcr()
            .write(|w| w.twint().set_bit().twsta().set_bit().twen().set_bit());
        match self.wait()? {
            START | REPEATED_START => {}
            status => return Err(status_error(status)),
        }
        let sla = (address & 0x7F) << 1 | u8::from(read);
        self.twi.twdr().write(|w| w.set(sla));
        self.twi
            .twcr()
            .write(|w| w.twint().set_bit().twen().set_bit());
        // simavr 1.6 (the Debian/Ubuntu package) answers SLA+W with the
        // data codes 0x28/0x30 instead of 0x18/0x20 (fixed in later
        // simavr); the silicon never gives 0x28/0x30 in this state, so
        // taking them as the address ACK/NACK changes nothing on a board.
        match (read, self.wait()?) {
            (false, SLA_W_ACK | DATA_W_ACK) | (true, SLA_R_ACK) => Ok(()),
            (false, SLA_W_NACK | DATA_W_NACK) | (true, SLA_R_NACK) => {
                Err(TwiError::NoAcknowledge(NoAcknowledgeSource::Address))
            }
            (_, status) => Err(status_error(status)),
        }
    }

    fn write_byte(&mut self, byte: u8) -> Result<(), TwiError> {
        self.twi.twdr().write(|w| w.set(byte));
        self.twi
            .twcr()
            .write(|w| w.twint().set_bit().twen().set_bit());
        match self.wait()? {
            DATA_W_ACK => Ok(()),
            DATA_W_NACK => Err(TwiError::NoAcknowledge(NoAcknowledgeSource::Data)),
            status => Err(status_error(status)),
        }
    }

    /// Receives one byte, acknowledging it unless it is the last one.
    fn read_byte(&mut self, ack: bool) -> Result<u8, TwiError> {
        if ack {
            self.twi
                .twcr()
                .write(|w| w.twint().set_bit().twea().set_bit().twen().set_bit());
        } else {
            self.twi
                .twcr()
                .write(|w| w.twint().set_bit().twen().set_bit());
        }
        match (ack, self.wait()?) {
            (true, DATA_R_ACK) | (false, DATA_R_NACK) => Ok(self.twi.twdr().read().bits()),
            (_, status) => Err(status_error(status)),
        }
    }

    /// STOP, then waits (bounded) until the hardware has sent it (TWSTO
    /// clears).
    fn stop(&mut self) -> Result<(), TwiError> {
        self.twi
            .twcr()
            .write(|w| w.twint().set_bit().twsto().set_bit().twen().set_bit());
        for _ in 0..TWINT_POLL_LIMIT {
            if self.twi.twcr().read().twsto().bit_is_clear() {
                return Ok(());
            }
        }
        Err(TwiError::Timeout)
    }

    /// Leaves the bus after a failed transaction: no STOP after a lost
    /// arbitration (the TWI is already in slave mode, the other master owns
    /// the bus), a reset of the TWI after a timeout, a STOP otherwise.
    fn recover(&mut self, error: TwiError) {
        match error {
            TwiError::ArbitrationLoss => {
                self.twi
                    .twcr()
                    .write(|w| w.twint().set_bit().twen().set_bit());
            }
            TwiError::Timeout => self.reset(),
            // Never produced here: the bus was not touched.
            TwiError::BusInUse => {}
            TwiError::NoAcknowledge(_) | TwiError::Bus(_) => {
                if self.stop().is_err() {
                    self.reset();
                }
            }
        }
    }

    /// Disables and re-enables the TWI, which releases SDA/SCL and clears
    /// any transfer in progress.
    fn reset(&mut self) {
        self.twi.twcr().write(|w| w.twen().clear_bit());
        self.twi.twcr().write(|w| w.twen().set_bit());
    }

    fn run(&mut self, address: u8, operations: &mut [Operation<'_>]) -> Result<(), TwiError> {
        let count = operations.len();
        // Whether the previous operation was a read (None before the first).
        let mut previous_read: Option<bool> = None;
        for index in 0..count {
            // The direction of the next operation decides whether the last
            // byte of a read is acknowledged (a read that continues) or not.
            let next_is_read = matches!(operations.get(index + 1), Some(Operation::Read(_)));
            let Some(operation) = operations.get_mut(index) else {
                break;
            };
            match operation {
                Operation::Write(bytes) => {
                    if previous_read != Some(false) {
                        self.address(address, false)?;
                    }
                    previous_read = Some(false);
                    for &byte in bytes.iter() {
                        self.write_byte(byte)?;
                    }
                }
                Operation::Read(buffer) => {
                    let first_of_group = previous_read != Some(true);
                    if first_of_group {
                        self.address(address, true)?;
                    }
                    previous_read = Some(true);
                    let len = buffer.len();
                    for (i, slot) in buffer.iter_mut().enumerate() {
                        let last = i + 1 == len && !next_is_read;
                        *slot = self.read_byte(!last)?;
                    }
                    // After SLA+R the master must clock at least one byte
                    // before a STOP or a repeated START: an empty read that
                    // ends its group reads one byte (not acknowledged) and
                    // drops it.
                    if len == 0 && first_of_group && !next_is_read {
                        self.read_byte(false)?;
                    }
                }
            }
        }
        Ok(())
    }
}

/// The error a status that the current step does not expect stands for.
fn status_error(status: u8) -> TwiError {
    match status {
        ARBITRATION_LOST => TwiError::ArbitrationLoss,
        BUS_ERROR => TwiError::Bus(BUS_ERROR),
        other => TwiError::Bus(other),
    }
}

impl ErrorType for I2c {
    type Error = TwiError;
}

impl embedded_hal::i2c::I2c<SevenBitAddress> for I2c {
    /// START, each operation (SLA+W or SLA+R with a repeated START whenever
    /// the direction changes; consecutive operations of one direction share
    /// one address phase), STOP. An empty transaction does nothing.
    fn transaction(
        &mut self,
        address: SevenBitAddress,
        operations: &mut [Operation<'_>],
    ) -> Result<(), TwiError> {
        if operations.is_empty() {
            return Ok(());
        }
        match self.run(address, operations) {
            Ok(()) => self.stop().inspect_err(|_| self.reset()),
            Err(error) => {
                self.recover(error);
                Err(error)
            }
        }
    }
}

/// One device's handle on a TWI shared by several drivers (the DS3231, the
/// compass and the accelerometer of the Mega). Like `embedded-hal-bus`'s
/// `RefCellDevice`, but a bus already borrowed is an error,
/// [`TwiError::BusInUse`], not a panic: the images keep no panic path.
#[derive(Clone, Copy)]
pub struct SharedI2c<'a> {
    bus: &'a RefCell<I2c>,
}

impl<'a> SharedI2c<'a> {
    /// A handle on `bus`.
    pub fn new(bus: &'a RefCell<I2c>) -> Self {
        SharedI2c { bus }
    }
}

impl ErrorType for SharedI2c<'_> {
    type Error = TwiError;
}

impl embedded_hal::i2c::I2c<SevenBitAddress> for SharedI2c<'_> {
    /// The whole transaction on the bus, or [`TwiError::BusInUse`].
    fn transaction(
        &mut self,
        address: SevenBitAddress,
        operations: &mut [Operation<'_>],
    ) -> Result<(), TwiError> {
        let mut bus = self.bus.try_borrow_mut().map_err(|_| TwiError::BusInUse)?;
        bus.transaction(address, operations)
    }
}
