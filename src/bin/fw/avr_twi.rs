//! Polled TWI (I²C) master of the ATmega328P / ATmega2560 (the same TWI
//! registers on both; datasheet "2-wire Serial Interface", status codes of
//! the master transmitter/receiver tables), 100 kHz at 16 MHz. Every wait is
//! bounded, so a missing or stuck device is an error, never a hang.

use crate::chip;

/// Why a transfer failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TwiError {
    /// The device did not acknowledge its address.
    AddressNack,
    /// The device did not acknowledge a data byte.
    DataNack,
    /// Bus error or arbitration lost (unexpected status).
    Bus,
    /// TWINT did not rise in time.
    Timeout,
}

// Status codes (TWSR & 0xF8), datasheet tables 22-2 and 22-3.
const START: u8 = 0x08;
const REPEATED_START: u8 = 0x10;
const SLA_W_ACK: u8 = 0x18;
const SLA_W_NACK: u8 = 0x20;
const DATA_W_ACK: u8 = 0x28;
const SLA_R_ACK: u8 = 0x40;
const SLA_R_NACK: u8 = 0x48;
const DATA_R_ACK: u8 = 0x50;
const DATA_R_NACK: u8 = 0x58;

/// Polls of TWINT before giving up (one byte at 100 kHz is ~90 µs, about
/// 1,440 cycles; a poll takes a few cycles).
const SPIN_LIMIT: u16 = 20_000;

/// The TWI master.
pub struct Twi {
    twi: chip::TWI,
}

impl Twi {
    /// 100 kHz: SCL = 16 MHz / (16 + 2·TWBR·1) → TWBR = 72.
    pub fn new(twi: chip::TWI) -> Self {
        twi.twsr().write(|w| w.twps().prescaler_1());
        twi.twbr().write(|w| w.set(72));
        twi.twcr().write(|w| w.twen().set_bit());
        Twi { twi }
    }

    fn wait(&mut self) -> Result<u8, TwiError> {
        for _ in 0..SPIN_LIMIT {
            if self.twi.twcr().read().twint().bit_is_set() {
                return Ok(self.twi.twsr().read().bits() & 0xF8);
            }
        }
        Err(TwiError::Timeout)
    }

    fn start(&mut self) -> Result<u8, TwiError> {
        self.twi
            .twcr()
            .write(|w| w.twint().set_bit().twsta().set_bit().twen().set_bit());
        self.wait()
    }

    fn send(&mut self, byte: u8) -> Result<u8, TwiError> {
        self.twi.twdr().write(|w| w.set(byte));
        self.twi
            .twcr()
            .write(|w| w.twint().set_bit().twen().set_bit());
        self.wait()
    }

    fn stop(&mut self) {
        self.twi
            .twcr()
            .write(|w| w.twint().set_bit().twsto().set_bit().twen().set_bit());
    }

    /// Writes `register`, then reads `buf.len()` bytes (repeated start).
    pub fn write_read(
        &mut self,
        address: u8,
        register: u8,
        buf: &mut [u8],
    ) -> Result<(), TwiError> {
        let r = self.transfer(address, register, buf);
        self.stop();
        r
    }

    fn transfer(&mut self, address: u8, register: u8, buf: &mut [u8]) -> Result<(), TwiError> {
        if self.start()? != START {
            return Err(TwiError::Bus);
        }
        match self.send(address << 1)? {
            SLA_W_ACK => {}
            SLA_W_NACK => return Err(TwiError::AddressNack),
            _ => return Err(TwiError::Bus),
        }
        if self.send(register)? != DATA_W_ACK {
            return Err(TwiError::DataNack);
        }
        if self.start()? != REPEATED_START {
            return Err(TwiError::Bus);
        }
        match self.send(address << 1 | 1)? {
            SLA_R_ACK => {}
            SLA_R_NACK => return Err(TwiError::AddressNack),
            _ => return Err(TwiError::Bus),
        }
        let n = buf.len();
        for (i, b) in buf.iter_mut().enumerate() {
            let last = i + 1 == n;
            if last {
                self.twi
                    .twcr()
                    .write(|w| w.twint().set_bit().twen().set_bit());
            } else {
                self.twi
                    .twcr()
                    .write(|w| w.twint().set_bit().twea().set_bit().twen().set_bit());
            }
            let status = self.wait()?;
            if status != DATA_R_ACK && status != DATA_R_NACK {
                return Err(TwiError::Bus);
            }
            *b = self.twi.twdr().read().bits();
        }
        Ok(())
    }
}

/// DS3231 RTC at address 0x68: reads registers 0x00–0x06 (BCD seconds …
/// year, datasheet "Timekeeping registers") into a UTC instant. The RTC
/// keeps UTC.
pub fn ds3231_now(twi: &mut Twi) -> Result<sun_algos::UtcTime, &'static str> {
    let mut r = [0u8; 7];
    match twi.write_read(0x68, 0x00, &mut r) {
        Ok(()) => {}
        Err(TwiError::AddressNack) => return Err("DS3231 not answering (address NACK)"),
        Err(TwiError::Timeout) => return Err("TWI timeout"),
        Err(_) => return Err("TWI bus error"),
    }
    let bcd = |b: u8| (b >> 4) * 10 + (b & 0x0F);
    let [s, m, h, _dow, d, mo, y] = r;
    // Bit 6 of the hours register selects 12-hour mode; we write 24-hour.
    if h & 0x40 != 0 {
        return Err("DS3231 in 12-hour mode");
    }
    // Bit 7 of the month register is the century bit (2100+).
    let year = 2000 + i32::from(bcd(y)) + if mo & 0x80 != 0 { 100 } else { 0 };
    sun_algos::UtcTime::from_ymd_hms(
        year,
        bcd(mo & 0x1F),
        bcd(d & 0x3F),
        bcd(h & 0x3F),
        bcd(m & 0x7F),
        bcd(s & 0x7F),
    )
    .map_err(|_| "DS3231 holds an invalid date")
}
