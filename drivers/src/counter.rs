//! Event counters: one out-of-line step of a saturating `u32` count.

/// Counts one more event in `counter`, stopping at `u32::MAX`
/// (`u32::saturating_add(1)`): a count never wraps back to small.
// Out of line on the AVR: a saturating 32-bit increment written out
// (load, add, carry test, store) is some 30 bytes on an 8-bit CPU, a call
// with its pointer under a third of that, and the fault, time and GPS
// statistics count in many places.
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn count_up(counter: &mut u32) {
    *counter = counter.saturating_add(1);
}

#[cfg(test)]
mod tests {
    use super::count_up;

    #[test]
    fn counts_up_and_stops_at_the_top() {
        let mut c = 0;
        count_up(&mut c);
        count_up(&mut c);
        assert_eq!(c, 2);
        let mut top = u32::MAX - 1;
        count_up(&mut top);
        assert_eq!(top, u32::MAX);
        count_up(&mut top);
        assert_eq!(top, u32::MAX);
    }
}
