//! One axis of the tracker: targets in degrees over a motor that counts in
//! steps (stepper) or encoder counts (servo).
//!
//! [`AxisDrive`] is the hardware side (a stepper or servo driver, or a
//! simulated plant); [`AxisController`] adds what every axis needs: the
//! counts-per-degree scale from the configuration (steps × microsteps ×
//! gear ratio / 360°), homing against the limit switch, soft limits,
//! backlash compensation, and three [`FeedbackMode`]s:
//!
//! - open loop: counted steps only;
//! - pseudo-closed loop (Jimoh & Aliyu 2019 §2.1): set-points applied open loop,
//!   the feedback only observed and its deviation reported;
//! - closed loop: correct toward the set-point from feedback until inside the
//!   deadband.

use crate::config::AxisConfig;
use crate::time::monotonic;
use drivers::stepper::{sat_add, sat_sub};

mod stall;

pub use stall::{StallVerdict, StallWatch};

/// The motor side of an axis.
pub trait AxisDrive {
    /// Bus or driver error.
    type Error;
    /// Starts a relative move of `counts` motor counts (signed). Moves are
    /// queued; [`AxisDrive::pending`] tells how many are not done yet.
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error>;
    /// Counts still to run of the moves started.
    fn pending(&self) -> i32;
    /// Stops at once, dropping pending counts.
    fn stop(&mut self) -> Result<(), Self::Error>;
    /// True while the homing limit switch is closed.
    fn at_limit(&mut self) -> Result<bool, Self::Error>;
    /// The axis angle from an output-side encoder, degrees, when fitted.
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error>;
    /// True for a drive that watches its own motor ([`AxisDrive::take_fault`]);
    /// the controller's checks of it compile away for the others.
    const SELF_WATCHED: bool = false;
    /// True while this drive watches its own motor: [`AxisDrive::SELF_WATCHED`],
    /// unless the kind is chosen at run time (a board's axis that is a
    /// stepper or a DC motor by its configuration).
    fn self_watched(&self) -> bool {
        Self::SELF_WATCHED
    }
    /// A fault the drive detected itself (a DC motor's current and Hall
    /// watch), reported once: a latched fault ([`DriveFault::Stall`],
    /// [`DriveFault::Obstruction`], [`DriveFault::TooSlow`]) refuses moves until
    /// [`AxisDrive::clear_fault`]; [`DriveFault::UnexpectedMotion`] is not
    /// latched. Drives without a watch of their own (steppers, servos,
    /// whose stalls the controller sees on the encoder) report none.
    fn take_fault(&mut self) -> Option<DriveFault> {
        None
    }
    /// True while a fault stops the drive (moves are refused).
    fn fault_latched(&self) -> bool {
        false
    }
    /// Ends a latched fault: the drive rests where it is and takes moves
    /// again (a retry).
    fn clear_fault(&mut self) {}
    /// The axis's count was taken back by `counts` (whole turns of an
    /// axis that turns without end, [`AxisController::rebase`]): a drive
    /// that counts its own feedback from the home switch takes its
    /// reference back as much, so that its angle stays within a turn of
    /// the switch (and exact in `f32`) however many turns the axis makes.
    fn rebase_counts(&mut self, _counts: i32) {}
    /// Whether the home switch stops motion toward it (on from power-on,
    /// as every drive here does). [`AxisController`] turns it off on an
    /// axis that turns without end once it is homed (the switch is then an
    /// index it passes once a turn) and on again to home.
    fn switch_stops(&mut self, _on: bool) {}
    /// At rest, takes the next move from where the drive measures itself
    /// rather than from its last target; [`AxisController::update`] calls
    /// it before it corrects a measured error. For a drive that rests only
    /// on its feedback's steps (a linear actuator on Hall pulse edges: the
    /// edge nearest the target), so that the correction of that step's
    /// error does not move it to the step on the other side, and back.
    fn rebase_at_rest(&mut self) {}
    /// The motor supply measured now, mV (0: none). A drive whose runs
    /// depend on it (a DC motor moved by time: [`crate::hw::TimedAxis`])
    /// scales them; the others ignore it.
    fn set_supply_mv(&mut self, _supply_mv: u32) {}
}

/// A fault seen by the drive itself ([`AxisDrive::take_fault`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriveFault {
    /// Driven, but no feedback count for the drive's stall time (jammed
    /// gear, failed Hall sensor, open motor lead).
    Stall,
    /// Motor current above its limit for the drive's overcurrent time (the
    /// axis met an obstacle).
    Obstruction,
    /// Counts while the motor rests (an external force back-drives the
    /// axis, or a loose gear).
    UnexpectedMotion,
    /// A move took longer than its distance at the drive's slowest
    /// expected speed, with a margin (a load or a low supply slows the
    /// motor).
    TooSlow,
}

/// How the axis uses feedback.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeedbackMode {
    /// Counted steps only.
    OpenLoop,
    /// Counted steps; feedback observed and reported, never acted upon.
    PseudoClosed,
    /// Correct from feedback until inside the deadband.
    ClosedLoop,
}

