//! DS1302 trickle-charge timekeeping chip over its three-wire interface; our
//! own driver (no maintained embedded-hal 1.0 crate drives it).
//!
//! Facts from the Maxim DS1302 datasheet (19-5420):
//! - Command byte: bit 7 = 1, bit 6 = 0 for clock/calendar (1 = RAM),
//!   bits 5..1 = register address, bit 0 = 1 to read, 0 to write.
//! - Bytes go LSB first. The chip latches input bits on the rising SCLK edge
//!   and, for reads, drives each output bit after a falling edge, starting
//!   with the falling edge of the eighth command clock.
//! - SCLK must be low when CE rises. Timing used here, valid down to
//!   VCC = 2.0 V: CE-to-SCLK setup tCC >= 4 us, CE inactive time tCWH >= 4 us,
//!   SCLK high/low times tCH/tCL >= 1000 ns, data delay tCDD <= 800 ns.
//! - Registers: seconds (bit 7 = CH, clock halt), minutes, hours (bit 7 =
//!   12/24-hour, bit 5 = PM in 12-hour mode), date, month, day of week, year,
//!   control (bit 7 = WP, write protect), all BCD. The clock burst command
//!   (address 31) reads or writes them in that order; a burst write must
//!   write all eight, control included.
//! - WP's power-on state is undefined, so it is cleared before every write;
//!   the burst write then sets it again through the control byte.
//! - CH set means the oscillator is stopped: we report it as "lost power".
//!
//! The I/O line is bidirectional. embedded-hal 1.0 has no pin-direction
//! trait, so the driver takes one pin type that is both `OutputPin` and
//! `InputPin`, used as an open-drain line: `set_high` releases it and then
//! `is_high` reads what the DS1302 drives. Wire it as an open-drain output
//! with a pull-up (e.g. 10 kΩ, against the chip's internal 40 kΩ
//! pull-down), or use a HAL "flex" pin that behaves the same way. One type
//! rather than two keeps the line from being driven from two places.
//!
//! The examples below run against `embedded-hal-mock` pins: the hidden
//! helper `Wire` (`src/doc_support/ds1302_wire.rs`) expands each command and
//! data byte into the datasheet's exact CE, SCLK and I/O transactions.

use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{InputPin, OutputPin};

use super::Clock;
use crate::time::DateTime;

const CMD: u8 = 0b1000_0000;
const CMD_READ: u8 = 0b0000_0001;
const REG_SECONDS: u8 = 0;
const REG_CONTROL: u8 = 7;
const REG_CLOCK_BURST: u8 = 31;

const SECONDS_CH: u8 = 0b1000_0000;
const HOURS_12H: u8 = 0b1000_0000;
const HOURS_PM: u8 = 0b0010_0000;
const CONTROL_WP: u8 = 0b1000_0000;

/// Clock registers read in a burst: seconds through year.
const CLOCK_REGS: usize = 7;

const T_CE_SETUP_NS: u32 = 4_000;
const T_CE_INACTIVE_NS: u32 = 4_000;
const T_HALF_CLOCK_NS: u32 = 1_000;

const fn write_cmd(reg: u8) -> u8 {
    CMD | (reg << 1)
}

const fn read_cmd(reg: u8) -> u8 {
    CMD | (reg << 1) | CMD_READ
}

/// DS1302 errors.
///
/// ```
/// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
/// # use wire::{done, Wire};
/// use drivers::rtc::{Clock, Ds1302, Ds1302Error};
/// use drivers::time::DateTime;
///
/// // The chip stores two-digit years, 2000..=2099: 2100 is refused before
/// // any pin is touched.
/// let wire = Wire::default();
/// let (ce, clk, io, delay) = wire.pins();
/// let mut rtc = Ds1302::new(ce, clk, io, delay);
/// let e = rtc.set_datetime(&DateTime::new(2100, 1, 1, 0, 0, 0)?).unwrap_err();
/// assert_eq!(e, Ds1302Error::OutOfRange);
/// assert_eq!(e.to_string(), "year outside 2000..=2099, which the DS1302 cannot store");
/// done(rtc.destroy());
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<E> {
    /// A pin failed.
    Comm(E),
    /// The registers hold no valid date-time (bad BCD or impossible date; an
    /// absent chip reads as all ones or all zeros).
    InvalidDeviceState,
    /// The year is outside 2000..=2099, which the chip cannot store.
    OutOfRange,
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "DS1302 pin error: {e:?}"),
            Error::InvalidDeviceState => f.write_str("DS1302 registers hold no valid date-time"),
            Error::OutOfRange => {
                f.write_str("year outside 2000..=2099, which the DS1302 cannot store")
            }
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

