//! STEP/DIR(/ENABLE) stepper driver chips (A4988, DRV8825, TMC2208 in legacy mode).
//!
//! Per step: set DIR if it changed and wait the DIR setup time, raise STEP,
//! wait the minimum high time, lower STEP. These waits are the only blocking
//! calls in `poll` (`DelayNs::delay_ns`, ≤ a few µs); the STEP low time and
//! everything longer (the ramp intervals, the wake-up after ENABLE) are
//! scheduled, not waited for. ENABLE is asserted when a move starts and
//! de-asserted when the axis is idle (no holding current).
//!
//! Minimum timings (datasheets): A4988 STEP high ≥ 1 µs, low ≥ 1 µs, DIR setup
//! and hold ≥ 200 ns; DRV8825 STEP high ≥ 1.9 µs, low ≥ 1.9 µs, setup and
//! hold ≥ 650 ns.

use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{InputPin, OutputPin};

use super::planner::{Due, Planner};
use super::ramp::{Ramp, RampError};
use super::{Direction, Error, Event, LimitSwitches};

/// Pulse timing of a driver chip.
///
/// ```
/// use drivers::stepper::step_dir::PulseTiming;
///
/// // Allegro A4988 datasheet: STEP high and low ≥ 1 µs, DIR setup ≥ 200 ns.
/// assert_eq!(PulseTiming::A4988.step_high_ns, 1_000);
/// // TI DRV8825 datasheet: STEP high and low ≥ 1.9 µs, setup ≥ 650 ns,
/// // wake-up from sleep 1.7 ms.
/// assert_eq!(PulseTiming::DRV8825.dir_setup_ns, 650);
/// assert_eq!(PulseTiming::DRV8825.wake_us, 1_700);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PulseTiming {
    /// Minimum STEP high time, ns.
    pub step_high_ns: u32,
    /// Minimum STEP low time, ns.
    pub step_low_ns: u32,
    /// DIR setup before the rising STEP edge (and hold after it), ns.
    pub dir_setup_ns: u32,
    /// Time from ENABLE asserted to the first step, µs (scheduled, not blocking).
    pub wake_us: u32,
}

impl PulseTiming {
    /// Allegro A4988.
    ///
    /// ```
    /// use drivers::stepper::step_dir::PulseTiming;
    ///
    /// // A4988 datasheet: STEP high/low ≥ 1 µs, DIR setup/hold ≥ 200 ns, no
    /// // wake-up time to wait for.
    /// let t = PulseTiming::A4988;
    /// assert_eq!((t.step_high_ns, t.step_low_ns, t.dir_setup_ns, t.wake_us), (1_000, 1_000, 200, 0));
    /// ```
    pub const A4988: Self = Self {
        step_high_ns: 1_000,
        step_low_ns: 1_000,
        dir_setup_ns: 200,
        wake_us: 0,
    };
    /// TI DRV8825 (wake-up from sleep 1.7 ms, used when nSLEEP is tied to ENABLE).
    ///
    /// ```
    /// use drivers::stepper::step_dir::PulseTiming;
    ///
    /// // DRV8825 datasheet: STEP high/low ≥ 1.9 µs, setup/hold ≥ 650 ns.
    /// let t = PulseTiming::DRV8825;
    /// assert_eq!((t.step_high_ns, t.step_low_ns, t.dir_setup_ns, t.wake_us), (1_900, 1_900, 650, 1_700));
    /// ```
    pub const DRV8825: Self = Self {
        step_high_ns: 1_900,
        step_low_ns: 1_900,
        dir_setup_ns: 650,
        wake_us: 1_700,
    };
}