/// Errors of an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisError<E> {
    /// The drive failed.
    Drive(E),
    /// The axis has not been homed.
    NotHomed,
    /// A target or feedback value was NaN or infinite.
    NotFinite,
    /// Homing ran its whole travel without closing the switch.
    HomeNotFound,
}

/// State of a homing run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HomeState {
    /// Not homed.
    Idle,
    /// The switch was closed at the start: moving off it first.
    BackingOff,
    /// Driving toward the switch.
    Seeking,
    /// Homed: the counted position is the switch angle.
    Done,
}

/// What one [`AxisController::update`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisReport {
    /// The target after soft limits.
    pub target_deg: f32,
    /// True when the target was clamped to a soft limit.
    pub clamped: bool,
    /// Counts commanded in this update (including backlash take-up).
    pub commanded_counts: i32,
    /// Feedback minus target, when feedback was available.
    pub deviation_deg: Option<f32>,
}

/// Total back-off from a closed limit switch, degrees: homing never takes
/// the counted position more than this above the lowest point homing took
/// it to since the axis last had a reference, however many attempts. A
/// stuck-closed switch thus costs 15° of motion once, not 15° per attempt.
pub const HOMING_BACKOFF_MAX_DEG: f32 = 15.0;

/// Margin of a homing seek below the lowest soft limit or the home angle,
/// whichever is lower, degrees (the backlash is added): once the axis has
/// had a reference, its counted position is a good estimate and a seek
/// stops there instead of running a whole travel into the hard stop.
pub const HOMING_SEEK_MARGIN_DEG: f32 = 5.0;

/// Extra travel of a homing attempt beyond the soft-limit span, degrees
/// (the backlash is added): an attempt takes the axis at most `max_deg −
/// min_deg + 10° + backlash_deg` below where it started.
pub const HOMING_SEEK_EXTRA_DEG: f32 = 10.0;

/// The slow final approach of homing (and the back-off before it) moves
/// this many times slower than the fast approach: `max_speed_deg_s / 50`
/// by time, and at least `chunk_deg / 50` a step.
pub const HOMING_FINE_DIVISOR: f32 = 50.0;

/// Longest monotonic interval one homing step moves for, milliseconds: the
/// move of a step covers the axis's speed × the time since the previous
/// step, but never more than this (a step after a pause — a safe stop, a
/// late tick — does not queue minutes of travel at once). Longer than any
/// board's controller tick, so homing runs at the drive's speed whatever
/// the tick.
pub const HOMING_MAX_INTERVAL_MS: u32 = 30_000;

/// Feedback is believed up to this far outside the soft limits, degrees;
/// beyond, it is clamped before the count is re-anchored on it (an encoder
/// glitch of 1e30° must not move the count out of every range).
pub const FEEDBACK_MARGIN_DEG: f32 = 90.0;

/// Counts per degree used when the configuration's are not finite or not
/// positive.
const FALLBACK_COUNTS_PER_DEG: f32 = 1.0;
/// Counts per degree are clamped to this (see
/// `config::ranges::COUNTS_PER_DEG`); below, the lowest value that keeps
/// `counted_deg` meaningful for any `i64` count.
const COUNTS_PER_DEG_CLAMP: (f32, f32) = (1e-3, 1e6);
/// Angles of an invalid configuration are clamped to this, degrees.
const ANGLE_CLAMP_DEG: f32 = 365.0;
/// Speeds of an invalid configuration are clamped to the configuration's
/// range, °/s (the lowest when not finite).
const SPEED_RANGE_DEG_S: (f32, f32) = crate::config::ranges::MAX_SPEED_DEG_S;

/// `v` into `lo..=hi` by comparisons (`f32::max`/`min` and `clamp` are
/// library calls on an AVR, and `clamp` has a panic path); NaN stays NaN.
/// Not inlined: a call is smaller than the compares at each of its callers
/// (measured on the Black Pill and the Uno alike).
#[inline(never)]
fn within(v: f32, lo: f32, hi: f32) -> f32 {
    if v < lo {
        lo
    } else if v > hi {
        hi
    } else {
        v
    }
}

/// `v` when finite, else `fallback`; then [`within`] `lo..=hi`. Not
/// inlined: seven calls build a [`Geometry`].
#[inline(never)]
fn sane(v: f32, fallback: f32, lo: f32, hi: f32) -> f32 {
    within(if v.is_finite() { v } else { fallback }, lo, hi)
}

/// Angles and scale of an axis, made safe for the arithmetic whatever the
/// configuration: finite, ordered, bounded. For a configuration that passes
/// `Config::validate` they equal the configured values.
#[derive(Debug, Clone, Copy)]
struct Geometry {
    counts_per_deg: f32,
    min_deg: f32,
    max_deg: f32,
    home_deg: f32,
    backlash_deg: f32,
    deadband_deg: f32,
    speed_deg_s: f32,
    /// Motor counts per turn of an axis that turns without end
    /// (`continuous` on, a whole number of counts per turn); 0 for an
    /// axis between limits.
    turn_counts: i32,
}

