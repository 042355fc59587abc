//! `defmt::Format` for [`DateTime`] (feature `defmt`): ISO 8601 as its
//! `Display`, `2024-03-10T12:34:56Z`, with `.sss` only when the milliseconds
//! are not zero.

use super::DateTime;

impl defmt::Format for DateTime {
    fn format(&self, f: defmt::Formatter<'_>) {
        if self.millis == 0 {
            defmt::write!(
                f,
                "{=u16:04}-{=u8:02}-{=u8:02}T{=u8:02}:{=u8:02}:{=u8:02}Z",
                self.year(),
                self.month(),
                self.day(),
                self.hour,
                self.minute,
                self.second
            );
        } else {
            defmt::write!(
                f,
                "{=u16:04}-{=u8:02}-{=u8:02}T{=u8:02}:{=u8:02}:{=u8:02}.{=u16:03}Z",
                self.year(),
                self.month(),
                self.day(),
                self.hour,
                self.minute,
                self.second,
                self.millis
            );
        }
    }
}