/// Configuration of a STEP/DIR axis.
///
/// ```
/// use drivers::stepper::ramp::Ramp;
/// use drivers::stepper::step_dir::{Config, PulseTiming};
///
/// // 1/16 microstepping on a 200-step motor: 3200 steps per turn; a
/// // quarter turn per second at cruise.
/// let config = Config {
///     ramp: Ramp { start_speed_sps: 200, max_speed_sps: 800, accel_sps2: 1_600 },
///     timing: PulseTiming::A4988,
///     invert_dir: true,
///     enable_active_low: true,
///     settle_us: 50_000,
/// };
/// assert_eq!(config.ramp.validate(), Ok(()));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Speed profile (in microsteps as set on the chip's MS pins).
    pub ramp: Ramp,
    /// Chip timing.
    pub timing: PulseTiming,
    /// DIR low means forward.
    pub invert_dir: bool,
    /// ENABLE is active low (A4988 ¬ENABLE, DRV8825 nENBL).
    pub enable_active_low: bool,
    /// Keep enabled this long after the last step, µs.
    pub settle_us: u32,
}

/// STEP, DIR and the optional ENABLE pin.
///
/// ```
/// use drivers::stepper::step_dir::StepDirPins;
/// use embedded_hal_mock::eh1::digital::Mock as Pin;
///
/// // ENABLE not wired (tied active on the board).
/// let pins = StepDirPins { step: Pin::new(&[]), dir: Pin::new(&[]), enable: None };
/// for mut p in [pins.step, pins.dir] {
///     p.done();
/// }
/// ```
#[derive(Debug)]
pub struct StepDirPins<P> {
    /// STEP input of the chip.
    pub step: P,
    /// DIR input of the chip.
    pub dir: P,
    /// ENABLE input of the chip, if wired.
    pub enable: Option<P>,
}

/// A stepper behind a STEP/DIR driver chip.
///
/// ```
/// use drivers::stepper::ramp::Ramp;
/// use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
/// use drivers::stepper::{Event, LimitSwitches};
/// use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
///
/// // TI DRV8825 datasheet: nENBL active low; wake-up 1.7 ms after nSLEEP
/// // (tied to it); DIR setup 650 ns; STEP high ≥ 1.9 µs. One step backward
/// // (DIR low), then the chip is disabled again.
/// let (h, l) = (T::set(State::High), T::set(State::Low));
/// let mut step = Pin::new(&[h.clone(), l.clone()]);
/// let mut dir = Pin::new(&[l.clone()]);
/// let mut enable = Pin::new(&[l.clone(), h.clone()]);
/// let mut delay = CheckedDelay::new(&[D::delay_ns(650), D::delay_ns(1_900)]);
/// let pins = StepDirPins { step: step.clone(), dir: dir.clone(), enable: Some(enable.clone()) };
/// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
/// let config = Config { ramp, timing: PulseTiming::DRV8825, invert_dir: false, enable_active_low: true, settle_us: 0 };
/// let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), delay.clone(), config)?;
/// motor.move_to(-1);
/// assert_eq!(motor.poll(0)?, Event::Waiting); // enabled, waking up
/// assert_eq!(motor.poll(1_699)?, Event::Waiting);
/// assert_eq!(motor.poll(1_700)?, Event::Arrived);
/// assert_eq!(motor.position(), -1);
/// for pin in [&mut step, &mut dir, &mut enable] {
///     pin.done();
/// }
/// delay.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct StepDirStepper<P, L, D> {
    pins: StepDirPins<P>,
    limits: LimitSwitches<L>,
    delay: D,
    planner: Planner,
    config: Config,
    dir_state: Option<Direction>,
    enabled: bool,
    ready_at_us: u64,
    disable_at_us: Option<u64>,
}

