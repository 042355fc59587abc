//! Position, target and step timing shared by the stepper drivers.
//!
//! The planner knows nothing about pins: `next(now_us)` says whether a step is
//! due and in which direction; the driver then checks its limit switch, moves
//! the coils or pulses STEP, and calls `stepped(now_us)`.

use super::ramp::{Ramp, RampError};
use super::Direction;

/// What the planner wants at `now_us`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Due {
    /// Nothing to do: position == target.
    Idle,
    /// Moving, next step not due yet.
    Wait,
    /// Take one step in this direction now.
    Step(Direction),
}

/// Motion state of one axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
            cruise_level: ramp.cruise_level(),
        })
    }

    /// Current position, steps.
    pub fn position(&self) -> i32 {
        self.position
    }

    /// Current target, steps.
    pub fn target(&self) -> i32 {
        self.pending.unwrap_or(self.target)
    }

    /// The ramp in use.
    pub fn ramp(&self) -> Ramp {
        self.ramp
    }

    /// True while a move is under way.
    pub fn is_moving(&self) -> bool {
        self.position != self.target || self.pending.is_some()
    }

    /// Redefines the current position (e.g. 0 after homing); only when idle.
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
    pub fn move_by(&mut self, delta: i32) {
        self.move_to(self.target().saturating_add(delta));
    }

    /// Decelerates to rest along the ramp.
    pub fn stop(&mut self) {
        if self.position != self.target {
            self.target = self.stop_position();
        }
        self.pending = None;
    }

    /// Drops the motion at once (limit switch): target = position.
    pub fn halt(&mut self) {
        self.target = self.position;
        self.pending = None;
        self.steps_done = 0;
        self.next_due_us = None;
    }

    fn stop_position(&self) -> i32 {
        let d = i32::try_from(self.level).unwrap_or(i32::MAX);
        match self.dir {
            Direction::Forward => self.position.saturating_add(d).min(self.target),
            Direction::Backward => self.position.saturating_sub(d).max(self.target),
        }
    }

    /// Is a step due at `now_us`?
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
    pub fn stepped(&mut self, now_us: u64) -> bool {
        self.position = match self.dir {
            Direction::Forward => self.position.saturating_add(1),
            Direction::Backward => self.position.saturating_sub(1),
        };
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