impl Geometry {
    fn of(c: &AxisConfig) -> Self {
        let cpd = c.counts_per_deg();
        let counts_per_deg = if cpd > 0.0 {
            // An infinite scale takes the fallback too.
            sane(
                cpd,
                FALLBACK_COUNTS_PER_DEG,
                COUNTS_PER_DEG_CLAMP.0,
                COUNTS_PER_DEG_CLAMP.1,
            )
        } else {
            FALLBACK_COUNTS_PER_DEG
        };
        let a = sane(
            c.min_deg,
            -ANGLE_CLAMP_DEG,
            -ANGLE_CLAMP_DEG,
            ANGLE_CLAMP_DEG,
        );
        let b = sane(
            c.max_deg,
            ANGLE_CLAMP_DEG,
            -ANGLE_CLAMP_DEG,
            ANGLE_CLAMP_DEG,
        );
        let (min_deg, max_deg) = if a <= b { (a, b) } else { (b, a) };
        Geometry {
            counts_per_deg,
            min_deg,
            max_deg,
            home_deg: sane(c.home_deg, min_deg, min_deg - 5.0, max_deg + 5.0),
            backlash_deg: sane(c.backlash_deg, 0.0, 0.0, 5.0),
            deadband_deg: sane(c.deadband_deg, 0.0, 0.0, 5.0),
            speed_deg_s: sane(
                c.max_speed_deg_s,
                SPEED_RANGE_DEG_S.0,
                SPEED_RANGE_DEG_S.0,
                SPEED_RANGE_DEG_S.1,
            ),
            turn_counts: if c.continuous != 0 { turn_counts(c) } else { 0 },
        }
    }

    /// `target_deg` inside the soft limits; as it is on an axis that turns
    /// without end (the limits bound its homing only).
    fn limit(&self, target_deg: f32) -> f32 {
        if self.turn_counts != 0 {
            target_deg
        } else {
            within(target_deg, self.min_deg, self.max_deg)
        }
    }

    /// `deg` in motor counts, to the nearest count. `deg` is clamped to
    /// ±4 × 365°, which no move of a sane geometry exceeds, so the result
    /// is within ±1.5 × 10^9 counts (`counts_per_deg` ≤ 10^6), inside the
    /// `i32` range; NaN gives 0.
    // Not inlined: called from eight places of homing and moves; an
    // inlined copy (clamp, product, rounding, conversion) is some 150 B on
    // an AVR.
    #[inline(never)]
    fn counts(&self, deg: f32) -> i32 {
        const LIMIT_DEG: f32 = 4.0 * ANGLE_CLAMP_DEG;
        if deg.is_nan() {
            return 0;
        }
        let c = within(deg, -LIMIT_DEG, LIMIT_DEG) * self.counts_per_deg;
        // To the nearest count, halves away from zero (a truncated move
        // ends up to a whole count short of its target, and the counts of
        // successive moves would always fall short the same way). By ±0.5
        // and truncation, not libm's `roundf` (some 200 B of bit handling
        // inlined on an AVR): the sum rounds to f32, so a value less than
        // one unit in the last place below a half may round up, a count
        // off in a case no configuration meets on purpose. In range of i32
        // by the clamps; `as` saturates anyway.
        (if c < 0.0 { c - 0.5 } else { c + 0.5 }) as i32
    }
}

/// Motor counts per turn of the axis, when whole and at most
/// [`MAX_TURN_COUNTS`] (what a configuration that passes
/// `Config::validate` with `continuous` on has: its counts per degree are
/// at most 10^6); else 0. In integers: the product in `f32` is not exact
/// beyond 2^24.
fn turn_counts(c: &AxisConfig) -> i32 {
    let gear = c.gear_ratio as i32;
    let cpd = c.counts_per_deg();
    // Bounded first by the counts per degree (in `f32`, within a
    // millionth): the exact product below is then under 3.6 × 10^8 × (1 +
    // 10^-6), far inside `i32`, and plain (wrapping) products compute it.
    // (`checked_mul` links the runtime's overflow-checking product, which
    // on the AVR ran the stack into the static RAM.)
    if gear as f32 != c.gear_ratio || gear <= 0 || !(cpd > 0.0 && cpd <= 1e6) {
        return 0;
    }
    let n = c
        .counts_per_motor_rev
        .wrapping_mul(u32::from(c.microsteps))
        .wrapping_mul(gear as u32);
    if n > 0 && n <= MAX_TURN_COUNTS as u32 {
        n as i32
    } else {
        0
    }
}

/// Largest turn of an axis that turns without end, motor counts: 360° at
/// the highest counts per degree the configuration allows (10^6).
const MAX_TURN_COUNTS: i32 = 360_000_000;

