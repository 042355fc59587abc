//! Position, target and step timing shared by the stepper drivers.
//!
//! The planner knows nothing about pins: `next(now_us)` says whether a step is
//! due and in which direction; the driver then checks its limit switch, moves
//! the coils or pulses STEP, and calls `stepped(now_us)`.
//!
//! The intervals in the examples are the ramp's `10⁶ / √(v₀² + 2·a·k)` µs
//! evaluated independently (Python): 10 000, 5 780, 4 484 µs for k = 0, 1,
//! 2 with v₀ = 100 steps/s and a = 10 000 steps/s².

use super::ramp::{Ramp, RampError};
use super::{sat_add, sat_sub, Direction};

/// What the planner wants at `now_us`.
///
/// ```
/// use drivers::stepper::planner::{Due, Planner};
/// use drivers::stepper::ramp::Ramp;
/// use drivers::stepper::Direction;
///
/// let mut p = Planner::new(Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 })?;
/// assert_eq!(p.due(0), Due::Idle);
/// p.move_to(2);
/// assert_eq!(p.due(0), Due::Step(Direction::Forward));
/// p.stepped(0);
/// assert_eq!(p.due(1), Due::Wait);
/// # Ok::<(), drivers::stepper::ramp::RampError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Due {
    /// Nothing to do: position == target.
    Idle,
    /// Moving, next step not due yet.
    Wait,
    /// Take one step in this direction now.
    Step(Direction),
}

/// Motion state of one axis.
///
/// ```
/// use drivers::stepper::planner::{Due, Planner};
/// use drivers::stepper::ramp::Ramp;
/// use drivers::stepper::Direction;
///
/// // A driver's loop without pins: step when due, report the step.
/// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
/// let mut p = Planner::new(ramp)?;
/// p.move_to(3);
/// let mut steps_at = Vec::new();
/// for now_us in (0..20_000).step_by(1) {
///     if let Due::Step(Direction::Forward) = p.due(now_us) {
///         steps_at.push(now_us);
///         if p.stepped(now_us) {
///             break;
///         }
///     }
/// }
/// // Intervals at levels 1 and 1 (one step from the nearer end each time).
/// assert_eq!(steps_at, [0, 5_780, 11_560]);
/// # Ok::<(), drivers::stepper::ramp::RampError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Planner {
    ramp: Ramp,
    position: i32,
    target: i32,
    /// Steps taken since the axis last stood still.
    steps_done: u32,
    /// Time the next step is due; `None` = immediately.
    next_due_us: Option<u64>,
    /// Direction of the current motion (meaningful while moving).
    dir: Direction,
    /// Ramp level used for the last interval (the stopping distance).
    level: u32,
    /// Target to go to once a reversal has come to rest.
    pending: Option<i32>,
    /// Level at which the ramp reaches cruise speed.
    cruise_level: u32,
}

impl Planner {
    /// A planner at position 0, standing still.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::{Ramp, RampError};
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// assert_eq!((p.position(), p.due(0)), (0, Due::Idle));
    /// let bad = Ramp { start_speed_sps: 0, ..ramp };
    /// assert_eq!(Planner::new(bad), Err(RampError::Zero));
    /// # Ok::<(), RampError>(())
    /// ```
    pub fn new(ramp: Ramp) -> Result<Self, RampError> {
        ramp.validate()?;
        Ok(Self {
            ramp,
            position: 0,
            target: 0,
            steps_done: 0,
            next_due_us: None,
            dir: Direction::Forward,
            level: 0,
            pending: None,
            // Validated above: the 32-bit computation.
            cruise_level: ramp.cruise_level_valid(),
        })
    }

    /// Current position, steps.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// p.move_to(-2);
    /// assert_eq!(p.due(0), Due::Step(Direction::Backward));
    /// p.stepped(0);
    /// assert_eq!(p.position(), -1);
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn position(&self) -> i32 {
        self.position
    }

    /// Current target, steps.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// p.move_to(100);
    /// p.due(0);
    /// p.stepped(0);
    /// // A reversal while moving: the planner first comes to rest (one more
    /// // step at ramp level 1), then heads for −5; `target` is the final one.
    /// p.move_to(-5);
    /// assert_eq!(p.target(), -5);
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn target(&self) -> i32 {
        self.pending.unwrap_or(self.target)
    }

    /// The ramp in use.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// assert_eq!(p.ramp(), ramp);
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn ramp(&self) -> Ramp {
        self.ramp
    }

    /// True while a move is under way.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// assert!(!p.is_moving());
    /// p.move_by(1);
    /// assert!(p.is_moving());
    /// p.due(0);
    /// assert!(p.stepped(0)); // that was the last step
    /// assert!(!p.is_moving());
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn is_moving(&self) -> bool {
        self.position != self.target || self.pending.is_some()
    }

    /// Redefines the current position (e.g. 0 after homing); only when idle.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// assert!(p.set_position(250));
    /// assert_eq!((p.position(), p.target()), (250, 250));
    /// p.move_to(0);
    /// assert!(!p.set_position(0));
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn set_position(&mut self, position: i32) -> bool {
        if self.is_moving() {
            return false;
        }
        self.position = position;
        self.target = position;
        true
    }