impl<P, L, D, E> StepDirStepper<P, L, D>
where
    P: OutputPin<Error = E>,
    L: InputPin<Error = E>,
    D: DelayNs,
{
    /// Creates the driver at position 0, disabled. Refuses a ramp whose
    /// shortest interval cannot hold one STEP pulse plus DIR hold.
    ///
    /// ```
    /// use drivers::stepper::ramp::{Ramp, RampError};
    /// use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// use drivers::stepper::{Error, LimitSwitches};
    /// use embedded_hal_mock::eh1::delay::NoopDelay;
    /// use embedded_hal_mock::eh1::digital::Mock as Pin;
    ///
    /// // 62 500 steps/s is a 16 µs interval; a pulse timing of 10 µs high
    /// // plus 10 µs low does not fit it.
    /// let mut pins = [Pin::new(&[]), Pin::new(&[]), Pin::new(&[])];
    /// let [step, dir, enable] = pins.clone();
    /// let ramp = Ramp { start_speed_sps: 1_000, max_speed_sps: 62_500, accel_sps2: 1_000_000 };
    /// let slow = PulseTiming { step_high_ns: 10_000, step_low_ns: 10_000, ..PulseTiming::A4988 };
    /// let config = Config { ramp, timing: slow, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// let e = StepDirStepper::new(
    ///     StepDirPins { step, dir, enable: Some(enable) },
    ///     LimitSwitches::<Pin>::none(),
    ///     NoopDelay::new(),
    ///     config,
    /// )
    /// .err();
    /// assert_eq!(e, Some(Error::InvalidConfig(RampError::PulseTooLong)));
    /// // The A4988 (1 µs + 1 µs) fits.
    /// let [step, dir, enable] = pins.clone();
    /// let a4988 = Config { timing: PulseTiming::A4988, ..config };
    /// let motor = StepDirStepper::new(
    ///     StepDirPins { step, dir, enable: Some(enable) },
    ///     LimitSwitches::<Pin>::none(),
    ///     NoopDelay::new(),
    ///     a4988,
    /// )?;
    /// assert!(!motor.is_enabled());
    /// pins.iter_mut().for_each(Pin::done); // no pin touched
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn new(
        pins: StepDirPins<P>,
        limits: LimitSwitches<L>,
        delay: D,
        config: Config,
    ) -> Result<Self, Error<E>> {
        let planner = Planner::new(config.ramp).map_err(Error::InvalidConfig)?;
        let t = config.timing;
        let pulse_ns = u64::from(t.step_high_ns) + u64::from(t.step_low_ns.max(t.dir_setup_ns));
        let min_interval_ns = 1_000 * u64::from(config.ramp.interval_us(u32::MAX));
        if pulse_ns > min_interval_ns {
            return Err(Error::InvalidConfig(RampError::PulseTooLong));
        }
        Ok(Self {
            pins,
            limits,
            delay,
            planner,
            config,
            dir_state: None,
            enabled: false,
            ready_at_us: 0,
            disable_at_us: None,
        })
    }

    /// Gives the pins and the delay back.
    ///
    /// ```
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// # let pins = StepDirPins { step: Pin::new(&[]), dir: Pin::new(&[]), enable: Some(Pin::new(&[])) };
    /// # let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), CheckedDelay::new(&[]), config)?;
    /// let (pins, limits, delay) = motor.destroy();
    /// assert!(pins.enable.is_some() && limits.min.is_none());
    /// let mut motor = StepDirStepper::new(pins, limits, delay, config)?; // e.g. after a reconfiguration
    /// # let (pins, _, mut delay) = motor.destroy();
    /// # for mut p in [pins.step, pins.dir, pins.enable.unwrap()] { p.done(); }
    /// # delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> (StepDirPins<P>, LimitSwitches<L>, D) {
        (self.pins, self.limits, self.delay)
    }

    /// Position in (micro)steps.
    ///
    /// ```
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// # // A4988: ENABLE (active low) asserted, DIR high, 200 ns setup, STEP
    /// # // high for 1 µs, twice; then ENABLE released.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = StepDirPins {
    /// #     step: Pin::new(&[h.clone(), l.clone(), h.clone(), l.clone()]),
    /// #     dir: Pin::new(&[h.clone()]),
    /// #     enable: Some(Pin::new(&[l.clone(), h.clone()])),
    /// # };
    /// # let delay = CheckedDelay::new(&[D::delay_ns(200), D::delay_ns(1_000), D::delay_ns(1_000)]);
    /// # let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), delay, config)?;
    /// motor.move_to(2);
    /// motor.poll(0)?;
    /// assert_eq!(motor.position(), 1);
    /// motor.poll(5_780)?; // 10⁶ / √(100² + 2·10 000·1) µs later
    /// assert_eq!(motor.position(), 2);
    /// # let (pins, _, mut delay) = motor.destroy();
    /// # for mut p in [pins.step, pins.dir, pins.enable.unwrap()] { p.done(); }
    /// # delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn position(&self) -> i32 {
        self.planner.position()
    }

    /// True while moving.
    ///
    /// ```
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// # // A4988: ENABLE (active low) asserted, DIR high, 200 ns setup, STEP
    /// # // high for 1 µs, twice; then ENABLE released.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = StepDirPins {
    /// #     step: Pin::new(&[h.clone(), l.clone(), h.clone(), l.clone()]),
    /// #     dir: Pin::new(&[h.clone()]),
    /// #     enable: Some(Pin::new(&[l.clone(), h.clone()])),
    /// # };
    /// # let delay = CheckedDelay::new(&[D::delay_ns(200), D::delay_ns(1_000), D::delay_ns(1_000)]);
    /// # let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), delay, config)?;
    /// motor.move_to(2);
    /// assert!(motor.is_moving());
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// assert!(!motor.is_moving());
    /// # let (pins, _, mut delay) = motor.destroy();
    /// # for mut p in [pins.step, pins.dir, pins.enable.unwrap()] { p.done(); }
    /// # delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn is_moving(&self) -> bool {
        self.planner.is_moving()
    }

    /// True while ENABLE is asserted.
    ///
    /// ```
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// # // A4988: ENABLE (active low) asserted, DIR high, 200 ns setup, STEP
    /// # // high for 1 µs, twice; then ENABLE released.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = StepDirPins {
    /// #     step: Pin::new(&[h.clone(), l.clone(), h.clone(), l.clone()]),
    /// #     dir: Pin::new(&[h.clone()]),
    /// #     enable: Some(Pin::new(&[l.clone(), h.clone()])),
    /// # };
    /// # let delay = CheckedDelay::new(&[D::delay_ns(200), D::delay_ns(1_000), D::delay_ns(1_000)]);
    /// # let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), delay, config)?;
    /// assert!(!motor.is_enabled());
    /// motor.move_to(2);
    /// motor.poll(0)?;
    /// assert!(motor.is_enabled());
    /// motor.poll(5_780)?; // arrived, disabled at once (settle_us = 0)
    /// assert!(!motor.is_enabled());
    /// # let (pins, _, mut delay) = motor.destroy();
    /// # for mut p in [pins.step, pins.dir, pins.enable.unwrap()] { p.done(); }
    /// # delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn is_enabled(&self) -> bool {
        self.enabled
    }

    /// Redefines the position (after homing); refused (false) while moving.
    ///
    /// ```
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// # let pins = StepDirPins { step: Pin::new(&[]), dir: Pin::new(&[]), enable: Some(Pin::new(&[])) };
    /// # let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), CheckedDelay::new(&[]), config)?;
    /// assert!(motor.set_position(-500));
    /// assert_eq!(motor.position(), -500);
    /// motor.move_by(10);
    /// assert!(!motor.set_position(0)); // moving
    /// # let (pins, _, mut delay) = motor.destroy();
    /// # for mut p in [pins.step, pins.dir, pins.enable.unwrap()] { p.done(); }
    /// # delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_position(&mut self, position: i32) -> bool {
        self.planner.set_position(position)
    }

    /// Go to an absolute position.
    ///
    /// ```
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// # // A4988: ENABLE (active low) asserted, DIR high, 200 ns setup, STEP
    /// # // high for 1 µs, twice; then ENABLE released.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = StepDirPins {
    /// #     step: Pin::new(&[h.clone(), l.clone(), h.clone(), l.clone()]),
    /// #     dir: Pin::new(&[h.clone()]),
    /// #     enable: Some(Pin::new(&[l.clone(), h.clone()])),
    /// # };
    /// # let delay = CheckedDelay::new(&[D::delay_ns(200), D::delay_ns(1_000), D::delay_ns(1_000)]);
    /// # let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), delay, config)?;
    /// motor.move_to(2);
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// assert_eq!(motor.poll(1_000)?, Event::Waiting);
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// assert_eq!(motor.poll(9_999)?, Event::Idle);
    /// # let (pins, _, mut delay) = motor.destroy();
    /// # for mut p in [pins.step, pins.dir, pins.enable.unwrap()] { p.done(); }
    /// # delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn move_to(&mut self, target: i32) {
        self.disable_at_us = None;
        self.planner.move_to(target);
    }

    /// Go by a relative number of steps.
    ///
    /// ```
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// # // A4988: ENABLE (active low) asserted, DIR high, 200 ns setup, STEP
    /// # // high for 1 µs, twice; then ENABLE released.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = StepDirPins {
    /// #     step: Pin::new(&[h.clone(), l.clone(), h.clone(), l.clone()]),
    /// #     dir: Pin::new(&[h.clone()]),
    /// #     enable: Some(Pin::new(&[l.clone(), h.clone()])),
    /// # };
    /// # let delay = CheckedDelay::new(&[D::delay_ns(200), D::delay_ns(1_000), D::delay_ns(1_000)]);
    /// # let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), delay, config)?;
    /// motor.move_by(3);
    /// motor.move_by(-1); // relative to the target: 2
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// assert_eq!(motor.position(), 2);
    /// # let (pins, _, mut delay) = motor.destroy();
    /// # for mut p in [pins.step, pins.dir, pins.enable.unwrap()] { p.done(); }
    /// # delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn move_by(&mut self, delta: i32) {
        self.disable_at_us = None;
        self.planner.move_by(delta);
    }

    /// Decelerate to rest along the ramp.
    ///
    /// ```
    /// # use drivers::stepper::ramp::Ramp;
    /// # use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// # use drivers::stepper::{Event, LimitSwitches};
    /// # use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// # let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// # // A4988: ENABLE (active low) asserted, DIR high, 200 ns setup, STEP
    /// # // high for 1 µs, twice; then ENABLE released.
    /// # let (h, l) = (T::set(State::High), T::set(State::Low));
    /// # let pins = StepDirPins {
    /// #     step: Pin::new(&[h.clone(), l.clone(), h.clone(), l.clone()]),
    /// #     dir: Pin::new(&[h.clone()]),
    /// #     enable: Some(Pin::new(&[l.clone(), h.clone()])),
    /// # };
    /// # let delay = CheckedDelay::new(&[D::delay_ns(200), D::delay_ns(1_000), D::delay_ns(1_000)]);
    /// # let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), delay, config)?;
    /// motor.move_to(10_000);
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// motor.stop(); // at ramp level 1: one more step
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// assert_eq!(motor.position(), 2);
    /// # let (pins, _, mut delay) = motor.destroy();
    /// # for mut p in [pins.step, pins.dir, pins.enable.unwrap()] { p.done(); }
    /// # delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn stop(&mut self) {
        self.planner.stop();
    }

    /// Drive the state machine; call often.
    ///
    /// ```
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// use drivers::stepper::{Event, LimitSwitches};
    /// use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // Allegro A4988 datasheet: ¬ENABLE active low; DIR set up ≥ 200 ns
    /// // before the rising STEP edge; STEP high ≥ 1 µs. Two steps forward
    /// // (DIR high), then ENABLE released 2 ms after the last step.
    /// let (h, l) = (T::set(State::High), T::set(State::Low));
    /// let mut step = Pin::new(&[h.clone(), l.clone(), h.clone(), l.clone()]);
    /// let mut dir = Pin::new(&[h.clone()]);
    /// let mut enable = Pin::new(&[l.clone(), h.clone()]);
    /// let mut delay = CheckedDelay::new(&[D::delay_ns(200), D::delay_ns(1_000), D::delay_ns(1_000)]);
    /// let pins = StepDirPins { step: step.clone(), dir: dir.clone(), enable: Some(enable.clone()) };
    /// // Intervals 10⁶ / √(100² + 2·10 000·k) µs (see `Ramp`): 5 780 µs at k = 1.
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 2_000 };
    /// let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), delay.clone(), config)?;
    /// motor.move_to(2);
    /// assert_eq!(motor.poll(0)?, Event::Stepped);
    /// assert_eq!(motor.poll(5_779)?, Event::Waiting);
    /// assert_eq!(motor.poll(5_780)?, Event::Arrived);
    /// assert_eq!(motor.poll(7_779)?, Event::Idle);
    /// assert!(motor.is_enabled());
    /// assert_eq!(motor.poll(7_780)?, Event::Idle);
    /// assert!(!motor.is_enabled());
    /// for pin in [&mut step, &mut dir, &mut enable] {
    ///     pin.done();
    /// }
    /// delay.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn poll(&mut self, now_us: u64) -> Result<Event, Error<E>> {
        match self.planner.due(now_us) {
            Due::Idle => {
                if let Some(t) = self.disable_at_us {
                    if now_us >= t {
                        self.disable()?;
                    }
                }
                Ok(Event::Idle)
            }
            Due::Wait => Ok(Event::Waiting),
            Due::Step(dir) => {
                if let Some(limit) = self.limits.blocking(dir).map_err(Error::Comm)? {
                    self.planner.halt();
                    self.disable()?;
                    return Ok(Event::LimitReached(limit));
                }
                if !self.enabled {
                    self.enable()?;
                    self.ready_at_us = now_us.saturating_add(u64::from(self.config.timing.wake_us));
                }
                if now_us < self.ready_at_us {
                    return Ok(Event::Waiting);
                }
                if self.dir_state != Some(dir) {
                    let high = (dir == Direction::Forward) != self.config.invert_dir;
                    set(&mut self.pins.dir, high)?;
                    self.dir_state = Some(dir);
                    self.delay.delay_ns(self.config.timing.dir_setup_ns);
                }
                self.pins.step.set_high().map_err(Error::Comm)?;
                self.delay.delay_ns(self.config.timing.step_high_ns);
                self.pins.step.set_low().map_err(Error::Comm)?;
                if self.planner.stepped(now_us) {
                    if self.config.settle_us == 0 {
                        self.disable()?;
                    } else {
                        self.disable_at_us =
                            Some(now_us.saturating_add(u64::from(self.config.settle_us)));
                    }
                    Ok(Event::Arrived)
                } else {
                    Ok(Event::Stepped)
                }
            }
        }
    }

    fn enable(&mut self) -> Result<(), Error<E>> {
        let level = !self.config.enable_active_low;
        if let Some(p) = self.pins.enable.as_mut() {
            set(p, level)?;
        }
        self.enabled = true;
        Ok(())
    }

    /// De-asserts ENABLE (outputs off, no holding current).
    ///
    /// ```
    /// use drivers::stepper::ramp::Ramp;
    /// use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
    /// use drivers::stepper::LimitSwitches;
    /// use embedded_hal_mock::eh1::delay::NoopDelay;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // A4988 ¬ENABLE is active low: de-asserting drives it high.
    /// let mut enable = Pin::new(&[T::set(State::High)]);
    /// let pins = StepDirPins { step: Pin::new(&[]), dir: Pin::new(&[]), enable: Some(enable.clone()) };
    /// let ramp = Ramp { start_speed_sps: 100, max_speed_sps: 1_000, accel_sps2: 10_000 };
    /// let config = Config { ramp, timing: PulseTiming::A4988, invert_dir: false, enable_active_low: true, settle_us: 0 };
    /// let mut motor = StepDirStepper::new(pins, LimitSwitches::<Pin>::none(), NoopDelay::new(), config)?;
    /// motor.disable()?;
    /// assert!(!motor.is_enabled());
    /// let (pins, _, _) = motor.destroy();
    /// for mut p in [pins.step, pins.dir] {
    ///     p.done();
    /// }
    /// enable.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn disable(&mut self) -> Result<(), Error<E>> {
        self.disable_at_us = None;
        let level = self.config.enable_active_low;
        if let Some(p) = self.pins.enable.as_mut() {
            set(p, level)?;
        }
        self.enabled = false;
        Ok(())
    }
}

fn set<P: OutputPin>(p: &mut P, high: bool) -> Result<(), Error<P::Error>> {
    if high {
        p.set_high().map_err(Error::Comm)
    } else {
        p.set_low().map_err(Error::Comm)
    }
}
