//! The stall watch every board's axes share: a commanded move whose
//! feedback (an encoder, or attitude sensors) shows no motion within a
//! time is a stall.
//!
//! The watch keeps one thing: the feedback angle and the monotonic time
//! where it was armed (a move started) or where motion was last seen. Its
//! callers choose the two thresholds: the library
//! [`Controller`](crate::controller::Controller) decides one tick after a
//! command of at least half a degree, with 0.05° of motion as the proof
//! (a timeout of
//! [`STALL_MIN_WAIT_MS`](crate::controller::STALL_MIN_WAIT_MS): the next
//! look at least that long after the command decides); the servo loop of the Uno
//! waits [`STALL_TIMEOUT_MS`](crate::servo_tracker::STALL_TIMEOUT_MS) for
//! half an encoder count. Both run on the monotonic clock, so a step of
//! the wall clock never delays the verdict.

/// What a look at the feedback found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StallVerdict {
    /// The feedback moved at least the threshold: the watch restarts at
    /// the new angle and time.
    Moving,
    /// No motion of the threshold within the timeout.
    Stalled,
    /// No motion yet, but the timeout has not run out.
    Waiting,
}

/// A stall watch over one axis (see the module documentation).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StallWatch {
    /// Feedback angle, degrees, and the monotonic ms (the 32-bit clock of
    /// [`crate::time::monotonic`]) where the watch started or motion was
    /// last seen; `None` while disarmed. The time since wraps correctly
    /// below 49.7 days; a watch is looked at every tick, so a verdict never
    /// waits that long.
    origin: Option<(f32, u32)>,
}

impl StallWatch {
    /// A disarmed watch.
    pub const fn new() -> Self {
        StallWatch { origin: None }
    }

    /// A move starts with the feedback at `feedback_deg`, at monotonic
    /// `now_ms`.
    pub fn arm(&mut self, feedback_deg: f32, now_ms: u32) {
        self.origin = Some((feedback_deg, now_ms));
    }

    /// Nothing to watch (the axis rests, homes, or was stopped).
    pub fn disarm(&mut self) {
        self.origin = None;
    }

    /// True while a move is watched.
    pub fn is_armed(&self) -> bool {
        self.origin.is_some()
    }

    /// Looks at the feedback `feedback_deg` at monotonic `now_ms`: moved at
    /// least `min_motion_deg` from where the watch started →
    /// [`StallVerdict::Moving`] (and the watch restarts there); else, once
    /// `timeout_ms` have passed since → [`StallVerdict::Stalled`]; else
    /// [`StallVerdict::Waiting`]. `None` while disarmed. A non-finite
    /// feedback value counts as no motion.
    pub fn check(
        &mut self,
        feedback_deg: f32,
        now_ms: u32,
        min_motion_deg: f32,
        timeout_ms: u32,
    ) -> Option<StallVerdict> {
        let (from_deg, since_ms) = self.origin?;
        let still = (feedback_deg - from_deg).abs() < min_motion_deg || !feedback_deg.is_finite();
        if !still {
            self.origin = Some((feedback_deg, now_ms));
            return Some(StallVerdict::Moving);
        }
        if crate::time::monotonic::elapsed_ms(now_ms, since_ms) >= timeout_ms {
            Some(StallVerdict::Stalled)
        } else {
            Some(StallVerdict::Waiting)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disarmed_has_no_verdict() {
        let mut w = StallWatch::new();
        assert_eq!(w.check(10.0, 1_000, 0.05, 0), None);
        w.arm(10.0, 0);
        w.disarm();
        assert_eq!(w.check(10.0, 1_000, 0.05, 0), None);
    }

    #[test]
    fn motion_restarts_the_watch() {
        let mut w = StallWatch::new();
        w.arm(10.0, 0);
        assert_eq!(
            w.check(10.2, 1_000, 0.15, 5_000),
            Some(StallVerdict::Moving)
        );
        // Timed from the motion at 1,000 ms, not from the arming.
        assert_eq!(
            w.check(10.25, 5_999, 0.15, 5_000),
            Some(StallVerdict::Waiting)
        );
        assert_eq!(
            w.check(10.25, 6_000, 0.15, 5_000),
            Some(StallVerdict::Stalled)
        );
    }

    #[test]
    fn zero_timeout_decides_at_the_next_look() {
        let mut w = StallWatch::new();
        w.arm(-3.0, 500);
        assert_eq!(w.check(-3.04, 500, 0.05, 0), Some(StallVerdict::Stalled));
        assert_eq!(w.check(-3.06, 600, 0.05, 0), Some(StallVerdict::Moving));
    }

    #[test]
    fn non_finite_feedback_is_no_motion() {
        let mut w = StallWatch::new();
        w.arm(0.0, 0);
        assert_eq!(w.check(f32::NAN, 10, 0.05, 0), Some(StallVerdict::Stalled));
        assert_eq!(
            w.check(f32::INFINITY, 10, 0.05, 0),
            Some(StallVerdict::Stalled)
        );
    }
}
