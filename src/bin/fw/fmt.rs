//! Number formatting for the firmware images without `core::fmt`.
//!
//! `core::fmt` with floats costs several kilobytes of flash on an 8-bit AVR
//! and carries panic paths; these routines write integers and fixed-point
//! decimals byte by byte into any [`Sink`], never panic and never allocate.
// Shared by several images; each uses a part.
#![allow(dead_code)]

/// Where formatted text goes: a UART, semihosting, or a buffer in tests.
pub trait Sink {
    /// Writes all of `bytes`.
    fn put(&mut self, bytes: &[u8]);

    /// Writes a string.
    fn text(&mut self, s: &str) {
        self.put(s.as_bytes());
    }

    /// Writes an unsigned integer in decimal.
    fn u32(&mut self, value: u32) {
        let mut digits = [0u8; 10];
        let mut n = value;
        let mut len = 0;
        for slot in digits.iter_mut().rev() {
            *slot = b'0' + (n % 10) as u8;
            n /= 10;
            len += 1;
            if n == 0 {
                break;
            }
        }
        let start = digits.len() - len;
        if let Some(used) = digits.get(start..) {
            self.put(used);
        }
    }

    /// Writes a signed integer in decimal.
    fn i32(&mut self, value: i32) {
        if value < 0 {
            self.put(b"-");
        }
        self.u32(value.unsigned_abs());
    }

    /// Writes an unsigned integer padded with zeros to `width` digits.
    fn u32_padded(&mut self, value: u32, width: u8) {
        let mut limit: u32 = 10;
        for _ in 1..width {
            if value < limit {
                self.put(b"0");
            }
            limit = limit.saturating_mul(10);
        }
        self.u32(value);
    }

    /// Writes `value` rounded to `decimals` places (at most 6); `nan` for a
    /// value that is not finite or too large for the fixed-point range.
    fn fixed(&mut self, value: f32, decimals: u8) {
        const POW10: [u32; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];
        let decimals = decimals.min(6);
        let scale = POW10.get(usize::from(decimals)).copied().unwrap_or(1);
        let magnitude = if value < 0.0 { -value } else { value };
        let scaled = magnitude * scale as f32 + 0.5;
        // Also rejects NaN.
        if !scaled.is_finite() || scaled >= 4.0e9 {
            self.put(b"nan");
            return;
        }
        let units = scaled as u32;
        if value < 0.0 && units != 0 {
            self.put(b"-");
        }
        // `scale` is never zero; checked division keeps panics out anyway.
        self.u32(units.checked_div(scale).unwrap_or(0));
        if decimals > 0 {
            self.put(b".");
            self.u32_padded(units.checked_rem(scale).unwrap_or(0), decimals);
        }
    }

    /// Writes a UTC instant as `YYYY-MM-DDTHH:MM:SSZ`.
    fn utc(&mut self, t: &sun_algos::UtcTime) {
        let (y, mo, d) = t.ymd();
        let (h, mi, s, _) = t.hms_milli();
        self.i32(y);
        self.put(b"-");
        self.u32_padded(u32::from(mo), 2);
        self.put(b"-");
        self.u32_padded(u32::from(d), 2);
        self.put(b"T");
        self.u32_padded(u32::from(h), 2);
        self.put(b":");
        self.u32_padded(u32::from(mi), 2);
        self.put(b":");
        self.u32_padded(u32::from(s), 2);
        self.put(b"Z");
    }
}
