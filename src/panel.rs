//! The panel's voltage and the day's energy figure of M. E. H. Chowdhury,
//! A. Khandakar, B. Hossain and R. Abouhasera (2019), "A Low-Cost Closed-Loop
//! Solar Tracking System Based on the Sun Position Algorithm": the panel
//! voltage is read on the microcontroller's ADC through a resistor divider,
//! logged with each set-point, and the area under the voltage curve over the
//! day (the paper's Table 1 and Fig. 8, an "area under the curve" in V·h) is
//! summed by the trapezoid rule (its §2.5).
//!
//! Everything is integer arithmetic (millivolts, milliseconds of the
//! monotonic clock), so an 8-bit part needs no float for it, and no input
//! can overflow it: products are formed in `u64` and saturate.

use crate::log::Sink;
use sun_algos::time::{div_rem_u64, div_rem_u64_u16};

/// A resistor divider between the panel and the ADC pin: the pin sees
/// `V_panel · r_bottom / (r_top + r_bottom)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Divider {
    /// Resistor from the panel to the pin, ohms.
    pub r_top_ohm: u32,
    /// Resistor from the pin to ground, ohms.
    pub r_bottom_ohm: u32,
}

/// An ADC channel reading the panel through a divider.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PanelAdc {
    /// The ADC's reference, millivolts (AVcc = 5,000 on an Arduino Uno).
    pub vref_mv: u32,
    /// Resolution, bits (10 on the ATmega328P).
    pub bits: u8,
    /// The divider in front of the pin.
    pub divider: Divider,
}

/// Why a panel reading is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PanelError {
    /// The divider has no bottom resistor, or the resolution is not 1–16
    /// bits: no voltage can be computed.
    BadConfig,
    /// The code is beyond the converter's range (`2^bits − 1`).
    CodeOutOfRange,
}

impl PanelAdc {
    /// The panel voltage, millivolts, for conversion result `code`:
    /// `V_pin = code · V_ref / 2^bits` (ATmega328P datasheet §24.7 "ADC
    /// Conversion Result": `ADC = V_in · 1024 / V_ref`), then through the
    /// divider, `V_panel = V_pin · (r_top + r_bottom) / r_bottom`; rounded
    /// down, saturating at `u32::MAX`.
    pub fn panel_mv(&self, code: u16) -> Result<u32, PanelError> {
        if self.divider.r_bottom_ohm == 0 || !(1..=16).contains(&self.bits) {
            return Err(PanelError::BadConfig);
        }
        let full = 1u64 << self.bits;
        if u64::from(code) >= full {
            return Err(PanelError::CodeOutOfRange);
        }
        // code · V_ref < 2^48; times (r_top + r_bottom) < 2^33 it saturates
        // only for absurd dividers (the result is then u32::MAX anyway).
        let total_ohm = u64::from(self.divider.r_top_ohm) + u64::from(self.divider.r_bottom_ohm);
        let num =
            (u64::from(code) * u64::from(self.vref_mv)).saturating_mul(total_ohm) >> self.bits;
        // In 32 bits when it fits (an Uno's: under 2^27), a few hundred
        // cycles instead of the long division's 65,000 on an 8-bit part.
        let mv = match u32::try_from(num) {
            Ok(n) => u64::from(n / self.divider.r_bottom_ohm),
            Err(_) => div_rem_u64(num, self.divider.r_bottom_ohm).map_or(0, |(q, _)| q),
        };
        Ok(u32::try_from(mv).unwrap_or(u32::MAX))
    }
}

/// The day's area under the panel voltage, by the trapezoid rule over the
/// samples given (the servo tracker samples at each set-point; Chowdhury et al.
/// do not say how often they sampled).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DayEnergy {
    /// The previous sample: monotonic ms (32-bit clock) and mV.
    last: Option<(u32, u32)>,
    sum_mv_ms: u64,
    samples: u32,
}