fn bcd_to_bin(v: u8) -> Option<u8> {
    let (hi, lo) = (v >> 4, v & 0x0f);
    (hi <= 9 && lo <= 9).then_some(hi * 10 + lo)
}

fn bin_to_bcd(v: u8) -> u8 {
    ((v / 10) << 4) | (v % 10)
}

/// Decodes seconds..year as read by a clock burst.
fn decode(regs: &[u8; CLOCK_REGS]) -> Option<DateTime> {
    let [sec, min, hour, date, month, _weekday, year] = *regs;
    let second = bcd_to_bin(sec & !SECONDS_CH)?;
    let minute = bcd_to_bin(min)?;
    let hour = if hour & HOURS_12H != 0 {
        let h12 = bcd_to_bin(hour & 0x1f)?;
        if !(1..=12).contains(&h12) {
            return None;
        }
        (h12 % 12) + if hour & HOURS_PM != 0 { 12 } else { 0 }
    } else {
        bcd_to_bin(hour)?
    };
    let day = bcd_to_bin(date)?;
    let month = bcd_to_bin(month)?;
    let year = 2000 + u16::from(bcd_to_bin(year)?);
    DateTime::new(year, month, day, hour, minute, second).ok()
}

/// A DS1302 on three GPIO lines.
///
/// ```
/// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
/// # use wire::{done, Wire};
/// use drivers::rtc::{Clock, Ds1302};
/// use drivers::time::DateTime;
///
/// // DS1302 datasheet (Maxim 19-5420): command 0xBF is a clock burst read of
/// // seconds, minutes, hours, date, month, day of week, year, all BCD.
/// let mut wire = Wire::default();
/// wire.read(0xBF, &[0x56, 0x34, 0x12, 0x21, 0x06, 0x01, 0x26]);
/// let (ce, clk, io, delay) = wire.pins();
/// let mut rtc = Ds1302::new(ce, clk, io, delay);
/// assert_eq!(rtc.datetime()?, DateTime::new(2026, 6, 21, 12, 34, 56)?);
/// done(rtc.destroy());
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Ds1302<CE, CLK, IO, D> {
    ce: CE,
    clk: CLK,
    io: IO,
    delay: D,
}

