//! The monotonic clock as the core keeps it: the board's milliseconds since
//! boot, the low 32 bits ([`Platform::now_ms`](crate::firmware::Platform)
//! truncated), wrapping every 2³² ms (49.7 days).
//!
//! Every duration the tracker measures on this clock is far shorter than
//! that (the longest: a retry back-off of 10 minutes, an hour of fault
//! history, a wind release or a status period of hours), and on an 8-bit
//! core a 64-bit stamp costs eight registers for each comparison and
//! subtraction. Three rules keep a wrapped stamp from ever looking recent:
//!
//! - a duration is a wrapping difference ([`elapsed_ms`]), exact for any
//!   span under 2³² ms;
//! - a deadline is reached once `now` is at or past it by at most
//!   [`MAX_AGE_MS`] ([`reached`]); whoever holds a deadline looks at it
//!   every tick and pulls a passed one up to `now` ([`catch_up`]), so a
//!   passed deadline stays passed however long it waits;
//! - a stamp that may be kept for long is read through [`age_ms`], which
//!   holds it at most [`MAX_AGE_MS`] in the past: read every tick, its age
//!   grows to 24.8 days and stays there.

/// The longest age a stamp is counted to, and the furthest a deadline is
/// set ahead: 2³¹ − 1 ms (24.8 days).
pub const MAX_AGE_MS: u32 = i32::MAX as u32;

/// The core's clock from a board's 64-bit millisecond count: its low 32
/// bits.
///
/// ```
/// use suntracker::time::monotonic::from_board_ms;
///
/// assert_eq!(from_board_ms(1_000), 1_000);
/// assert_eq!(from_board_ms((1 << 32) + 7), 7); // 49.7 days on: wrapped
/// ```
#[inline]
pub const fn from_board_ms(board_ms: u64) -> u32 {
    board_ms as u32
}

/// Milliseconds from `since_ms` to `now_ms` on the wrapping 32-bit clock.
///
/// ```
/// use suntracker::time::monotonic::elapsed_ms;
///
/// assert_eq!(elapsed_ms(1_500, 1_000), 500);
/// // Across the wrap: 5 ms before it to 5 ms after.
/// assert_eq!(elapsed_ms(4, u32::MAX - 5), 10);
/// ```
#[inline]
pub const fn elapsed_ms(now_ms: u32, since_ms: u32) -> u32 {
    now_ms.wrapping_sub(since_ms)
}

/// Whether `deadline_ms` has come at `now_ms`: `now_ms` is at the deadline
/// or past it by at most [`MAX_AGE_MS`] (the deadline was set at most that
/// far ahead, and passed deadlines are caught up every tick).
///
/// ```
/// use suntracker::time::monotonic::reached;
///
/// assert!(!reached(999, 1_000));
/// assert!(reached(1_000, 1_000));
/// // Set 10 ms before the wrap for 20 ms later: due 10 ms after it.
/// let deadline = (u32::MAX - 9).wrapping_add(20);
/// assert!(!reached(u32::MAX, deadline));
/// assert!(reached(10, deadline));
/// ```
#[inline]
pub const fn reached(now_ms: u32, deadline_ms: u32) -> bool {
    elapsed_ms(now_ms, deadline_ms) <= MAX_AGE_MS
}

/// Pulls a passed `deadline_ms` up to `now_ms`: it stays reached, however
/// long the holder waits before acting on it.
#[inline]
pub fn catch_up(deadline_ms: &mut u32, now_ms: u32) {
    if reached(now_ms, *deadline_ms) {
        *deadline_ms = now_ms;
    }
}

/// The age of `since_ms` at `now_ms`, at most [`MAX_AGE_MS`]: an older
/// stamp (or one after `now_ms`) is moved to [`MAX_AGE_MS`] before
/// `now_ms`, so that it stays that old as long as it is read at least once
/// every 24.8 days.
///
/// ```
/// use suntracker::time::monotonic::{age_ms, MAX_AGE_MS};
///
/// let mut since = 1_000;
/// assert_eq!(age_ms(&mut since, 61_000), 60_000);
/// assert_eq!(since, 1_000);
/// // Read every 10 days: held at 24.8 days from the third reading on, also
/// // past the clock's 49.7-day wrap.
/// let mut now: u32 = 61_000;
/// for days in [10, 20, 30, 40, 50, 60] {
///     now = now.wrapping_add(10 * 86_400_000);
///     let age = age_ms(&mut since, now);
///     assert_eq!(age, (days * 86_400_000 + 60_000).min(MAX_AGE_MS as u64) as u32);
/// }
/// ```
#[cfg_attr(not(target_arch = "avr"), inline)]
// Out of line on the AVR: four inlined copies there.
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn age_ms(since_ms: &mut u32, now_ms: u32) -> u32 {
    let age = elapsed_ms(now_ms, *since_ms);
    if age > MAX_AGE_MS {
        *since_ms = now_ms.wrapping_sub(MAX_AGE_MS);
        MAX_AGE_MS
    } else {
        age
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_passed_deadline_caught_up_every_day_stays_passed_for_a_hundred_days() {
        let mut deadline = 5_000u32;
        let mut now = 0u32;
        for _ in 0..100 {
            now = now.wrapping_add(86_400_000);
            assert!(reached(now, deadline), "{now}");
            catch_up(&mut deadline, now);
        }
        // Without catching up, the same deadline reads as not reached
        // between 24.8 and 49.7 days after it.
        assert!(!reached(5_000 + 30 * 86_400_000, 5_000));
    }

    #[test]
    fn a_deadline_ahead_is_not_pulled_in() {
        let mut deadline = 10_000u32;
        catch_up(&mut deadline, 9_999);
        assert_eq!(deadline, 10_000);
        catch_up(&mut deadline, 10_001);
        assert_eq!(deadline, 10_001);
    }

    #[test]
    fn an_aged_stamp_never_comes_round() {
        let mut since = 0u32;
        let mut now = 0u32;
        // Read hourly for 200 days (four wraps of the clock).
        for hour in 1..=24 * 200u32 {
            now = now.wrapping_add(3_600_000);
            let true_age_ms = u64::from(hour) * 3_600_000;
            let age = age_ms(&mut since, now);
            assert_eq!(u64::from(age), true_age_ms.min(u64::from(MAX_AGE_MS)));
        }
    }
}