/// Milliseconds in an hour: 2^7 × 28,125, so that an hour's division is a
/// shift and a division by a 16-bit divisor.
const MS_PER_HOUR: u32 = 3_600_000;
/// [`MS_PER_HOUR`] = `HOUR_SHIFT` bits × [`HOUR_DIVISOR`].
const HOUR_SHIFT: u32 = 7;
const HOUR_DIVISOR: u16 = 28_125;

impl DayEnergy {
    /// Nothing summed.
    pub const fn new() -> Self {
        DayEnergy {
            last: None,
            sum_mv_ms: 0,
            samples: 0,
        }
    }

    /// Adds the sample `panel_mv` taken at `now_ms` of the monotonic clock
    /// (its 32 bits, [`crate::time::monotonic`]): the trapezoid between it
    /// and the previous sample. A sample at the previous one's instant, or
    /// not after it (a clock that went back, which a monotonic clock never
    /// does), or more than 24.8 days after it adds no area and replaces it.
    pub fn add(&mut self, now_ms: u32, panel_mv: u32) {
        if let Some((t0, v0)) = self.last {
            let dt_ms = crate::time::monotonic::elapsed_ms(now_ms, t0);
            if dt_ms <= crate::time::monotonic::MAX_AGE_MS {
                let twice_mean = u64::from(v0) + u64::from(panel_mv);
                self.sum_mv_ms = self
                    .sum_mv_ms
                    .saturating_add(twice_mean.saturating_mul(u64::from(dt_ms)) / 2);
            }
        }
        self.last = Some((now_ms, panel_mv));
        drivers::counter::count_up(&mut self.samples);
    }

    /// Samples added since the last reset.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The area so far, millivolt-hours (V·h × 1000), rounded to nearest.
    pub fn mvh(&self) -> u64 {
        // sum = 2^7 · s + low, s = 28,125 · q + r: sum = 3,600,000 · q +
        // (2^7 · r + low), that remainder below 3,600,000. A divisor below
        // 2^16 divides in four 32-bit steps (a few dozen bytes on an AVR,
        // where the general 64-bit division takes 500).
        let low = (self.sum_mv_ms & ((1 << HOUR_SHIFT) - 1)) as u32;
        let (q, r) = div_rem_u64_u16(self.sum_mv_ms >> HOUR_SHIFT, HOUR_DIVISOR).unwrap_or((0, 0));
        let rem_ms = (u32::from(r) << HOUR_SHIFT) | low;
        q + u64::from(rem_ms >= MS_PER_HOUR / 2)
    }

    /// Starts a new day.
    pub fn reset(&mut self) {
        *self = DayEnergy::new();
    }
}

