//! What the Maxim RTC models share: BCD registers, the 12/24-hour hours
//! register, and a clock that counts whole seconds on emulated time.
//!
//! Both the DS3231 (19-5170, "Timekeeping Registers") and the DS1302
//! (19-5420, Table 3) keep seconds, minutes, hours, date, month and a
//! two-digit year in BCD, a day of week 1–7 that steps at midnight and whose
//! meaning (which day is 1) the user chooses, and an hours
//! register whose 12-hour flag selects a PM bit (bit 5) and hours 1–12;
//! they differ in the flag's bit (DS3231 bit 6, DS1302 bit 7), the
//! registers' order and what else a register holds (century, clock halt).

use drivers::time::{civil_from_days, days_from_civil};

/// `v` (0–99) in BCD.
pub fn bcd(v: u32) -> u8 {
    ((v / 10) << 4 | (v % 10)) as u8
}

/// A BCD byte's value (each nibble taken as it is).
pub fn unbcd(b: u8) -> u32 {
    u32::from(b >> 4) * 10 + u32::from(b & 0x0F)
}

/// The PM bit of a 12-hour hours register (both chips: bit 5).
const PM: u8 = 0x20;

/// The hours register for hour `h` (0–23): BCD 00–23, or in 12-hour mode
/// `flag_12h | PM | BCD 1–12`.
pub fn hours_register(h: u32, mode_12h: bool, flag_12h: u8) -> u8 {
    if mode_12h {
        let h12 = match h % 12 {
            0 => 12,
            x => x,
        };
        flag_12h | if h >= 12 { PM } else { 0 } | bcd(h12)
    } else {
        bcd(h)
    }
}

/// The hour (0–23) an hours register holds, and whether it is in 12-hour
/// mode (its `flag_12h` bit set).
pub fn hour_of_register(r: u8, flag_12h: u8) -> (u32, bool) {
    if r & flag_12h != 0 {
        let h12 = unbcd(r & 0x1F) % 12;
        (h12 + if r & PM != 0 { 12 } else { 0 }, true)
    } else {
        (unbcd(r & 0x3F), false)
    }
}

/// A calendar time as an RTC's registers hold it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Civil {
    /// Four-digit year.
    pub year: u16,
    /// 1–12.
    pub month: u8,
    /// 1–31.
    pub day: u8,
    /// 0–23.
    pub hour: u32,
    /// 0–59.
    pub minute: u32,
    /// 0–59.
    pub second: u32,
    /// Day of week register, 1–7.
    pub dow: u8,
}

/// Whole seconds counted on emulated time ([`crate::twi::EmuClock`]): the
/// Unix second shown at an emulated instant, and the day-of-week register's
/// offset from the day count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SecondsClock {
    /// Unix seconds shown at emulated time `base_at_s`.
    base_unix_s: i64,
    /// Emulated time at which `base_unix_s` started.
    base_at_s: f64,
    /// Day of week = (days since 1970-01-01 + offset) mod 7 + 1.
    dow_offset: i64,
    /// False: the oscillator is stopped and the time stands.
    running: bool,
}

impl SecondsClock {
    /// A running clock showing `unix_s` at emulated time 0, its day of week
    /// register `(days + dow_offset) mod 7 + 1`.
    pub fn new(unix_s: i64, dow_offset: i64) -> Self {
        SecondsClock {
            base_unix_s: unix_s,
            base_at_s: 0.0,
            dow_offset,
            running: true,
        }
    }

    /// Whether the seconds count.
    pub fn running(&self) -> bool {
        self.running
    }

    /// The time shown at emulated time `now_s`, Unix seconds.
    pub fn unix_at(&self, now_s: f64) -> i64 {
        if self.running {
            self.base_unix_s + (now_s - self.base_at_s).floor() as i64
        } else {
            self.base_unix_s
        }
    }

    /// The calendar at emulated time `now_s` (2000-01-01 outside the
    /// calendar's years).
    pub fn civil_at(&self, now_s: f64) -> Civil {
        let t = self.unix_at(now_s);
        let days = t.div_euclid(86_400);
        let sod = t.rem_euclid(86_400) as u32;
        let (year, month, day) = civil_from_days(days).unwrap_or((2000, 1, 1));
        Civil {
            year,
            month,
            day,
            hour: sod / 3600,
            minute: sod / 60 % 60,
            second: sod % 60,
            dow: ((days + self.dow_offset).rem_euclid(7) + 1) as u8,
        }
    }

    /// Sets the calendar at emulated time `now_s` (fields out of range
    /// clamped: a chip's behaviour there is undefined) and whether it runs.
    /// A running clock keeps its phase within the second unless
    /// `restart_phase`; a clock that starts counts its first second from
    /// `now_s`.
    pub fn set(&mut self, c: &Civil, now_s: f64, running: bool, restart_phase: bool) {
        let days = days_from_civil(c.year, c.month.clamp(1, 12), c.day.clamp(1, 31));
        let dow = i64::from(c.dow.clamp(1, 7)) - 1;
        self.dow_offset = (dow - days).rem_euclid(7);
        let frac = if restart_phase || !self.running {
            0.0
        } else {
            (now_s - self.base_at_s).rem_euclid(1.0)
        };
        self.base_at_s = now_s - frac;
        self.base_unix_s = days * 86_400 + i64::from(c.hour * 3600 + c.minute * 60 + c.second);
        self.running = running;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hours_registers_of_both_modes() {
        // 23 h: 24-hour BCD 0x23; 12-hour 11 PM with either chip's flag.
        assert_eq!(hours_register(23, false, 0x80), 0x23);
        assert_eq!(hours_register(23, true, 0x80), 0x80 | 0x20 | 0x11);
        assert_eq!(hours_register(0, true, 0x40), 0x40 | 0x12); // 12 AM
        assert_eq!(hours_register(12, true, 0x40), 0x40 | 0x20 | 0x12); // 12 PM
        for flag in [0x40, 0x80] {
            for h in 0..24 {
                for mode in [false, true] {
                    assert_eq!(
                        hour_of_register(hours_register(h, mode, flag), flag),
                        (h, mode)
                    );
                }
            }
        }
    }

    #[test]
    fn a_stopped_clock_stands_and_restarts_its_second() {
        // 1970-01-01 was a Thursday: day 5 when 1 is Sunday (offset 4).
        let mut c = SecondsClock::new(0, 4);
        assert_eq!(c.civil_at(0.0).dow, 5);
        let now = c.civil_at(10.5);
        assert_eq!((now.second, c.unix_at(10.5)), (10, 10));
        c.set(&now, 10.5, false, false);
        assert_eq!(c.unix_at(1_000.0), 10);
        c.set(&now, 1_000.25, true, false);
        assert_eq!((c.unix_at(1_001.2), c.unix_at(1_001.25)), (10, 11));
    }
}