impl<CE, CLK, IO, D, E> Ds1302<CE, CLK, IO, D>
where
    CE: OutputPin<Error = E>,
    CLK: OutputPin<Error = E>,
    IO: InputPin<Error = E> + OutputPin<Error = E>,
    D: DelayNs,
{
    /// Takes the pins and a delay; no pin is touched until the first transfer.
    ///
    /// ```
    /// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
    /// # use wire::{done, Wire};
    /// use drivers::rtc::Ds1302;
    ///
    /// // No transactions expected: constructing touches no pin.
    /// let wire = Wire::default();
    /// let (ce, clk, io, delay) = wire.pins();
    /// let rtc = Ds1302::new(ce, clk, io, delay);
    /// done(rtc.destroy());
    /// ```
    pub fn new(ce: CE, clk: CLK, io: IO, delay: D) -> Self {
        Self { ce, clk, io, delay }
    }

    /// Gives the pins and the delay back.
    ///
    /// ```
    /// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
    /// # use wire::{done, Wire};
    /// use drivers::rtc::Ds1302;
    ///
    /// // DS1302 datasheet: 0x81 reads the seconds register (bit 7 = CH).
    /// let mut wire = Wire::default();
    /// wire.read(0x81, &[0x42]);
    /// let (ce, clk, io, delay) = wire.pins();
    /// let mut rtc = Ds1302::new(ce, clk, io, delay);
    /// assert_eq!(rtc.read_register(0)?, 0x42);
    /// let (ce, clk, io, delay) = rtc.destroy();
    /// // The pins are free again, e.g. to check the mocks.
    /// done((ce, clk, io, delay));
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> (CE, CLK, IO, D) {
        (self.ce, self.clk, self.io, self.delay)
    }

    fn begin(&mut self) -> Result<(), Error<E>> {
        self.clk.set_low().map_err(Error::Comm)?;
        self.ce.set_high().map_err(Error::Comm)?;
        self.delay.delay_ns(T_CE_SETUP_NS);
        Ok(())
    }

    fn end(&mut self) -> Result<(), Error<E>> {
        self.ce.set_low().map_err(Error::Comm)?;
        self.delay.delay_ns(T_CE_INACTIVE_NS);
        Ok(())
    }

    /// Shifts out one byte, LSB first. With `release_last`, the I/O line is
    /// released after the last rising edge so the chip can drive it from the
    /// following falling edge on.
    fn write_byte(&mut self, byte: u8, release_last: bool) -> Result<(), Error<E>> {
        // One bit mask walking from bit 0 to bit 7 (a byte-wide counter: an
        // 8-bit MCU shifts it in one instruction).
        let mut mask: u8 = 1;
        while mask != 0 {
            if byte & mask != 0 {
                self.io.set_high().map_err(Error::Comm)?;
            } else {
                self.io.set_low().map_err(Error::Comm)?;
            }
            self.delay.delay_ns(T_HALF_CLOCK_NS);
            self.clk.set_high().map_err(Error::Comm)?;
            self.delay.delay_ns(T_HALF_CLOCK_NS);
            mask <<= 1;
            if mask == 0 && release_last {
                self.io.set_high().map_err(Error::Comm)?;
            }
            self.clk.set_low().map_err(Error::Comm)?;
        }
        Ok(())
    }

    /// Shifts in one byte, LSB first; each bit is valid after the previous
    /// falling edge and the clock pulse that follows moves to the next bit.
    fn read_byte(&mut self) -> Result<u8, Error<E>> {
        let mut byte = 0;
        let mut mask: u8 = 1;
        while mask != 0 {
            self.delay.delay_ns(T_HALF_CLOCK_NS);
            if self.io.is_high().map_err(Error::Comm)? {
                byte |= mask;
            }
            self.clk.set_high().map_err(Error::Comm)?;
            self.delay.delay_ns(T_HALF_CLOCK_NS);
            self.clk.set_low().map_err(Error::Comm)?;
            mask <<= 1;
        }
        Ok(byte)
    }

    fn read_into(&mut self, reg: u8, out: &mut [u8]) -> Result<(), Error<E>> {
        self.begin()?;
        let result = self.write_byte(read_cmd(reg), true).and_then(|()| {
            out.iter_mut().try_for_each(|b| {
                *b = self.read_byte()?;
                Ok(())
            })
        });
        // Always try to end the transfer, but report the first error.
        let ended = self.end();
        result.and(ended)
    }

    fn write_from(&mut self, reg: u8, data: &[u8]) -> Result<(), Error<E>> {
        self.begin()?;
        let result = self
            .write_byte(write_cmd(reg), false)
            .and_then(|()| data.iter().try_for_each(|&b| self.write_byte(b, false)));
        let ended = self.end();
        result.and(ended)
    }

    /// Reads one clock register (0..=8).
    ///
    /// ```
    /// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
    /// # use wire::{done, Wire};
    /// use drivers::rtc::Ds1302;
    ///
    /// // DS1302 datasheet, register 7 (control): command 0x8F reads it;
    /// // 0x80 is WP set, the chip write-protected.
    /// let mut wire = Wire::default();
    /// wire.read(0x8F, &[0x80]);
    /// let (ce, clk, io, delay) = wire.pins();
    /// let mut rtc = Ds1302::new(ce, clk, io, delay);
    /// assert_eq!(rtc.read_register(7)?, 0x80);
    /// done(rtc.destroy());
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn read_register(&mut self, reg: u8) -> Result<u8, Error<E>> {
        let mut b = [0];
        self.read_into(reg, &mut b)?;
        Ok(b[0])
    }

    /// Sets or clears write protection (WP, control register bit 7).
    ///
    /// ```
    /// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
    /// # use wire::{done, Wire};
    /// use drivers::rtc::Ds1302;
    ///
    /// // DS1302 datasheet: 0x8E writes the control register, WP is bit 7.
    /// let mut wire = Wire::default();
    /// wire.write(0x8E, &[0x80]);
    /// wire.write(0x8E, &[0x00]);
    /// let (ce, clk, io, delay) = wire.pins();
    /// let mut rtc = Ds1302::new(ce, clk, io, delay);
    /// rtc.set_write_protect(true)?;
    /// rtc.set_write_protect(false)?;
    /// done(rtc.destroy());
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_write_protect(&mut self, protect: bool) -> Result<(), Error<E>> {
        let value = if protect { CONTROL_WP } else { 0 };
        self.write_from(REG_CONTROL, &[value])
    }
}

