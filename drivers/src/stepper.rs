//! Stepper motors, non-blocking: one `poll(now_us)` per main-loop pass per axis.
//!
//! * [`hbridge`]: a bipolar stepper driven through an H-bridge from four
//!   `OutputPin`s (Li et al. 2022: two bipolar steppers behind optocouplers
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
//!
//! The examples drive `embedded-hal-mock` pins; the expected pin levels
//! come from each driver's coil table or chip timing (module docs).

pub mod hbridge;
pub mod planner;
pub mod ramp;
pub mod step_dir;

/// `a + b` in steps, saturated at the ends of the i32 range
/// (`i32::saturating_add`); positions and targets never wrap.
// Out of line on the AVR: a saturating 32-bit add written out is some 40
// bytes on an 8-bit CPU, a call a third of that, and the planner and the
// tracker's axis code use it in many places.
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn sat_add(a: i32, b: i32) -> i32 {
    a.saturating_add(b)
}

/// `a - b` in steps, saturated at the ends of the i32 range
/// (`i32::saturating_sub`).
// Out of line on the AVR, as `sat_add`.
#[cfg_attr(target_arch = "avr", inline(never))]
pub fn sat_sub(a: i32, b: i32) -> i32 {
    a.saturating_sub(b)
}

/// Direction of rotation, counted in the position as +1 / −1 step.
///
/// ```
/// use drivers::stepper::planner::{Due, Planner};
/// use drivers::stepper::ramp::Ramp;
/// use drivers::stepper::Direction;
///
/// let mut p = Planner::new(Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 })?;
/// p.move_to(-3);
/// assert_eq!(p.due(0), Due::Step(Direction::Backward));
/// # Ok::<(), drivers::stepper::ramp::RampError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Direction {
    /// Position increases.
    Forward,
    /// Position decreases.
    Backward,
}

/// Which end-of-travel switch.
///
/// ```
/// use drivers::stepper::{Direction, Limit};
///
/// // The switch that stops a direction of travel.
/// let guard = |d: Direction| match d {
///     Direction::Forward => Limit::Max,
///     Direction::Backward => Limit::Min,
/// };
/// assert_eq!(guard(Direction::Backward), Limit::Min);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Limit {
    /// The switch at the low end (stops `Backward` motion).
    Min,
    /// The switch at the high end (stops `Forward` motion).
    Max,
}

/// What one call to `poll` did.
///
/// ```
/// use drivers::stepper::Event;
///
/// // A main loop keeps polling while the axis is busy.
/// let busy = |e: Event| matches!(e, Event::Waiting | Event::Stepped);
/// assert!(busy(Event::Stepped) && !busy(Event::Arrived) && !busy(Event::Idle));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
///
/// ```
/// use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
/// use drivers::stepper::ramp::{Ramp, RampError};
/// use drivers::stepper::{Error, LimitSwitches};
/// use embedded_hal_mock::eh1::digital::Mock as Pin;
///
/// // A start speed above the cruise speed is refused before any pin is used.
/// let ramp = Ramp { start_speed_sps: 500, max_speed_sps: 400, accel_sps2: 1_000 };
/// let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
/// let mut pins = [Pin::new(&[]), Pin::new(&[]), Pin::new(&[]), Pin::new(&[])];
/// let [in1, in2, in3, in4] = pins.clone();
/// let bridge = BridgePins { in1, in2, in3, in4 };
/// let e = HBridgeStepper::new(bridge, LimitSwitches::<Pin>::none(), config).unwrap_err();
/// assert_eq!(e, Error::InvalidConfig(RampError::StartAboveMax));
/// assert_eq!(e.to_string(), "unusable stepper configuration: start speed above maximum speed");
/// pins.iter_mut().for_each(Pin::done); // no pin was touched
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
///
/// ```
/// use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
/// use drivers::stepper::ramp::Ramp;
/// use drivers::stepper::{Event, Limit, LimitSwitches};
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
///
/// // A switch to ground with a pull-up at the high end reads low when
/// // pressed: the forward step is not taken, and the coils are released
/// // (all four bridge inputs low).
/// let mut max = Pin::new(&[T::get(State::Low)]);
/// let limits = LimitSwitches { min: None, max: Some(max.clone()), active_low: true };
/// let low = [T::set(State::Low)];
/// let (mut in1, mut in2, mut in3, mut in4) =
///     (Pin::new(&low), Pin::new(&low), Pin::new(&low), Pin::new(&low));
/// let pins = BridgePins { in1: in1.clone(), in2: in2.clone(), in3: in3.clone(), in4: in4.clone() };
/// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
/// let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
/// let mut motor = HBridgeStepper::new(pins, limits, config)?;
/// motor.move_to(10);
/// assert_eq!(motor.poll(0)?, Event::LimitReached(Limit::Max));
/// assert_eq!((motor.position(), motor.target()), (0, 0));
/// for pin in [&mut in1, &mut in2, &mut in3, &mut in4, &mut max] {
///     pin.done();
/// }
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
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
    ///
    /// ```
    /// use drivers::stepper::LimitSwitches;
    /// use embedded_hal_mock::eh1::digital::Mock as Pin;
    ///
    /// let none = LimitSwitches::<Pin>::none();
    /// assert!(none.min.is_none() && none.max.is_none());
    /// ```
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

#[cfg(test)]
mod sat_tests {
    use super::{sat_add, sat_sub};

    #[test]
    fn saturating_helpers_stop_at_the_ends_of_the_i32_range() {
        assert_eq!(sat_add(2, 3), 5);
        assert_eq!(sat_add(-7, 3), -4);
        assert_eq!(sat_add(i32::MAX, 1), i32::MAX);
        assert_eq!(sat_add(i32::MIN, -1), i32::MIN);
        assert_eq!(sat_sub(2, 3), -1);
        assert_eq!(sat_sub(i32::MIN, 1), i32::MIN);
        assert_eq!(sat_sub(0, i32::MIN), i32::MAX);
        assert_eq!(sat_sub(-1, i32::MIN), i32::MAX);
        assert_eq!(sat_sub(-2, i32::MAX), i32::MIN);
    }
}
