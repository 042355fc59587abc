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

use crate::twi::{I2cDevice, RegisterPointer};
use drivers::time::{civil_from_days, days_from_civil};

/// Seven-bit address.
pub const ADDRESS: u8 = 0x68;
const LEN: u8 = 0x13;
/// OSF, status bit 7.
pub const OSF: u8 = 0x80;

fn bcd(v: u32) -> u8 {
    ((v / 10) << 4 | (v % 10)) as u8
}

fn unbcd(b: u8) -> u32 {
    u32::from(b >> 4) * 10 + u32::from(b & 0x0F)
}

/// The DS3231 model.
#[derive(Debug, Clone)]
pub struct Ds3231 {
    /// Unix seconds shown at emulated time `base_at_s`.
    base_unix_s: i64,
    /// Emulated time at which the countdown chain was last reset.
    base_at_s: f64,
    /// Day register offset: day = (days since 1970 + offset) mod 7 + 1.
    dow_offset: i64,
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
        d.base_unix_s = unix_s;
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
            base_unix_s: 946_684_800,
            base_at_s: 0.0,
            dow_offset: 0,
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
        self.base_unix_s + (now_s - self.base_at_s).floor() as i64
    }

    /// Copies the internal time into the user buffer (00h–06h).
    fn sync(&mut self, now_s: f64) {
        let t = self.unix_at(now_s);
        let days = t.div_euclid(86_400);
        let sod = t.rem_euclid(86_400) as u32;
        let (y, m, d) = civil_from_days(days).unwrap_or((2000, 1, 1));
        let (h, mi, s) = (sod / 3600, sod / 60 % 60, sod % 60);
        self.regs[0] = bcd(s);
        self.regs[1] = bcd(mi);
        self.regs[2] = if self.mode_12h {
            let pm = h >= 12;
            let h12 = match h % 12 {
                0 => 12,
                x => x,
            };
            0x40 | if pm { 0x20 } else { 0 } | bcd(h12)
        } else {
            bcd(h)
        };
        self.regs[3] = ((days + self.dow_offset).rem_euclid(7) + 1) as u8;
        self.regs[4] = bcd(u32::from(d));
        let century = if y >= 2100 { 0x80 } else { 0 };
        self.regs[5] = century | bcd(u32::from(m));
        self.regs[6] = bcd(u32::from(y) % 100);
    }

    /// Re-derives the internal time from the user buffer after a write.
    fn load(&mut self, now_s: f64, seconds_written: bool) {
        let r = &self.regs;
        let s = unbcd(r[0] & 0x7F);
        let mi = unbcd(r[1] & 0x7F);
        self.mode_12h = r[2] & 0x40 != 0;
        let h = if self.mode_12h {
            let h12 = unbcd(r[2] & 0x1F) % 12;
            h12 + if r[2] & 0x20 != 0 { 12 } else { 0 }
        } else {
            unbcd(r[2] & 0x3F)
        };
        let d = unbcd(r[4] & 0x3F).clamp(1, 31) as u8;
        let m = unbcd(r[5] & 0x1F).clamp(1, 12) as u8;
        let y = 2000 + unbcd(r[6]) as u16 + if r[5] & 0x80 != 0 { 100 } else { 0 };
        let days = days_from_civil(y, m, d);
        let dow = i64::from(r[3].clamp(1, 7)) - 1;
        self.dow_offset = (dow - days).rem_euclid(7);
        let frac = if seconds_written {
            0.0
        } else {
            (now_s - self.base_at_s).rem_euclid(1.0)
        };
        self.base_at_s = now_s - frac;
        self.base_unix_s = days * 86_400 + i64::from(h * 3600 + mi * 60 + s);
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
