//! Bipolar stepper through an H-bridge (L298N class, or discrete bridges behind
//! optocouplers as in Li et al. 2022), four `OutputPin`s.
//!
//! Pins: `IN1` = coil A+, `IN2` = coil A−, `IN3` = coil B+, `IN4` = coil B−
//! (a high input drives that coil end high). Coil table, half-step phase 0..7
//! (1 = high), forward = increasing phase:
//!
//! | phase | IN1 IN2 IN3 IN4 | coils       | used by      |
//! |-------|-----------------|-------------|--------------|
//! | 0     | 1 0 0 0         | A+          | wave, half   |
//! | 1     | 1 0 1 0         | A+ B+       | full, half   |
//! | 2     | 0 0 1 0         | B+          | wave, half   |
//! | 3     | 0 1 1 0         | A− B+       | full, half   |
//! | 4     | 0 1 0 0         | A−          | wave, half   |
//! | 5     | 0 1 0 1         | A− B−       | full, half   |
//! | 6     | 0 0 0 1         | B−          | wave, half   |
//! | 7     | 1 0 0 1         | A+ B−       | full, half   |
//!
//! Wave drive (one phase on) uses the even phases, full step (two phases on,
//! full torque) the odd ones, half step all eight; wave and full steps move
//! two phases per step. Every step writes all four pins, the ones going low
//! first and then the ones going high (break before make, so no bridge leg is
//! ever commanded high on both sides). Releasing the coils sets all four low:
//! no holding current while idle (e.g. all night).

use embedded_hal::digital::{InputPin, OutputPin};

use super::planner::{Due, Planner};
use super::ramp::Ramp;
use super::{Direction, Error, Event, LimitSwitches};

/// Half-step coil table, `[IN1, IN2, IN3, IN4]`.
const PHASES: [[bool; 4]; 8] = [
    [true, false, false, false],
    [true, false, true, false],
    [false, false, true, false],
    [false, true, true, false],
    [false, true, false, false],
    [false, true, false, true],
    [false, false, false, true],
    [true, false, false, true],
];

/// Drive sequence.
///
/// ```
/// use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
/// use drivers::stepper::ramp::Ramp;
/// use drivers::stepper::LimitSwitches;
/// use embedded_hal_mock::eh1::digital::Mock as Pin;
///
/// // Each mode starts from its first phase of the coil table: wave and half
/// // step from 0 (A+), full step from 1 (A+ B+).
/// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
/// for (mode, phase) in [(StepMode::Wave, 0), (StepMode::Full, 1), (StepMode::Half, 0)] {
///     let pins = BridgePins { in1: Pin::new(&[]), in2: Pin::new(&[]), in3: Pin::new(&[]), in4: Pin::new(&[]) };
///     let config = Config { mode, ramp, settle_us: 0, release_when_idle: true };
///     let motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
///     assert_eq!(motor.phase(), phase);
///     let (pins, _) = motor.destroy();
///     for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] {
///         p.done();
///     }
/// }
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StepMode {
    /// One coil at a time (even phases), least current.
    Wave,
    /// Two coils at a time (odd phases), full torque.
    Full,
    /// Alternating one and two coils, twice the resolution.
    Half,
}

impl StepMode {
    fn phase_increment(self) -> u8 {
        match self {
            StepMode::Half => 1,
            StepMode::Wave | StepMode::Full => 2,
        }
    }

    fn first_phase(self) -> u8 {
        match self {
            StepMode::Full => 1,
            StepMode::Wave | StepMode::Half => 0,
        }
    }
}

/// Configuration of an H-bridge stepper.
///
/// ```
/// use drivers::stepper::hbridge::{Config, StepMode};
/// use drivers::stepper::ramp::Ramp;
///
/// // Half steps, coils held 50 ms after each move, then released.
/// let config = Config {
///     mode: StepMode::Half,
///     ramp: Ramp { start_speed_sps: 50, max_speed_sps: 400, accel_sps2: 800 },
///     settle_us: 50_000,
///     release_when_idle: true,
/// };
/// assert_eq!(config.ramp.cruise_level(), 99); // ⌈(400² − 50²) / (2 · 800)⌉ = ⌈98.4⌉
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Drive sequence.
    pub mode: StepMode,
    /// Speed profile (in steps of `mode`).
    pub ramp: Ramp,
    /// Keep the coils energised this long after the last step before releasing
    /// them (lets the rotor settle); 0 = release in the same `poll`.
    pub settle_us: u32,
    /// Release the coils when idle (no holding current).
    pub release_when_idle: bool,
}