/// An axis under control.
///
/// Fields in this order (`repr(C)`): the homing and position state, then
/// the geometry, then the drive (the largest, read through its own
/// methods). The AVR's `ldd`/`std` reach 63 bytes past a pointer, and with
/// the compiler's order (the drive first) most of the state lay beyond
/// them: this order is 408 B less on the ATmega2560 (116,768 -> 116,360 B).
#[derive(Debug)]
#[repr(C)]
pub struct AxisController<D> {
    home: HomeState,
    /// Position in counts relative to the home switch, as commanded; while
    /// not homed, counted on from the last reference (or from power-on).
    /// 32 bits: every position homing or a move reaches is within the
    /// soft limits' span plus the homing margins, a few times 365° ×
    /// `counts_per_deg` ≤ 10^6 (see `Geometry::counts`); the arithmetic
    /// saturates beyond.
    position_counts: i32,
    /// Direction of the last move: +1, −1 or 0 (unknown).
    last_dir: i8,
    /// Second, slow approach of homing.
    fine: bool,
    /// The axis has been homed at least once: the counted position is an
    /// estimate of the angle even while not homed.
    referenced: bool,
    /// Lowest counted position homing reached since the last reference
    /// (`None` until homing starts); back-off stays within
    /// [`HOMING_BACKOFF_MAX_DEG`] of it.
    homing_low_counts: Option<i32>,
    /// Counted position at the start of this homing attempt.
    attempt_start_counts: i32,
    /// Monotonic time of the previous homing step of this attempt, ms: the
    /// next step moves for the time since.
    /// Kept in 32 bits: a step more than 49.7 days after the previous one
    /// takes the wrapped interval, and every interval is capped at
    /// [`HOMING_MAX_INTERVAL_MS`] anyway.
    homing_last_ms: Option<u32>,
    /// The configuration as the arithmetic uses it (the configuration
    /// itself is not kept: its owner holds it).
    geo: Geometry,
    drive: D,
}

impl<D: AxisDrive> AxisController<D> {
    /// An axis over `drive`; not homed yet. Any `config` is accepted; the
    /// arithmetic stays in range even for one that fails
    /// `Config::validate` (its values are then clamped). Always inlined on
    /// the AVR: built in its place in the controller, not first in a
    /// frame of the controller's constructor (two axes there were 440 B of
    /// the ATmega2560's deepest stack, the power-on's).
    #[cfg_attr(target_arch = "avr", inline(always))]
    pub fn new(drive: D, config: AxisConfig) -> Self {
        AxisController {
            drive,
            geo: Geometry::of(&config),
            position_counts: 0,
            last_dir: 0,
            home: HomeState::Idle,
            attempt_start_counts: 0,
            fine: false,
            referenced: false,
            homing_low_counts: None,
            homing_last_ms: None,
        }
    }

    /// The drive.
    pub fn drive_mut(&mut self) -> &mut D {
        &mut self.drive
    }

    /// The drive, read-only.
    pub fn drive(&self) -> &D {
        &self.drive
    }

    /// The home switch's angle, degrees.
    pub fn home_deg(&self) -> f32 {
        self.geo.home_deg
    }

    /// The soft limits `(min_deg, max_deg)`, ordered.
    pub fn limits_deg(&self) -> (f32, f32) {
        (self.geo.min_deg, self.geo.max_deg)
    }

    /// Takes a new configuration (an operator changed it). When what turns
    /// counts into degrees changed (counts per degree of axis, from the
    /// counts per motor revolution, microsteps and gear ratio; the home
    /// switch's angle), the counted position no longer means the same
    /// angle: the axis forgets its reference and homes again as at
    /// power-on. New limits, speed, dead band, backlash or `continuous`
    /// apply from the next move.
    pub fn set_config(&mut self, config: AxisConfig) {
        let new = Geometry::of(&config);
        let scale_same =
            new.counts_per_deg == self.geo.counts_per_deg && new.home_deg == self.geo.home_deg;
        // A homed axis made one that turns without end passes its switch
        // from now on; made one between limits, stops at it again.
        let endless = new.turn_counts != 0;
        if endless != (self.geo.turn_counts != 0) && self.home == HomeState::Done {
            self.drive.switch_stops(!endless);
        }
        self.geo = new;
        if !scale_same {
            self.home = HomeState::Idle;
            self.referenced = false;
            self.homing_low_counts = None;
            self.fine = false;
        }
    }

    /// Homing state.
    pub fn home_state(&self) -> HomeState {
        self.home
    }

    /// True once the axis has been homed: while not homed, the counted
    /// position is then an estimate from that reference.
    pub fn has_had_reference(&self) -> bool {
        self.referenced
    }

    /// Forgets the reference (after a fault): homing is needed again. The
    /// count goes on from the last reference, which bounds the homing
    /// moves (see [`AxisController::home_step`]).
    pub fn unhome(&mut self) {
        self.home = HomeState::Idle;
    }

