//! Stepper motors, non-blocking: one `poll(now_us)` per main-loop pass per axis.
//!
//! * [`hbridge`]: a bipolar stepper driven through an H-bridge from four
//!   `OutputPin`s (seed *li-2022*: two bipolar steppers behind optocouplers
//!   and an H-bridge). Wave, full-step and half-step sequences; coils released
//!   when idle.
//! * [`step_dir`]: STEP/DIR(/ENABLE) driver chips of the A4988 / DRV8825 class.
//! * [`ramp`]: trapezoidal speed profile, the step interval computed per step in
//!   integer microseconds.
//! * [`planner`]: position in steps, target, timing and limit-switch logic shared
//!   by both drivers.
//!
//! Both drivers take limit switches as `InputPin`s; a switch that is active in
//! the direction of travel stops the motion before the step and is reported as
//! [`Event::LimitReached`].

pub mod hbridge;
pub mod planner;
pub mod ramp;
pub mod step_dir;

/// Direction of rotation, counted in the position as +1 / −1 step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Position increases.
    Forward,
    /// Position decreases.
    Backward,
}

/// Which end-of-travel switch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// The switch at the low end (stops `Backward` motion).
    Min,
    /// The switch at the high end (stops `Forward` motion).
    Max,
}

/// What one call to `poll` did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// No motion requested (coils may have been released in this call).
    Idle,
    /// Moving; the next step is not due yet.
    Waiting,
    /// One step was taken; more follow.
    Stepped,
    /// The last step of the move was taken: position == target.
    Arrived,
    /// A limit switch in the direction of travel is active: motion stopped
    /// without stepping, target reset to the current position, coils released.
    LimitReached(Limit),
}

/// Driver errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error<E> {
    /// A pin operation failed.
    Comm(E),
    /// The ramp or timing configuration is unusable (see [`ramp::RampError`]).
    InvalidConfig(ramp::RampError),
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "stepper pin error: {e:?}"),
            Error::InvalidConfig(r) => write!(f, "unusable stepper configuration: {r}"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

/// Limit-switch inputs; either may be absent.
#[derive(Debug)]
pub struct LimitSwitches<L> {
    /// Switch at the low end.
    pub min: Option<L>,
    /// Switch at the high end.
    pub max: Option<L>,
    /// True when a pressed switch reads low (switch to ground with pull-up).
    pub active_low: bool,
}

impl<L> LimitSwitches<L> {
    /// No switches.
    pub fn none() -> Self {
        Self {
            min: None,
            max: None,
            active_low: true,
        }
    }
}

impl<L: embedded_hal::digital::InputPin> LimitSwitches<L> {
    /// Reads the switch that guards motion in `dir`; `Ok(None)` when inactive or absent.
    pub(crate) fn blocking(&mut self, dir: Direction) -> Result<Option<Limit>, L::Error> {
        let (pin, which) = match dir {
            Direction::Forward => (self.max.as_mut(), Limit::Max),
            Direction::Backward => (self.min.as_mut(), Limit::Min),
        };
        match pin {
            None => Ok(None),
            Some(p) => {
                let high = p.is_high()?;
                Ok((high != self.active_low).then_some(which))
            }
        }
    }
}