/// The four bridge inputs.
///
/// ```
/// use drivers::stepper::hbridge::BridgePins;
/// use embedded_hal_mock::eh1::digital::Mock as Pin;
///
/// // IN1/IN2 drive coil A, IN3/IN4 coil B (L298N-class bridge).
/// let pins = BridgePins { in1: Pin::new(&[]), in2: Pin::new(&[]), in3: Pin::new(&[]), in4: Pin::new(&[]) };
/// for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] {
///     p.done();
/// }
/// ```
#[derive(Debug)]
pub struct BridgePins<P> {
    /// IN1, coil A+.
    pub in1: P,
    /// IN2, coil A−.
    pub in2: P,
    /// IN3, coil B+.
    pub in3: P,
    /// IN4, coil B−.
    pub in4: P,
}

/// A bipolar stepper behind an H-bridge.
///
/// ```
/// use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
/// use drivers::stepper::ramp::Ramp;
/// use drivers::stepper::{Event, LimitSwitches};
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
///
/// // Half steps from phase 0 (IN1..IN4 = 1000) to phase 1 (1010), by the
/// // coil table above: IN1 stays high, IN2 and IN4 are written low first,
/// // then IN3 high (break before make). Then the coils are released.
/// let (h, l) = (T::set(State::High), T::set(State::Low));
/// let pins = BridgePins {
///     in1: Pin::new(&[h.clone(), l.clone()]),
///     in2: Pin::new(&[l.clone(), l.clone()]),
///     in3: Pin::new(&[h.clone(), l.clone()]),
///     in4: Pin::new(&[l.clone(), l.clone()]),
/// };
/// let ramp = Ramp { start_speed_sps: 50, max_speed_sps: 200, accel_sps2: 400 };
/// let config = Config { mode: StepMode::Half, ramp, settle_us: 0, release_when_idle: true };
/// let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
/// motor.move_to(1);
/// assert_eq!(motor.poll(0)?, Event::Arrived);
/// assert_eq!((motor.position(), motor.phase(), motor.is_energised()), (1, 1, false));
/// let (pins, _) = motor.destroy();
/// for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] {
///     p.done();
/// }
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
//
// Fields in this order on the AVR (`repr(C)` there): the small per-step
// state first, within the 63 bytes an AVR `ldd`/`std` reaches past the
// pointer, then the planner, configuration and pins. Elsewhere the
// compiler's order (no padding).
#[derive(Debug)]
#[cfg_attr(target_arch = "avr", repr(C))]
pub struct HBridgeStepper<P, L> {
    phase: u8,
    energised: bool,
    /// The coils have been energised at `phase` since power-on: the rotor
    /// rests there (before that its phase is unknown).
    rotor_at_phase: bool,
    /// The `min` switch does not stop motion toward it (see
    /// [`HBridgeStepper::set_min_limit`]).
    min_limit_off: bool,
    release_at_us: Option<u64>,
    planner: Planner,
    config: Config,
    pins: BridgePins<P>,
    limits: LimitSwitches<L>,
}