/// `day_energy vh=<V·h, 3 decimals>`: the day's area, at its end.
pub fn log_day_energy(out: &mut dyn Sink, energy: &DayEnergy) {
    let (whole, thousandths) = div_rem_u64_u16(energy.mvh(), 1000).unwrap_or((0, 0));
    out.flash(crate::flash_str!("day_energy vh="));
    out.u32(u32::try_from(whole).unwrap_or(u32::MAX));
    out.flash(crate::flash_str!("."));
    out.u32_padded(u32::from(thousandths), 3);
    out.flash(crate::flash_str!("\n"));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fixed buffer (the library is `no_std` in its unit tests too).
    struct Text {
        buf: [u8; 64],
        len: usize,
    }
    impl Text {
        fn new() -> Self {
            Text {
                buf: [0; 64],
                len: 0,
            }
        }
        fn as_str(&self) -> &str {
            core::str::from_utf8(&self.buf[..self.len]).unwrap()
        }
    }
    impl Sink for Text {
        fn put(&mut self, bytes: &[u8]) {
            self.buf[self.len..self.len + bytes.len()].copy_from_slice(bytes);
            self.len += bytes.len();
        }
    }

    const UNO: PanelAdc = PanelAdc {
        vref_mv: 5_000,
        bits: 10,
        divider: Divider {
            r_top_ohm: 10_000,
            r_bottom_ohm: 10_000,
        },
    };

    #[test]
    fn codes_become_panel_millivolts() {
        // 512 of 1024 at 5 V is 2.5 V on the pin, 5.0 V through 1:2.
        assert_eq!(UNO.panel_mv(512), Ok(5_000));
        assert_eq!(UNO.panel_mv(0), Ok(0));
        // 1023 · 5000 / 1024 = 4995.1 mV on the pin → 9990.2 → 9990.
        assert_eq!(UNO.panel_mv(1023), Ok(9_990));
        assert_eq!(UNO.panel_mv(1024), Err(PanelError::CodeOutOfRange));
        let no_bottom = PanelAdc {
            divider: Divider {
                r_top_ohm: 1,
                r_bottom_ohm: 0,
            },
            ..UNO
        };
        assert_eq!(no_bottom.panel_mv(1), Err(PanelError::BadConfig));
        let absurd = PanelAdc {
            vref_mv: u32::MAX,
            bits: 16,
            divider: Divider {
                r_top_ohm: u32::MAX,
                r_bottom_ohm: 1,
            },
        };
        assert_eq!(absurd.panel_mv(u16::MAX), Ok(u32::MAX));
    }

    #[test]
    fn trapezoids_sum_exactly() {
        // 6 V for 12 hours, sampled every 4 minutes: 72 V·h.
        let mut e = DayEnergy::new();
        for k in 0..=180u32 {
            e.add(k * 240_000, 6_000);
        }
        assert_eq!(e.mvh(), 72_000);
        // A ramp 0 → 6 V over 2 h: 6 V·h (exact for a line).
        let mut e = DayEnergy::new();
        for k in 0..=30u32 {
            e.add(k * 240_000, k * 200);
        }
        assert_eq!(e.mvh(), 6_000);
        // A sample at the same instant or earlier adds nothing (nor does
        // one 2^31 ms or more after the previous one).
        e.add(30 * 240_000, 50_000);
        e.add(0, 50_000);
        e.add(1 << 31, 50_000);
        assert_eq!(e.mvh(), 6_000);
        assert_eq!(e.samples(), 34);
        let mut out = Text::new();
        log_day_energy(&mut out, &e);
        assert_eq!(out.as_str(), "day_energy vh=6.000\n");
        e.reset();
        assert_eq!(e.mvh(), 0);
    }

    #[test]
    fn the_log_line_has_three_decimals() {
        let mut e = DayEnergy::new();
        // 1.5 V for 1 h 2 min 2.4 s = 1.551 V·h.
        e.add(0, 1_500);
        e.add(3_722_400, 1_500);
        let mut out = Text::new();
        log_day_energy(&mut out, &e);
        assert_eq!(out.as_str(), "day_energy vh=1.551\n");
    }

    #[test]
    fn half_a_millivolt_hour_rounds_up() {
        // 1 mV for half an hour: 1,800,000 mV·ms, 0.5 mV·h → 1.
        let mut e = DayEnergy::new();
        e.add(0, 1);
        e.add(1_800_000, 1);
        assert_eq!(e.mvh(), 1);
        // A millisecond less: 0.49999… → 0.
        let mut e = DayEnergy::new();
        e.add(0, 1);
        e.add(1_799_999, 1);
        assert_eq!(e.mvh(), 0);
        // 60 V for the longest span counted, 2^31 − 1 ms: 60,000 ·
        // 2,147,483,647 / 3,600,000 = 35,791,394.1167 mV·h (Python's
        // fractions), down.
        let mut e = DayEnergy::new();
        e.add(0, 60_000);
        e.add((1 << 31) - 1, 60_000);
        assert_eq!(e.mvh(), 35_791_394);
    }

    #[test]
    fn nothing_overflows() {
        // The largest trapezoids, across the clock's wrap, until the sum
        // saturates.
        let mut e = DayEnergy::new();
        let mut t = 0u32;
        for _ in 0..4 {
            e.add(t, u32::MAX);
            t = t.wrapping_add((1 << 31) - 1);
        }
        assert!(e.mvh() > 0);
    }
}