    /// The angle the step count says, degrees. Out of line on the AVR: a
    /// call is smaller than the count's load and the call it wraps, at a
    /// dozen callers.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn counted_deg(&self) -> f32 {
        self.deg_from_home(self.position_counts)
    }

    /// The axis angle `counts` motor counts from the home switch, degrees.
    /// Not inlined: a call is smaller than its float load, convert, divide
    /// and add (a dozen callers).
    #[inline(never)]
    pub fn deg_from_home(&self, counts: i32) -> f32 {
        self.geo.home_deg + counts as f32 / self.geo.counts_per_deg
    }

    /// Motor counts from the home switch to the axis angle `deg`, to the
    /// nearest count (see `Geometry::counts` for the range); not held to
    /// the soft limits.
    pub fn counts_from_home(&self, deg: f32) -> i32 {
        self.geo.counts(deg - self.geo.home_deg)
    }

    /// Motor counts per degree of axis, as this controller computes with
    /// (the configuration's, made safe as [`AxisController::new`] says).
    pub fn counts_per_deg(&self) -> f32 {
        self.geo.counts_per_deg
    }

    /// The counted position, motor counts from the home switch.
    pub fn position_counts(&self) -> i32 {
        self.position_counts
    }

    /// True for an axis that turns without end (`continuous` on).
    pub fn is_continuous(&self) -> bool {
        self.geo.turn_counts != 0
    }

    /// `deg`, an angle of the axis measured (an encoder's, the compass's),
    /// on an axis that turns without end by whole turns to within half a
    /// turn of the counted position (where the counts say the axis is,
    /// whatever turn the measurement counts from); unchanged on an axis
    /// between limits, and when not finite.
    pub fn near_count(&self, deg: f32) -> f32 {
        if self.geo.turn_counts == 0 || !deg.is_finite() {
            return deg;
        }
        let d = deg - self.counted_deg();
        // Whole turns, to the nearest (halves away from zero); `as`
        // saturates for an absurd reading, which `reanchor` clamps.
        let turns = (d / 360.0 + if d < 0.0 { -0.5 } else { 0.5 }) as i32;
        deg - turns as f32 * 360.0
    }

    /// How far above its home switch the axis is now, degrees: the counted
    /// position less the counts the drive has still to run. A move is
    /// counted when it is commanded, and a drive that starts slowly (a DC
    /// motor ramping up) is still on its switch a tick or more after a
    /// move away from it: by the counted position alone its closed switch
    /// read as met far from home. On an axis that turns without end, within
    /// the turn (a move passes the switch once a turn), within
    /// [`HOMING_BACKOFF_MAX_DEG`] below the switch counting as at it
    /// (negative).
    pub fn above_home_deg(&self) -> f32 {
        let turn = self.geo.turn_counts;
        let now = sat_sub(self.position_counts, self.drive.pending());
        if turn == 0 {
            return self.deg_from_home(now) - self.geo.home_deg;
        }
        let d = now.wrapping_rem_euclid(turn) as f32 / self.geo.counts_per_deg;
        if d > 360.0 - HOMING_BACKOFF_MAX_DEG {
            d - 360.0
        } else {
            d
        }
    }

    /// On a homed axis that turns without end, takes whole turns off the
    /// count so that it lies within the turn above the home switch
    /// (nothing moves; the drive takes its own count back as much,
    /// [`AxisDrive::rebase_counts`]) and returns the turns taken off
    /// (negative when added); 0 otherwise. Exact: a turn is a whole number
    /// of counts. The owner of targets in degrees takes as many turns off
    /// them.
    pub fn rebase(&mut self) -> i32 {
        let turn = self.geo.turn_counts;
        if turn == 0 || self.home != HomeState::Done {
            return 0;
        }
        let within = self.position_counts.wrapping_rem_euclid(turn);
        let shift = sat_sub(self.position_counts, within);
        if shift == 0 {
            return 0;
        }
        self.position_counts = within;
        self.drive.rebase_counts(shift);
        // `turn` > 0 (no overflow: the wrapping forms have no panic path).
        shift.wrapping_div(turn)
    }

    /// Commands `c` counts and returns them; the caller accounts the
    /// position.
    fn command(&mut self, c: i32) -> Result<i32, AxisError<D::Error>> {
        if c != 0 {
            self.drive.move_counts(c).map_err(AxisError::Drive)?;
        }
        Ok(c)
    }

    /// Takes `feedback_deg` (an encoder's or the attitude sensors' angle
    /// of the axis) as the counted position: after a stall the drive
    /// stopped where it was held, and the count follows the measurement
    /// rather than the commands. Non-finite feedback is ignored; feedback
    /// beyond the soft limits by more than [`FEEDBACK_MARGIN_DEG`] is
    /// clamped first.
    pub fn reanchor(&mut self, feedback_deg: f32) {
        if feedback_deg.is_finite() {
            let g = &self.geo;
            // An axis that turns without end is kept within a turn above
            // its switch, and its targets within half a turn of that.
            let (lo, hi) = if g.turn_counts != 0 {
                (g.home_deg - 180.0, g.home_deg + 540.0)
            } else {
                (g.min_deg, g.max_deg)
            };
            let fb = within(
                feedback_deg,
                lo - FEEDBACK_MARGIN_DEG,
                hi + FEEDBACK_MARGIN_DEG,
            );
            self.position_counts = g.counts(fb - g.home_deg);
        }
    }

    /// Stops the drive and takes the counts it drops off the position.
    /// (Stopping through [`AxisController::drive_mut`] instead would leave the
    /// position counting a move that never ran.)
    pub fn stop(&mut self) -> Result<(), AxisError<D::Error>> {
        let before = self.drive.pending();
        self.drive.stop().map_err(AxisError::Drive)?;
        // A ramped stop still runs `after` counts; the rest never will.
        let after = self.drive.pending();
        let dropped = sat_sub(before, after);
        self.position_counts = sat_sub(self.position_counts, dropped);
        Ok(())
    }

    fn note_low(&mut self) {
        let p = self.position_counts;
        self.homing_low_counts = Some(self.homing_low_counts.map_or(p, |l| l.min(p)));
    }

    /// Counts a back-off may still move up: within
    /// [`HOMING_BACKOFF_MAX_DEG`] of the lowest point of homing and, with a
    /// reference, not beyond `max_deg` (an axis that turns without end has
    /// no end there: it may rest just below its switch, a turn above it
    /// by the count).
    fn backoff_room_counts(&self) -> i32 {
        let low = self.homing_low_counts.unwrap_or(self.position_counts);
        let mut ceiling = sat_add(low, self.geo.counts(HOMING_BACKOFF_MAX_DEG));
        if self.referenced && self.geo.turn_counts == 0 {
            ceiling = ceiling.min(self.geo.counts(self.geo.max_deg - self.geo.home_deg));
        }
        sat_sub(ceiling, self.position_counts)
    }

    /// Counts a seek may still move down: the documented travel below the
    /// position where the attempt started and, with a reference, not below the lower limit or home angle by
    /// more than [`HOMING_SEEK_MARGIN_DEG`] + backlash.
    fn seek_room_counts(&self) -> i32 {
        let g = &self.geo;
        // A whole turn finds the switch of an axis that turns without end.
        let span_deg = if g.turn_counts != 0 {
            360.0
        } else {
            g.max_deg - g.min_deg
        };
        let travel_deg = span_deg + HOMING_SEEK_EXTRA_DEG + g.backlash_deg;
        let below_start = sat_sub(self.attempt_start_counts, self.position_counts);
        let mut room = sat_sub(g.counts(travel_deg), below_start);
        if self.referenced {
            let lowest_deg = if g.home_deg < g.min_deg {
                g.home_deg
            } else {
                g.min_deg
            };
            let floor_deg = lowest_deg - HOMING_SEEK_MARGIN_DEG - g.backlash_deg;
            let floor = g.counts(floor_deg - g.home_deg);
            room = room.min(sat_sub(self.position_counts, floor));
        }
        room
    }

    /// Counts one homing move may keep queued at `now_ms`: the distance
    /// the axis covers at its homing speed (`max_speed_deg_s`, or
    /// [`HOMING_FINE_DIVISOR`] times slower on the final approach) in the
    /// monotonic time since the previous homing step, at most
    /// [`HOMING_MAX_INTERVAL_MS`] of it, plus one chunk (`chunk_deg`, or
    /// `chunk_deg / 50` on the final approach); at least one count. The
    /// chunk keeps a drive that runs at its speed from running dry just
    /// before the next step (a ramped drive would slow to a stop and start
    /// again every tick); the first step of an attempt moves one chunk.
    fn homing_move_counts(&mut self, chunk_deg: f32, now_ms: u32) -> i32 {
        let dt_ms = self
            .homing_last_ms
            .map_or(0, |t| monotonic::elapsed_ms(now_ms, t))
            .min(HOMING_MAX_INTERVAL_MS);
        self.homing_last_ms = Some(now_ms);
        let (speed_deg_s, chunk_deg) = if self.fine {
            (
                self.geo.speed_deg_s / HOMING_FINE_DIVISOR,
                chunk_deg / HOMING_FINE_DIVISOR,
            )
        } else {
            (self.geo.speed_deg_s, chunk_deg)
        };
        // dt_ms ≤ 30,000: exact in f32; the product ≤ 30 °/s × 30 s.
        let by_time_deg = speed_deg_s * (dt_ms as f32 / 1000.0);
        self.geo.counts(by_time_deg + chunk_deg).max(1)
    }

    /// One step of homing at `now_ms` (monotonic): drive toward the switch
    /// (negative direction); when the switch closes, stop, back off at the
    /// slow speed, approach it again [`HOMING_FINE_DIVISOR`] times slower,
    /// and take the switch angle as the position. Call until it returns
    /// `Done`, once a tick or more often.
    ///
    /// Speed: the moves of a step keep queued at most what the axis covers
    /// at `max_speed_deg_s` (the final approach and the back-off before it
    /// at a fiftieth of it) in the time since the previous step (see
    /// [`HOMING_MAX_INTERVAL_MS`]) plus `chunk_deg` (`chunk_deg / 50` on
    /// the final approach), minus what the drive still has queued: a drive
    /// slower than configured is topped up, never flooded. So homing runs
    /// at the drive's speed whatever the tick, and steps called in a row at
    /// one instant move one chunk each. The switch is looked at once a
    /// step: a drive that does not stop at the switch by itself (the
    /// H-bridge driver given it as its `min` limit and the servo axis do)
    /// runs up to one step's move past it, and the final approach's move
    /// is then the precision of the reference.
    ///
    /// Bounds on the motion:
    /// - a switch closed at the start (or stuck closed) is backed away from
    ///   by at most [`HOMING_BACKOFF_MAX_DEG`] above the lowest point homing
    ///   reached since the last reference, over all attempts: a new attempt
    ///   after [`AxisError::HomeNotFound`] does not back off again;
    /// - an attempt takes the axis at most `max_deg − min_deg` +
    ///   [`HOMING_SEEK_EXTRA_DEG`] + `backlash_deg` below where it started,
    ///   then reports [`AxisError::HomeNotFound`] once the drive has run it;
    /// - once the axis has had a reference, the counted position never goes
    ///   above `max_deg` backing off, nor below the lower of `min_deg` and
    ///   `home_deg` by more than [`HOMING_SEEK_MARGIN_DEG`] + `backlash_deg`
    ///   seeking.
    pub fn home_step(
        &mut self,
        chunk_deg: f32,
        now_ms: u32,
    ) -> Result<HomeState, AxisError<D::Error>> {
        if !chunk_deg.is_finite() || chunk_deg <= 0.0 {
            return Err(AxisError::NotFinite);
        }
        if self.home == HomeState::Done {
            return Ok(HomeState::Done);
        }
        let closed = self.drive.at_limit().map_err(AxisError::Drive)?;
        let pending = self.drive.pending();
        let settled = pending == 0;
        if settled && self.home != HomeState::BackingOff {
            self.note_low();
        }
        if self.home == HomeState::Idle {
            if !self.referenced {
                // Without a reference the count only bounds the moves:
                // each attempt counts from where it starts, so that
                // attempts repeated for days (a switch stuck open at a
                // hard stop) never run the count out of its 32 bits. The
                // lowest point of homing moves with it.
                let shift = self.position_counts;
                self.position_counts = 0;
                self.homing_low_counts = self.homing_low_counts.map(|l| sat_sub(l, shift));
            }
            self.attempt_start_counts = self.position_counts;
            self.fine = false;
            self.homing_last_ms = None;
            self.note_low();
            if self.geo.turn_counts != 0 {
                self.drive.switch_stops(true);
            }
            // Approach the switch from the open side: a switch already
            // closed (or stuck) is first backed away from.
            self.home = if closed {
                HomeState::BackingOff
            } else {
                HomeState::Seeking
            };
        }
        // Each branch ends in the move it asks for, `want` counts at most
        // `room` in its direction; the move itself is written once below.
        let (state, want, room) = if self.home == HomeState::BackingOff {
            if !closed {
                self.stop()?;
                self.home = HomeState::Seeking;
                return Ok(HomeState::Seeking);
            }
            // Still running down (the tail of a ramped stop): wait.
            if pending < 0 {
                return Ok(HomeState::BackingOff);
            }
            let room = self.backoff_room_counts();
            if room <= 0 {
                if !settled {
                    return Ok(HomeState::BackingOff);
                }
                self.home = HomeState::Idle;
                return Err(AxisError::HomeNotFound);
            }
            let want = sat_sub(self.homing_move_counts(chunk_deg, now_ms), pending);
            (HomeState::BackingOff, want, room)
        } else {
            if closed && !self.fine {
                self.stop()?;
                self.note_low();
                self.fine = true;
                self.home = HomeState::BackingOff;
                return Ok(HomeState::BackingOff);
            }
            if closed {
                self.stop()?;
                self.position_counts = 0;
                // Arrived moving negative: the gear's slack is taken up that way.
                self.last_dir = -1;
                self.referenced = true;
                self.homing_low_counts = None;
                self.homing_last_ms = None;
                self.home = HomeState::Done;
                if self.geo.turn_counts != 0 {
                    // Passed once a turn from now on.
                    self.drive.switch_stops(false);
                }
                return Ok(HomeState::Done);
            }
            // Still running up (the tail of a ramped stop): wait.
            if pending > 0 {
                return Ok(HomeState::Seeking);
            }
            let room = self.seek_room_counts();
            if room <= 0 {
                if !settled {
                    return Ok(HomeState::Seeking); // the last moves still run
                }
                // A referenced axis that reaches its floor without closing the
                // switch was not where it counted (steps lost while stalled):
                // the count is no reference any more, and the next attempt runs
                // the whole travel instead of stopping at the same wrong floor
                // for ever.
                self.referenced = false;
                self.home = HomeState::Idle;
                return Err(AxisError::HomeNotFound);
            }
            // `pending` ≤ 0 here: what is queued downward.
            let want = sat_add(self.homing_move_counts(chunk_deg, now_ms), pending);
            (HomeState::Seeking, want, room)
        };
        if want > 0 {
            // Backing off moves up, seeking down; 0 < `room` here.
            let up = state == HomeState::BackingOff;
            let counts = want.min(room);
            let c = self.command(if up { counts } else { -counts })?;
            self.position_counts = sat_add(self.position_counts, c);
            self.last_dir = if up { 1 } else { -1 };
        }
        Ok(state)
    }

    /// Moves toward `target_deg` (clamped to the soft limits) and, per
    /// `mode`, uses `feedback_deg` (the axis angle from an encoder or from
    /// attitude sensors). Feedback more than [`FEEDBACK_MARGIN_DEG`]
    /// outside the soft limits is clamped before the count is re-anchored
    /// on it; the reported deviation uses it as given.
    pub fn update(
        &mut self,
        target_deg: f32,
        mode: FeedbackMode,
        feedback_deg: Option<f32>,
    ) -> Result<AxisReport, AxisError<D::Error>> {
        if self.home != HomeState::Done {
            return Err(AxisError::NotHomed);
        }
        if !target_deg.is_finite() || feedback_deg.is_some_and(|f| !f.is_finite()) {
            return Err(AxisError::NotFinite);
        }
        let g = self.geo;
        let t = g.limit(target_deg);
        let clamped = t != target_deg;
        let deviation = feedback_deg.map(|f| f - t);
        let goal_counts = g.counts(t - g.home_deg);
        if let (FeedbackMode::ClosedLoop, Some(fb)) = (mode, feedback_deg) {
            // A drive that closes its own loop (a DC motor on its Hall
            // count) still running to this same goal finishes the move:
            // dropped and commanded again, a swing longer than a tick was
            // braked and started again at every tick.
            let finishing = goal_counts == self.position_counts
                && self.drive.pending() != 0
                && self.drive.self_watched();
            if (t - fb).abs() > g.deadband_deg && !finishing {
                // Re-anchor the count on the measurement and correct; a
                // move still under way is dropped first, or its counts
                // would be commanded twice.
                if self.drive.pending() != 0 {
                    self.drive.stop().map_err(AxisError::Drive)?;
                } else {
                    self.drive.rebase_at_rest();
                }
                self.reanchor(fb);
            } else {
                // Inside the deadband, or finishing: trust the counted
                // position.
                return Ok(AxisReport {
                    target_deg: t,
                    clamped,
                    commanded_counts: 0,
                    deviation_deg: deviation,
                });
            }
        }
        let commanded = self.move_counted_to(goal_counts)?;
        Ok(AxisReport {
            target_deg: t,
            clamped,
            commanded_counts: commanded,
            deviation_deg: deviation,
        })
    }

    /// Moves toward `target_deg` (clamped to the soft limits) on the
    /// counted position alone: [`AxisController::update`] in
    /// [`FeedbackMode::OpenLoop`] without its report, for a drive that
    /// closes the loop on its own encoder (the Uno's servo axes).
    pub fn move_to(&mut self, target_deg: f32) -> Result<(), AxisError<D::Error>> {
        if self.home != HomeState::Done {
            return Err(AxisError::NotHomed);
        }
        if !target_deg.is_finite() {
            return Err(AxisError::NotFinite);
        }
        let g = &self.geo;
        let goal_counts = g.counts(g.limit(target_deg) - g.home_deg);
        self.move_counted_to(goal_counts).map(|_| ())
    }

    /// Moves `deg` from the counted position whether or not the axis is
    /// homed (an operator's jog of an axis with no reference), at most the
    /// span of the soft limits either way; the soft limits themselves are
    /// not applied (without a reference the count does not say where they
    /// are).
    pub fn nudge(&mut self, deg: f32) -> Result<(), AxisError<D::Error>> {
        if !deg.is_finite() {
            return Err(AxisError::NotFinite);
        }
        let g = self.geo;
        let span = g.max_deg - g.min_deg;
        let c = g.counts(within(deg, -span, span));
        self.move_counted_to(sat_add(self.position_counts, c))
            .map(|_| ())
    }

    /// Commands the move from the counted position to `goal_counts`, the
    /// slack taken up first on a reversal (`backlash_deg`), and counts it;
    /// returns the counts commanded.
    fn move_counted_to(&mut self, goal_counts: i32) -> Result<i32, AxisError<D::Error>> {
        let g = self.geo;
        let delta = sat_sub(goal_counts, self.position_counts);
        let mut commanded = 0;
        if delta != 0 {
            let dir: i8 = if delta > 0 { 1 } else { -1 };
            // Backlash compensation: on reversal, take up the slack first.
            let take_up = if self.last_dir != 0 && dir != self.last_dir {
                // ≥ 0 (backlash ≥ 0) and ≤ 5 × 10^6: negation is exact.
                let slack = g.counts(g.backlash_deg);
                if dir > 0 {
                    slack
                } else {
                    -slack
                }
            } else {
                0
            };
            commanded = self.command(sat_add(delta, take_up))?;
            // The take-up only closes the slack; the rest moves the axis.
            // Equal to `goal_counts` unless the command was clamped.
            let moved = sat_sub(commanded, take_up);
            self.position_counts = sat_add(self.position_counts, moved);
            self.last_dir = dir;
        }
        Ok(commanded)
    }
}