impl<P, L, E> HBridgeStepper<P, L>
where
    P: OutputPin<Error = E>,
    L: InputPin<Error = E>,
{
    /// Creates the driver at position 0 with the coils off. No pin is touched
    /// until the first `poll` or `release`.
    ///
    /// ```
    /// use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::LimitSwitches;
    /// use embedded_hal_mock::eh1::digital::Mock as Pin;
    ///
    /// // No pin transactions expected.
    /// let pins = BridgePins { in1: Pin::new(&[]), in2: Pin::new(&[]), in3: Pin::new(&[]), in4: Pin::new(&[]) };
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let config = Config { mode: StepMode::Wave, ramp, settle_us: 20_000, release_when_idle: true };
    /// let motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// assert_eq!((motor.position(), motor.phase(), motor.is_energised()), (0, 0, false));
    /// let (pins, _) = motor.destroy();
    /// for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] {
    ///     p.done();
    /// }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn new(
        pins: BridgePins<P>,
        limits: LimitSwitches<L>,
        config: Config,
    ) -> Result<Self, Error<E>> {
        let planner = Planner::new(config.ramp).map_err(Error::InvalidConfig)?;
        Ok(Self {
            pins,
            limits,
            planner,
            config,
            phase: config.mode.first_phase(),
            energised: false,
            rotor_at_phase: false,
            release_at_us: None,
            min_limit_off: false,
        })
    }

    /// Whether the `min` switch stops motion toward it: on from
    /// [`HBridgeStepper::new`]. Off for an axis that turns without end,
    /// whose home switch is an index it passes once a turn: its owner
    /// turns it on for homing only. The `max` switch always stops.
    pub fn set_min_limit(&mut self, on: bool) {
        self.min_limit_off = !on;
    }

    /// Gives the pins back.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # let pins = BridgePins { in1: Pin::new(&[]), in2: Pin::new(&[]), in3: Pin::new(&[]), in4: Pin::new(&[]) };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// let (pins, limits) = motor.destroy();
    /// assert!(limits.min.is_none() && limits.max.is_none());
    /// let mut motor = HBridgeStepper::new(pins, limits, config)?; // e.g. after a reconfiguration
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> (BridgePins<P>, LimitSwitches<L>) {
        (self.pins, self.limits)
    }

    /// Position in steps of the configured mode.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # // Full steps from phase 1 (IN1..IN4 = 1010) to 3 (0110) and 5 (0101),
    /// # // then released (0000): the coil table of the module docs.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = BridgePins {
    /// #     in1: Pin::new(&[l.clone(), l.clone(), l.clone()]),
    /// #     in2: Pin::new(&[h.clone(), h.clone(), l.clone()]),
    /// #     in3: Pin::new(&[h.clone(), l.clone(), l.clone()]),
    /// #     in4: Pin::new(&[l.clone(), h.clone(), l.clone()]),
    /// # };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// motor.move_to(2);
    /// motor.poll(0)?;
    /// assert_eq!(motor.position(), 1);
    /// motor.poll(5_780)?; // 10⁶ / √(100² + 2·10 000·1) µs later
    /// assert_eq!(motor.position(), 2);
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn position(&self) -> i32 {
        self.planner.position()
    }

    /// Target in steps.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # let pins = BridgePins { in1: Pin::new(&[]), in2: Pin::new(&[]), in3: Pin::new(&[]), in4: Pin::new(&[]) };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// motor.move_to(-40);
    /// assert_eq!(motor.target(), -40);
    /// motor.move_by(15);
    /// assert_eq!(motor.target(), -25);
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn target(&self) -> i32 {
        self.planner.target()
    }

    /// True while moving.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # // Full steps from phase 1 (IN1..IN4 = 1010) to 3 (0110) and 5 (0101),
    /// # // then released (0000): the coil table of the module docs.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = BridgePins {
    /// #     in1: Pin::new(&[l.clone(), l.clone(), l.clone()]),
    /// #     in2: Pin::new(&[h.clone(), h.clone(), l.clone()]),
    /// #     in3: Pin::new(&[h.clone(), l.clone(), l.clone()]),
    /// #     in4: Pin::new(&[l.clone(), h.clone(), l.clone()]),
    /// # };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// assert!(!motor.is_moving());
    /// motor.move_to(2);
    /// assert!(motor.is_moving());
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// assert!(!motor.is_moving());
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn is_moving(&self) -> bool {
        self.planner.is_moving()
    }

    /// True while the coils carry current.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # // Full steps from phase 1 (IN1..IN4 = 1010) to 3 (0110) and 5 (0101),
    /// # // then released (0000): the coil table of the module docs.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = BridgePins {
    /// #     in1: Pin::new(&[l.clone(), l.clone(), l.clone()]),
    /// #     in2: Pin::new(&[h.clone(), h.clone(), l.clone()]),
    /// #     in3: Pin::new(&[h.clone(), l.clone(), l.clone()]),
    /// #     in4: Pin::new(&[l.clone(), h.clone(), l.clone()]),
    /// # };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// motor.move_to(2);
    /// motor.poll(0)?;
    /// assert!(motor.is_energised());
    /// motor.poll(5_780)?; // arrived; released at once (settle_us = 0)
    /// assert!(!motor.is_energised());
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn is_energised(&self) -> bool {
        self.energised
    }

    /// Current half-step phase 0..7 (the row of the coil table).
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # // Full steps from phase 1 (IN1..IN4 = 1010) to 3 (0110) and 5 (0101),
    /// # // then released (0000): the coil table of the module docs.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = BridgePins {
    /// #     in1: Pin::new(&[l.clone(), l.clone(), l.clone()]),
    /// #     in2: Pin::new(&[h.clone(), h.clone(), l.clone()]),
    /// #     in3: Pin::new(&[h.clone(), l.clone(), l.clone()]),
    /// #     in4: Pin::new(&[l.clone(), h.clone(), l.clone()]),
    /// # };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// assert_eq!(motor.phase(), 1); // full steps use the odd phases
    /// motor.move_to(2);
    /// motor.poll(0)?;
    /// assert_eq!(motor.phase(), 3);
    /// motor.poll(5_780)?;
    /// assert_eq!(motor.phase(), 5);
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn phase(&self) -> u8 {
        self.phase
    }

    /// Redefines the position (after homing); refused (false) while moving.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # let pins = BridgePins { in1: Pin::new(&[]), in2: Pin::new(&[]), in3: Pin::new(&[]), in4: Pin::new(&[]) };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// assert!(motor.set_position(1_000));
    /// assert_eq!((motor.position(), motor.target()), (1_000, 1_000));
    /// motor.move_to(0);
    /// assert!(!motor.set_position(0)); // moving
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_position(&mut self, position: i32) -> bool {
        self.planner.set_position(position)
    }

    /// Go to an absolute position.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # // Full steps from phase 1 (IN1..IN4 = 1010) to 3 (0110) and 5 (0101),
    /// # // then released (0000): the coil table of the module docs.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = BridgePins {
    /// #     in1: Pin::new(&[l.clone(), l.clone(), l.clone()]),
    /// #     in2: Pin::new(&[h.clone(), h.clone(), l.clone()]),
    /// #     in3: Pin::new(&[h.clone(), l.clone(), l.clone()]),
    /// #     in4: Pin::new(&[l.clone(), h.clone(), l.clone()]),
    /// # };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// motor.move_to(2);
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// assert_eq!(motor.poll(5_000)?, Event::Waiting); // next step due at 5 780 µs
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// assert_eq!(motor.poll(6_000)?, Event::Idle);
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn move_to(&mut self, target: i32) {
        self.release_at_us = None;
        self.planner.move_to(target);
    }

    /// Go by a relative number of steps.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # // Full steps from phase 1 (IN1..IN4 = 1010) to 3 (0110) and 5 (0101),
    /// # // then released (0000): the coil table of the module docs.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = BridgePins {
    /// #     in1: Pin::new(&[l.clone(), l.clone(), l.clone()]),
    /// #     in2: Pin::new(&[h.clone(), h.clone(), l.clone()]),
    /// #     in3: Pin::new(&[h.clone(), l.clone(), l.clone()]),
    /// #     in4: Pin::new(&[l.clone(), h.clone(), l.clone()]),
    /// # };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// motor.move_by(1);
    /// motor.move_by(1); // relative to the target, not the position
    /// assert_eq!(motor.target(), 2);
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn move_by(&mut self, delta: i32) {
        self.release_at_us = None;
        self.planner.move_by(delta);
    }

    /// Decelerate to rest along the ramp.
    ///
    /// ```
    /// # use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: true };
    /// # // Full steps from phase 1 (IN1..IN4 = 1010) to 3 (0110) and 5 (0101),
    /// # // then released (0000): the coil table of the module docs.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = BridgePins {
    /// #     in1: Pin::new(&[l.clone(), l.clone(), l.clone()]),
    /// #     in2: Pin::new(&[h.clone(), h.clone(), l.clone()]),
    /// #     in3: Pin::new(&[h.clone(), l.clone(), l.clone()]),
    /// #     in4: Pin::new(&[l.clone(), h.clone(), l.clone()]),
    /// # };
    /// # let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// motor.move_to(1_000);
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// // After one step the ramp is at level 1: one more step to come to rest.
    /// motor.stop();
    /// assert_eq!(motor.target(), 2);
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// # let (pins, _) = motor.destroy();
    /// # for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn stop(&mut self) {
        self.planner.stop();
    }

    /// Drive the state machine; call often (every main-loop pass).
    ///
    /// ```
    /// use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::{Event, LimitSwitches};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // Two full steps forward from phase 1 (IN1..IN4 = 1010) to phase 3
    /// // (0110) and phase 5 (0101), the coil table of the module docs, lows
    /// // written before highs; then the coils are released (0000) after a
    /// // 1 ms settling time.
    /// let (h, l) = (T::set(State::High), T::set(State::Low));
    /// let mut in1 = Pin::new(&[l.clone(), l.clone(), l.clone()]);
    /// let mut in2 = Pin::new(&[h.clone(), h.clone(), l.clone()]);
    /// let mut in3 = Pin::new(&[h.clone(), l.clone(), l.clone()]);
    /// let mut in4 = Pin::new(&[l.clone(), h.clone(), l.clone()]);
    /// let pins = BridgePins { in1: in1.clone(), in2: in2.clone(), in3: in3.clone(), in4: in4.clone() };
    /// // Intervals 10⁶ / √(100² + 2·10 000·k) µs (see `Ramp`): 5 780 µs at k = 1.
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let config = Config { mode: StepMode::Full, ramp, settle_us: 1_000, release_when_idle: true };
    /// let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// motor.move_to(2);
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// assert_eq!(motor.poll(5_779)?, Event::Waiting);
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// assert_eq!(motor.poll(6_000)?, Event::Idle); // still holding
    /// assert!(motor.is_energised());
    /// assert_eq!(motor.poll(6_780)?, Event::Idle); // released now
    /// assert!(!motor.is_energised());
    /// for pin in [&mut in1, &mut in2, &mut in3, &mut in4] {
    ///     pin.done();
    /// }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn poll(&mut self, now_us: u64) -> Result<Event, Error<E>> {
        match self.planner.due(now_us) {
            Due::Idle => {
                if let Some(t) = self.release_at_us {
                    if now_us >= t {
                        self.release()?;
                    }
                }
                Ok(Event::Idle)
            }
            Due::Wait => Ok(Event::Waiting),
            Due::Step(dir) => {
                let blocked = if dir == Direction::Backward && self.min_limit_off {
                    None
                } else {
                    self.limits.blocking(dir).map_err(Error::Comm)?
                };
                if let Some(limit) = blocked {
                    self.planner.halt();
                    self.release()?;
                    return Ok(Event::LimitReached(limit));
                }
                if !self.energised && self.rotor_at_phase {
                    // Released after a move: the rotor rests at `phase`.
                    // Hold it there first, then step. Energising the next
                    // phase straight from all-low passes through that
                    // phase's first coil alone, which (depending on the
                    // direction) can lie three half-phases from the rotor.
                    self.write_phase()?;
                }
                let inc = self.config.mode.phase_increment();
                self.phase = match dir {
                    Direction::Forward => (self.phase + inc) % 8,
                    Direction::Backward => (self.phase + 8 - inc) % 8,
                };
                self.write_phase()?;
                if self.planner.stepped(now_us) {
                    if self.config.release_when_idle {
                        if self.config.settle_us == 0 {
                            self.release()?;
                        } else {
                            self.release_at_us =
                                Some(now_us.saturating_add(u64::from(self.config.settle_us)));
                        }
                    }
                    Ok(Event::Arrived)
                } else {
                    Ok(Event::Stepped)
                }
            }
        }
    }

    /// Switches all four bridge inputs low: no coil current.
    ///
    /// ```
    /// use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::LimitSwitches;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // IN1..IN4 all written low.
    /// let low = [T::set(State::Low)];
    /// let pins = BridgePins { in1: Pin::new(&low), in2: Pin::new(&low), in3: Pin::new(&low), in4: Pin::new(&low) };
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let config = Config { mode: StepMode::Full, ramp, settle_us: 0, release_when_idle: false };
    /// let mut motor = HBridgeStepper::new(pins, LimitSwitches::<Pin>::none(), config)?;
    /// motor.release()?;
    /// assert!(!motor.is_energised());
    /// let (pins, _) = motor.destroy();
    /// for mut p in [pins.in1, pins.in2, pins.in3, pins.in4] {
    ///     p.done();
    /// }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn release(&mut self) -> Result<(), Error<E>> {
        self.release_at_us = None;
        for p in [
            &mut self.pins.in1,
            &mut self.pins.in2,
            &mut self.pins.in3,
            &mut self.pins.in4,
        ] {
            p.set_low().map_err(Error::Comm)?;
        }
        self.energised = false;
        Ok(())
    }

    fn write_phase(&mut self) -> Result<(), Error<E>> {
        let levels = PHASES
            .get(usize::from(self.phase))
            .copied()
            .unwrap_or([false; 4]);
        let mut pins = [
            &mut self.pins.in1,
            &mut self.pins.in2,
            &mut self.pins.in3,
            &mut self.pins.in4,
        ];
        // Break before make: lows first, then highs.
        for (p, &high) in pins.iter_mut().zip(levels.iter()) {
            if !high {
                p.set_low().map_err(Error::Comm)?;
            }
        }
        for (p, &high) in pins.iter_mut().zip(levels.iter()) {
            if high {
                p.set_high().map_err(Error::Comm)?;
            }
        }
        self.energised = true;
        self.rotor_at_phase = true;
        Ok(())
    }
}
