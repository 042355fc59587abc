//! `defmt::Format` for [`Date`] (feature `defmt`): ISO 8601 as its
//! `Display`, `2024-02-29`, `-0044-03-15`.

use crate::Date;

impl defmt::Format for Date {
    fn format(&self, f: defmt::Formatter<'_>) {
        let year = self.year();
        if year < 0 {
            defmt::write!(f, "-");
        }
        // |year| ≤ 9999: four digits.
        defmt::write!(
            f,
            "{=u16:04}-{=u8:02}-{=u8:02}",
            year.unsigned_abs() as u16,
            self.month(),
            self.day()
        );
    }
}
