//! Maxim DS3231 real-time clock (I²C address 0x68), after the Maxim
//! *DS3231 Extremely Accurate I²C-Integrated RTC/TCXO/Crystal* datasheet
//! (19-5170 Rev 10):
//!
//! - "Timekeeping Registers" (Figure 1, 00h–06h): BCD seconds, minutes,
//!   hours (bit 6 = 12-hour mode, bit 5 = PM in 12-hour mode), day 1–7,
//!   date, month (bit 7 = century), year 00–99.
//! - "Clock and Calendar": reads go through user buffers synchronised "on
//!   any START and when the register pointer rolls over to zero"; "the
//!   countdown chain is reset whenever the seconds register is written".
//! - "Control Register (0Eh)": power-on value 0x1C (RS2, RS1, INTCN).
//! - "Status Register (0Fh)": bit 7 OSF, set at power-on and "remains at
//!   logic 1 until written to logic 0"; bit 3 EN32kHz (power-on 1); bit 2
//!   BSY read-only; A2F/A1F can only be cleared.
//! - "I²C Serial Data Bus": the register pointer auto-increments and wraps
//!   from 12h to 00h.
//! - 11h–12h temperature (fixed at 25.00 °C here), 10h aging offset.
//!
//! The clock runs on emulated time (see [`crate::twi::EmuClock`]).

use crate::models::bcd_clock::{bcd, hour_of_register, hours_register, unbcd, Civil, SecondsClock};
use crate::twi::{I2cDevice, RegisterPointer};

/// Seven-bit address.
pub const ADDRESS: u8 = 0x68;
const LEN: u8 = 0x13;
/// OSF, status bit 7.
pub const OSF: u8 = 0x80;
/// The hours register's 12-hour flag (bit 6).
const HOURS_12H: u8 = 0x40;

/// The DS3231 model.
#[derive(Debug, Clone)]
pub struct Ds3231 {
    /// The time kept (always running: the oscillator runs on the battery).
    clock: SecondsClock,
    /// 12-hour mode flag as last written to the hours register.
    mode_12h: bool,
    regs: [u8; LEN as usize],
    ptr: RegisterPointer,
    /// Times the seconds register was written (the firmware set the clock).
    pub time_writes: u32,
}

impl Ds3231 {
    /// A clock showing `unix_s` at emulated time 0, oscillator flag clear
    /// (it kept time on its battery).
    pub fn running(unix_s: i64) -> Self {
        let mut d = Self::lost_power();
        d.clock = SecondsClock::new(unix_s, 0);
        d.regs[0x0F] = 0x08;
        d
    }

    /// A clock that lost power: OSF set, time 2000-01-01 00:00:00 (the
    /// power-on register contents are undefined in the datasheet; all-zero
    /// BCD is what fresh chips commonly read).
    pub fn lost_power() -> Self {
        let mut regs = [0u8; LEN as usize];
        regs[0x0E] = 0x1C;
        regs[0x0F] = OSF | 0x08;
        regs[0x11] = 25; // 25.00 °C
        Ds3231 {
            clock: SecondsClock::new(946_684_800, 0),
            mode_12h: false,
            regs,
            ptr: RegisterPointer::default(),
            time_writes: 0,
        }
    }

    /// Whether OSF is set.
    pub fn osf(&self) -> bool {
        self.regs[0x0F] & OSF != 0
    }

    /// The time the clock shows at emulated time `now_s`, Unix seconds.
    pub fn unix_at(&self, now_s: f64) -> i64 {
        self.clock.unix_at(now_s)
    }

    /// Copies the internal time into the user buffer (00h–06h).
    fn sync(&mut self, now_s: f64) {
        let c = self.clock.civil_at(now_s);
        self.regs[0] = bcd(c.second);
        self.regs[1] = bcd(c.minute);
        self.regs[2] = hours_register(c.hour, self.mode_12h, HOURS_12H);
        self.regs[3] = c.dow;
        self.regs[4] = bcd(u32::from(c.day));
        let century = if c.year >= 2100 { 0x80 } else { 0 };
        self.regs[5] = century | bcd(u32::from(c.month));
        self.regs[6] = bcd(u32::from(c.year) % 100);
    }

    /// Re-derives the internal time from the user buffer after a write.
    fn load(&mut self, now_s: f64, seconds_written: bool) {
        let r = &self.regs;
        let (hour, mode_12h) = hour_of_register(r[2], HOURS_12H);
        self.mode_12h = mode_12h;
        let civil = Civil {
            year: 2000 + unbcd(r[6]) as u16 + if r[5] & 0x80 != 0 { 100 } else { 0 },
            month: unbcd(r[5] & 0x1F) as u8,
            day: unbcd(r[4] & 0x3F) as u8,
            hour,
            minute: unbcd(r[1] & 0x7F),
            second: unbcd(r[0] & 0x7F),
            dow: r[3],
        };
        // "The countdown chain is reset whenever the seconds register is
        // written".
        self.clock.set(&civil, now_s, true, seconds_written);
    }

    /// Register read (with the buffer as last synchronised).
    pub fn register(&self, r: u8) -> u8 {
        self.regs.get(usize::from(r)).copied().unwrap_or(0)
    }
}

impl I2cDevice for Ds3231 {
    fn address(&self) -> u8 {
        ADDRESS
    }

    fn start(&mut self, read: bool, now_s: f64) -> bool {
        self.ptr.start(read);
        self.sync(now_s);
        true
    }