    /// Sets a new target. Same direction (or idle): the ramp adapts at once.
    /// Reversal while moving: decelerate to rest first, then go to `target`.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// p.move_to(100);
    /// assert_eq!(p.due(0), Due::Step(Direction::Forward));
    /// p.stepped(0);
    /// p.move_to(-1); // reverse: one more step forward to come to rest
    /// assert_eq!(p.due(5_780), Due::Step(Direction::Forward));
    /// p.stepped(5_780);
    /// assert_eq!(p.position(), 2);
    /// // Then backward, after the rest interval.
    /// assert_eq!(p.due(15_780), Due::Step(Direction::Backward));
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn move_to(&mut self, target: i32) {
        if !self.is_moving() {
            self.target = target;
            self.steps_done = 0;
            self.next_due_us = None;
            self.pending = None;
            return;
        }
        let ahead = match self.dir {
            Direction::Forward => target > self.position,
            Direction::Backward => target < self.position,
        };
        let stop_at = self.stop_position();
        let reachable = match self.dir {
            Direction::Forward => target >= stop_at,
            Direction::Backward => target <= stop_at,
        };
        if ahead && reachable {
            self.target = target;
            self.pending = None;
        } else {
            self.target = stop_at;
            self.pending = Some(target);
        }
    }

    /// Moves by `delta` steps relative to the current target.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// p.move_by(10);
    /// p.move_by(-3);
    /// assert_eq!(p.target(), 7);
    /// p.move_by(i32::MAX); // saturates
    /// assert_eq!(p.target(), i32::MAX);
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn move_by(&mut self, delta: i32) {
        self.move_to(sat_add(self.target(), delta));
    }

    /// Decelerates to rest along the ramp.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// p.move_to(1_000);
    /// for now_us in [0, 5_780, 10_264] {
    ///     // Intervals at levels 1 and 2: 5 780 and 4 484 µs.
    ///     assert_eq!(p.due(now_us), Due::Step(Direction::Forward));
    ///     p.stepped(now_us);
    /// }
    /// p.stop(); // level 3: three more steps to come to rest
    /// assert_eq!(p.target(), 6);
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn stop(&mut self) {
        if self.position != self.target {
            self.target = self.stop_position();
        }
        self.pending = None;
    }

    /// Drops the motion at once (limit switch): target = position.
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// p.move_to(1_000);
    /// p.due(0);
    /// p.stepped(0);
    /// p.halt();
    /// assert_eq!((p.position(), p.target(), p.is_moving()), (1, 1, false));
    /// assert_eq!(p.due(1), Due::Idle);
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn halt(&mut self) {
        self.target = self.position;
        self.pending = None;
        self.steps_done = 0;
        self.next_due_us = None;
    }

    fn stop_position(&self) -> i32 {
        let d = i32::try_from(self.level).unwrap_or(i32::MAX);
        match self.dir {
            Direction::Forward => sat_add(self.position, d).min(self.target),
            Direction::Backward => sat_sub(self.position, d).max(self.target),
        }
    }

    /// Is a step due at `now_us`?
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// assert_eq!(p.due(0), Due::Idle);
    /// p.move_to(2);
    /// assert_eq!(p.due(0), Due::Step(Direction::Forward));
    /// p.stepped(0);
    /// assert_eq!(p.due(5_779), Due::Wait);
    /// assert_eq!(p.due(5_780), Due::Step(Direction::Forward));
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn due(&mut self, now_us: u64) -> Due {
        if self.position == self.target {
            match self.pending.take() {
                Some(t) => {
                    self.target = t;
                    self.steps_done = 0;
                    // next_due_us kept: the rest interval before reversing.
                }
                None => return Due::Idle,
            }
            if self.position == self.target {
                return Due::Idle;
            }
        }
        if let Some(t) = self.next_due_us {
            if now_us < t {
                return Due::Wait;
            }
        }
        self.dir = if self.target > self.position {
            Direction::Forward
        } else {
            Direction::Backward
        };
        Due::Step(self.dir)
    }

    /// Records a step taken at `now_us` and schedules the next one. Returns
    /// true when this step reached the final target (no reversal pending).
    ///
    /// ```
    /// use drivers::stepper::planner::{Due, Planner};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::Direction;
    ///
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let mut p = Planner::new(ramp)?;
    /// p.move_to(3);
    /// p.due(0);
    /// assert!(!p.stepped(0)); // next due 5 780 µs later (level 1)
    /// assert_eq!(p.due(5_780), Due::Step(Direction::Forward));
    /// assert!(!p.stepped(5_780)); // level min(2, 1) = 1 again
    /// assert_eq!(p.due(11_560), Due::Step(Direction::Forward));
    /// assert!(p.stepped(11_560));
    /// # Ok::<(), drivers::stepper::ramp::RampError>(())
    /// ```
    pub fn stepped(&mut self, now_us: u64) -> bool {
        let step = match self.dir {
            Direction::Forward => 1,
            Direction::Backward => -1,
        };
        self.position = sat_add(self.position, step);
        self.steps_done = self.steps_done.saturating_add(1);
        let to_go = self.target.abs_diff(self.position);
        self.level = self.steps_done.min(to_go).min(self.cruise_level);
        let interval = u64::from(self.ramp.interval_us(self.level));
        self.next_due_us = Some(now_us.saturating_add(interval));
        if to_go == 0 {
            self.steps_done = 0;
            self.level = 0;
            if self.pending.is_none() {
                self.next_due_us = None;
                return true;
            }
        }
        false
    }
}
