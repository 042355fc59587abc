//! `defmt::Format` for [`UtcTime`] (feature `defmt`): ISO 8601 as its
//! `Display` (`2031-04-05T06:07:08Z`, milliseconds when not zero), with four
//! year digits after a minus sign as suntracker-time's `Date` prints them.
//! The other public types derive theirs where they are defined.

use crate::time::UtcTime;

impl defmt::Format for UtcTime {
    fn format(&self, f: defmt::Formatter<'_>) {
        let (y, mo, d) = self.ymd();
        let (h, mi, s, ms) = self.hms_milli();
        // Years −4000…8000: four digits.
        let abs = y.unsigned_abs() as u16;
        if y < 0 {
            defmt::write!(f, "-");
        }
        defmt::write!(
            f,
            "{=u16:04}-{=u8:02}-{=u8:02}T{=u8:02}:{=u8:02}:{=u8:02}",
            abs,
            mo,
            d,
            h,
            mi,
            s
        );
        if ms != 0 {
            defmt::write!(f, ".{=u16:03}", ms);
        }
        defmt::write!(f, "Z");
    }
}