impl<CE, CLK, IO, D, E> Clock for Ds1302<CE, CLK, IO, D>
where
    CE: OutputPin<Error = E>,
    CLK: OutputPin<Error = E>,
    IO: InputPin<Error = E> + OutputPin<Error = E>,
    D: DelayNs,
{
    type Error = Error<E>;

    /// Clock burst read of seconds..year.
    ///
    /// ```
    /// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
    /// # use wire::{done, Wire};
    /// use drivers::rtc::{Clock, Ds1302};
    /// use drivers::time::DateTime;
    ///
    /// // DS1302 datasheet: burst read 0xBF. Hours 0x72 = 12-hour mode (bit 7)
    /// // with PM (bit 5), 12 → 12 h; date 29, month 02, year 24.
    /// let mut wire = Wire::default();
    /// wire.read(0xBF, &[0x00, 0x30, 0xB2, 0x29, 0x02, 0x05, 0x24]);
    /// let (ce, clk, io, delay) = wire.pins();
    /// let mut rtc = Ds1302::new(ce, clk, io, delay);
    /// assert_eq!(rtc.datetime()?, DateTime::new(2024, 2, 29, 12, 30, 0)?);
    /// done(rtc.destroy());
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn datetime(&mut self) -> Result<DateTime, Error<E>> {
        let mut regs = [0; CLOCK_REGS];
        self.read_into(REG_CLOCK_BURST, &mut regs)?;
        decode(&regs).ok_or(Error::InvalidDeviceState)
    }

    /// Clears WP, then a clock burst write of all eight registers (24-hour
    /// mode, CH = 0 so the oscillator runs, day of week 1 = Sunday, and
    /// WP = 1 again in the control byte).
    ///
    /// ```
    /// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
    /// # use wire::{done, Wire};
    /// use drivers::rtc::{Clock, Ds1302};
    /// use drivers::time::DateTime;
    ///
    /// // DS1302 datasheet: clear WP (0x8E ← 0x00), then a clock burst write
    /// // (0xBE) of all eight registers: 56 s, 34 min, 12 h (24-hour mode),
    /// // date 21, month 06, day of week 1 (Sunday), year 26, control 0x80.
    /// let mut wire = Wire::default();
    /// wire.write(0x8E, &[0x00]);
    /// wire.write(0xBE, &[0x56, 0x34, 0x12, 0x21, 0x06, 0x01, 0x26, 0x80]);
    /// let (ce, clk, io, delay) = wire.pins();
    /// let mut rtc = Ds1302::new(ce, clk, io, delay);
    /// rtc.set_datetime(&DateTime::new(2026, 6, 21, 12, 34, 56)?)?;
    /// done(rtc.destroy());
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn set_datetime(&mut self, utc: &DateTime) -> Result<(), Error<E>> {
        let year = utc
            .year()
            .checked_sub(2000)
            .filter(|y| *y <= 99)
            .ok_or(Error::OutOfRange)?;
        // year <= 99 fits in a u8.
        let regs = [
            bin_to_bcd(utc.second()),
            bin_to_bcd(utc.minute()),
            bin_to_bcd(utc.hour()),
            bin_to_bcd(utc.day()),
            bin_to_bcd(utc.month()),
            utc.weekday_from_sunday(),
            bin_to_bcd(year as u8),
            CONTROL_WP,
        ];
        self.set_write_protect(false)?;
        self.write_from(REG_CLOCK_BURST, &regs)
    }

    /// The clock-halt bit (CH, seconds register bit 7).
    ///
    /// ```
    /// # mod wire { include!("../doc_support/ds1302_wire.rs"); }
    /// # use wire::{done, Wire};
    /// use drivers::rtc::{Clock, Ds1302};
    ///
    /// // DS1302 datasheet: seconds register (read command 0x81), bit 7 = CH,
    /// // the oscillator halted; 0x80 is its power-on state.
    /// let mut wire = Wire::default();
    /// wire.read(0x81, &[0x80]);
    /// wire.read(0x81, &[0x17]);
    /// let (ce, clk, io, delay) = wire.pins();
    /// let mut rtc = Ds1302::new(ce, clk, io, delay);
    /// assert!(rtc.lost_power()?);
    /// assert!(!rtc.lost_power()?);
    /// done(rtc.destroy());
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn lost_power(&mut self) -> Result<bool, Error<E>> {
        Ok(self.read_register(REG_SECONDS)? & SECONDS_CH != 0)
    }
}