    fn write(&mut self, byte: u8, now_s: f64) -> bool {
        let Some(r) = self.ptr.write(byte, LEN) else {
            return true;
        };
        match r {
            0..=6 => {
                self.regs[usize::from(r)] = byte;
                if r == 0 {
                    self.time_writes += 1;
                }
                self.load(now_s, r == 0);
            }
            0x0F => {
                let old = self.regs[0x0F];
                // OSF, A2F, A1F: write 0 to clear, 1 leaves them; BSY read-only.
                let sticky = old & 0x83 & byte;
                self.regs[0x0F] = sticky | (byte & 0x08) | (old & 0x04);
            }
            0x11 | 0x12 => {} // temperature: read-only
            _ => self.regs[usize::from(r)] = byte,
        }
        true
    }

    fn read(&mut self, now_s: f64) -> u8 {
        let r = self.ptr.read(LEN);
        let v = self.register(r);
        if self.ptr.pointer == 0 {
            // Rolled over to zero: the user buffer is synchronised again.
            self.sync(now_s);
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::twi::{EmuClock, HostI2c, TwiBus};
    use drivers::rtc::Clock as _;
    use drivers::time::DateTime;
    use std::cell::RefCell;
    use std::rc::Rc;

    const T0: i64 = 1_782_018_000; // 2026-06-21T05:00:00Z

    #[test]
    fn t0_is_the_default_start() {
        let d = DateTime::from_unix_seconds(T0).unwrap();
        assert_eq!(d, DateTime::new(2026, 6, 21, 5, 0, 0).unwrap());
    }

    #[test]
    fn registers_are_bcd_and_run_on_emulated_time() {
        let mut rtc = Ds3231::running(T0);
        rtc.start(false, 0.0);
        rtc.write(0x00, 0.0);
        rtc.start(true, 3_723.9);
        let regs: Vec<u8> = (0..7).map(|_| rtc.read(3_723.9)).collect();
        // 05:00:00 + 1 h 2 min 3.9 s = 06:02:03, Sunday 21 June 2026.
        assert_eq!(regs[0], 0x03);
        assert_eq!(regs[1], 0x02);
        assert_eq!(regs[2], 0x06);
        assert_eq!(regs[4], 0x21);
        assert_eq!(regs[5], 0x06);
        assert_eq!(regs[6], 0x26);
        assert!(!rtc.osf());
    }

    #[test]
    fn pointer_wraps_from_12h_to_00h() {
        let mut rtc = Ds3231::running(T0);
        rtc.start(false, 0.0);
        rtc.write(0x12, 0.0);
        rtc.start(true, 0.0);
        assert_eq!(rtc.read(0.0), 0x00); // 12h: temperature fraction
        assert_eq!(rtc.read(0.0), 0x00); // 00h: seconds
        assert_eq!(rtc.read(0.0), 0x00); // 01h: minutes
        assert_eq!(rtc.read(0.0), 0x05); // 02h: hours
    }

    #[test]
    fn osf_only_clears_and_writing_seconds_resets_the_countdown() {
        let mut rtc = Ds3231::lost_power();
        assert!(rtc.osf());
        rtc.start(false, 10.0);
        rtc.write(0x0F, 10.0);
        rtc.write(0xFF, 10.0); // writing 1 leaves OSF as it is
        assert!(rtc.osf());
        rtc.start(false, 10.0);
        rtc.write(0x0F, 10.0);
        rtc.write(0x08, 10.0);
        assert!(!rtc.osf());
        // Set 2026-06-21 12:34:56 at emulated 10.7 s; 0.5 s later still :56.
        rtc.start(false, 10.7);
        for b in [0x00, 0x56, 0x34, 0x12, 0x01, 0x21, 0x06, 0x26] {
            rtc.write(b, 10.7);
        }
        assert_eq!(rtc.unix_at(11.2), T0 + 7 * 3600 + 34 * 60 + 56);
        assert_eq!(rtc.unix_at(11.7), T0 + 7 * 3600 + 34 * 60 + 57);
        assert_eq!(rtc.time_writes, 1);
    }

    #[test]
    fn twelve_hour_mode_reads_back() {
        let mut rtc = Ds3231::running(T0);
        rtc.start(false, 0.0);
        for b in [0x00, 0x00, 0x00, 0x40 | 0x20 | 0x11] {
            rtc.write(b, 0.0); // 11 PM
        }
        rtc.start(false, 0.0);
        rtc.write(0x02, 0.0);
        rtc.start(true, 0.0);
        assert_eq!(rtc.read(0.0), 0x40 | 0x20 | 0x11);
        assert_eq!(rtc.unix_at(0.0).rem_euclid(86_400), 23 * 3600);
    }

    #[test]
    fn the_repository_driver_reads_sets_and_clears() {
        let clock = EmuClock::new();
        let bus = Rc::new(RefCell::new(TwiBus::new(clock.clone())));
        bus.borrow_mut().attach(Box::new(Ds3231::lost_power()));
        let i2c = HostI2c { bus: bus.clone() };
        let mut rtc = drivers::rtc::Ds3231::new(i2c.clone());
        assert!(rtc.lost_power().unwrap());
        let t = DateTime::new(2026, 6, 21, 5, 0, 0).unwrap();
        rtc.set_datetime(&t).unwrap();
        assert!(!rtc.lost_power().unwrap());
        drop(rtc);
        clock.set_s(61.5);
        let mut rtc = drivers::rtc::Ds3231::new(i2c);
        assert_eq!(
            rtc.datetime().unwrap(),
            DateTime::new(2026, 6, 21, 5, 1, 1).unwrap()
        );
    }
}
