//! Brushed DC gear motors (tracker axes, linear actuators) behind an
//! H-bridge, non-blocking: one `poll(now_ms)` per main-loop pass per axis.
//!
//! * [`bts7960`]: the Infineon BTS7960 half-bridge pair as sold on the IBT-2
//!   module (two PWM inputs RPWM/LPWM, two enables R_EN/L_EN), with the
//!   current sense of its IS pins read through [`crate::adc`].
//! * [`l298n`]: the ST L298 full bridge as on the common L298N module (one
//!   PWM enable ENA, two direction inputs IN1/IN2).
//!
//! Commands are a signed duty in permille (−1000..=1000, positive =
//! [`Direction::Forward`]), given as `f32` −1..+1 ([`duty_permille`]) or as
//! a direction and an integer permille. A command only sets the target; the
//! duty actually output moves towards it in `poll` by at most
//! [`Config::ramp_permille_per_ms`] per elapsed millisecond ([`DutyRamp`]):
//! soft start, soft stop and a soft reversal through zero, without ever
//! blocking. [`DcMotor::brake`] and [`DcMotor::coast`] act at once. When
//! the ramp comes down to zero the bridge is put into the configured
//! [`RestMode`].
//!
//! The commands, the ramp and the retry of a failed write are written once,
//! in [`DcMotor`]; a chip only says how its pins carry an [`Output`], by
//! implementing [`Bridge`] for its pin set ([`bts7960::Bts7960Pins`],
//! [`l298n::L298nPins`]). [`bts7960::Bts7960`] and [`l298n::L298n`] are
//! `DcMotor` over those pins.
//!
//! Each output (PWM channel or pin) is written only when its value changes;
//! the examples and tests list the exact writes with `embedded-hal-mock`.
//! Duty counts are `round(permille · max_duty / 1000)` in 32-bit integers.

pub mod bts7960;
pub mod l298n;

pub use crate::stepper::Direction;

/// Driver errors.
///
/// ```
/// use drivers::dc_motor::l298n::{L298n, L298nPins};
/// use drivers::dc_motor::{Config, Error, RestMode};
/// use embedded_hal_mock::eh1::digital::Mock as Pin;
/// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
///
/// // A PWM channel that reports a max duty of 0 cannot output any duty.
/// let mut ena = Pwm::new(&[P::max_duty_cycle(0)]);
/// let (mut in1, mut in2) = (Pin::new(&[]), Pin::new(&[]));
/// let pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
/// let config = Config { ramp_permille_per_ms: 1, rest: RestMode::Coast };
/// let e = L298n::new(pins, config).unwrap_err();
/// assert_eq!(e, Error::InvalidConfig);
/// assert_eq!(e.to_string(), "unusable DC motor configuration");
/// ena.done();
/// in1.done();
/// in2.done();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error<PwmE, PinE> {
    /// A PWM channel refused the duty cycle.
    Pwm(PwmE),
    /// A digital output refused the level.
    Pin(PinE),
    /// Duty command NaN, infinite or outside −1..+1 (−1000..=1000 ‰).
    InvalidDuty,
    /// A PWM channel reports a max duty of 0.
    InvalidConfig,
}

impl<PwmE: core::fmt::Debug, PinE: core::fmt::Debug> core::fmt::Display for Error<PwmE, PinE> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Pwm(e) => write!(f, "DC motor PWM error: {e:?}"),
            Error::Pin(e) => write!(f, "DC motor pin error: {e:?}"),
            Error::InvalidDuty => f.write_str("DC motor duty NaN, infinite or outside -1..+1"),
            Error::InvalidConfig => f.write_str("unusable DC motor configuration"),
        }
    }
}

impl<PwmE: core::fmt::Debug, PinE: core::fmt::Debug> core::error::Error for Error<PwmE, PinE> {}

/// What the bridge does when the ramp has brought the duty down to zero.
///
/// ```
/// use drivers::dc_motor::RestMode;
///
/// // A self-locking worm-gear axis can coast; a back-drivable one brakes.
/// let rest = |self_locking: bool| if self_locking { RestMode::Coast } else { RestMode::Brake };
/// assert_eq!(rest(false), RestMode::Brake);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RestMode {
    /// Both motor terminals to the same rail: the motor is shorted through
    /// the bridge (dynamic braking, "fast motor stop" in the L298 data sheet).
    Brake,
    /// All bridge switches off: the motor runs down freely ("free running
    /// motor stop").
    Coast,
}

/// Configuration shared by both bridges.
///
/// ```
/// use drivers::dc_motor::{Config, RestMode};
///
/// // 0 → full duty in 500 ms: 1000 ‰ / 500 ms = 2 ‰ per ms.
/// let config = Config { ramp_permille_per_ms: 2, rest: RestMode::Brake };
/// assert_eq!(1_000 / config.ramp_permille_per_ms, 500);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// Largest duty change per millisecond, ‰/ms; 0 = no ramp (the target
    /// is output in the next `poll`).
    pub ramp_permille_per_ms: u16,
    /// Bridge state at zero duty.
    pub rest: RestMode,
}

/// What the bridge is told to do.
///
/// ```
/// use drivers::dc_motor::Output;
///
/// let driving = |o: Output| matches!(o, Output::Forward(_) | Output::Backward(_));
/// assert!(driving(Output::Backward(250)) && !driving(Output::Brake));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Output {
    /// Driven forward at this duty, ‰ (1..=1000).
    Forward(u16),
    /// Driven backward at this duty, ‰ (1..=1000).
    Backward(u16),
    /// Terminals shorted.
    Brake,
    /// Bridge off.
    Coast,
}

impl Output {
    /// The output for a signed duty, ‰; `rest` at zero.
    fn from_permille(permille: i16, rest: RestMode) -> Self {
        if permille > 0 {
            Output::Forward(permille.unsigned_abs())
        } else if permille < 0 {
            Output::Backward(permille.unsigned_abs())
        } else {
            match rest {
                RestMode::Brake => Output::Brake,
                RestMode::Coast => Output::Coast,
            }
        }
    }
}

/// Full duty, ‰.
const FULL_PERMILLE: i16 = 1_000;

/// A duty −1..+1 as signed permille, rounded to the nearest (halves away
/// from zero); `None` for NaN, infinities and values outside −1..+1.
///
/// ```
/// use drivers::dc_motor::duty_permille;
///
/// assert_eq!(duty_permille(0.5), Some(500));
/// assert_eq!(duty_permille(-0.0125), Some(-13)); // −12.5 ‰, half away from zero
/// assert_eq!(duty_permille(-1.0), Some(-1_000));
/// assert_eq!(duty_permille(1.001), None);
/// assert_eq!(duty_permille(f32::NAN), None);
/// ```
pub fn duty_permille(duty: f32) -> Option<i16> {
    if !duty.is_finite() || !(-1.0..=1.0).contains(&duty) {
        return None;
    }
    // |duty · 1000| ≤ 1000: the conversion cannot truncate.
    let scaled = duty * f32::from(FULL_PERMILLE);
    let rounded = if scaled >= 0.0 {
        scaled + 0.5
    } else {
        scaled - 0.5
    };
    Some((rounded as i16).clamp(-FULL_PERMILLE, FULL_PERMILLE))
}

/// A direction and a magnitude, ‰, as signed permille; `None` above 1000.
///
/// ```
/// use drivers::dc_motor::{signed_permille, Direction};
///
/// assert_eq!(signed_permille(Direction::Backward, 300), Some(-300));
/// assert_eq!(signed_permille(Direction::Forward, 1_001), None);
/// ```
pub fn signed_permille(direction: Direction, permille: u16) -> Option<i16> {
    let p = i16::try_from(permille)
        .ok()
        .filter(|&p| p <= FULL_PERMILLE)?;
    Some(match direction {
        Direction::Forward => p,
        Direction::Backward => -p,
    })
}

/// Duty counts for `permille` of `max_duty`: `round(permille · max / 1000)`,
/// at most `max_duty`. `permille` ≤ 1000 and `max_duty` ≤ 65,535 keep the
/// product under 2³².
fn duty_counts(permille: u16, max_duty: u16) -> u16 {
    let p = u32::from(permille.min(FULL_PERMILLE.unsigned_abs()));
    let counts = (p * u32::from(max_duty) + 500) / 1_000;
    u16::try_from(counts).unwrap_or(max_duty).min(max_duty)
}

/// Calls `write(value)` unless `value` is already the last value written.
/// The record is cleared before the write, so a failed write is repeated
/// next time.
fn write_changed<T: Copy + PartialEq, E>(
    last: &mut Option<T>,
    value: T,
    write: impl FnOnce(T) -> Result<(), E>,
) -> Result<(), E> {
    if *last != Some(value) {
        *last = None;
        write(value)?;
        *last = Some(value);
    }
    Ok(())
}

/// Writes `duty` to a PWM channel unless it already has it
/// ([`write_changed`]).
fn write_duty<P: embedded_hal::pwm::SetDutyCycle>(
    pwm: &mut P,
    last: &mut Option<u16>,
    duty: u16,
) -> Result<(), P::Error> {
    write_changed(last, duty, |d| pwm.set_duty_cycle(d))
}

/// Sets a digital output unless it already has that level
/// ([`write_changed`]).
fn write_pin<P: embedded_hal::digital::OutputPin>(
    pin: &mut P,
    last: &mut Option<bool>,
    high: bool,
) -> Result<(), P::Error> {
    write_changed(
        last,
        high,
        |h| if h { pin.set_high() } else { pin.set_low() },
    )
}

/// The output stage of one H-bridge chip: how its pins carry an [`Output`].
///
/// Implemented by each chip's pin set; [`DcMotor`] does the rest (commands,
/// ramp, retry). An implementation keeps in [`Bridge::State`] what it needs
/// between writes (the channels' max duty, the value last written to each
/// input) and writes an input only when its value changes, in the order its
/// data sheet asks for.
///
/// ```
/// use drivers::dc_motor::{Bridge, Error, Output};
/// use embedded_hal::pwm::SetDutyCycle;
/// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
///
/// // A one-direction bridge (a single low-side switch on a PWM output):
/// // backward and brake are not available, coast is duty 0.
/// struct LowSide<C>(C);
/// impl<C: SetDutyCycle> Bridge for LowSide<C> {
///     type PwmError = C::Error;
///     type PinError = core::convert::Infallible;
///     type State = u16; // max duty
///     fn init(&mut self) -> Result<u16, Error<C::Error, Self::PinError>> {
///         let max = self.0.max_duty_cycle();
///         self.0.set_duty_cycle(0).map_err(Error::Pwm)?;
///         Ok(max)
///     }
///     fn apply(&mut self, max: &mut u16, output: Output) -> Result<(), Error<C::Error, Self::PinError>> {
///         let permille = match output {
///             Output::Forward(p) => u32::from(p),
///             _ => 0,
///         };
///         let counts = u16::try_from(permille * u32::from(*max) / 1_000).unwrap_or(*max);
///         self.0.set_duty_cycle(counts).map_err(Error::Pwm)
///     }
/// }
///
/// let mut pwm = Pwm::new(&[P::max_duty_cycle(100), P::set_duty_cycle(0), P::set_duty_cycle(30)]);
/// let mut bridge = LowSide(pwm.clone());
/// let mut max = bridge.init()?;
/// bridge.apply(&mut max, Output::Forward(300))?;
/// pwm.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub trait Bridge {
    /// Error of the PWM channels.
    type PwmError;
    /// Error of the digital outputs.
    type PinError;
    /// What the bridge keeps between writes (max duties, last values).
    type State;

    /// Reads what the bridge needs from its channels (a max duty of 0 is
    /// [`Error::InvalidConfig`], before any write) and leaves it coasting.
    fn init(&mut self) -> Result<Self::State, Error<Self::PwmError, Self::PinError>>;

    /// Writes the inputs for `output`, each only when its value in `state`
    /// differs. A write that fails leaves `state` so that `apply` with the
    /// same `output` again repeats only the writes still missing.
    fn apply(
        &mut self,
        state: &mut Self::State,
        output: Output,
    ) -> Result<(), Error<Self::PwmError, Self::PinError>>;
}

/// A brushed DC motor on the H-bridge `B`: commands, the [`DutyRamp`] and
/// the retry of a failed write, the same for every chip.
///
/// [`bts7960::Bts7960`] and [`l298n::L298n`] are this type over their pin
/// sets; the examples here use the L298N, whose truth table (ENA = duty,
/// IN1/IN2 = direction, ENA 0 while they change) keeps the writes short.
/// Code above the drivers can stay generic over the chip:
///
/// ```
/// use drivers::dc_motor::l298n::{L298n, L298nPins};
/// use drivers::dc_motor::{Bridge, Config, DcMotor, Error, Output, RestMode};
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
/// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
///
/// // An axis loop's end stop, for any bridge: brake unless already stopped.
/// fn stop<B: Bridge>(m: &mut DcMotor<B>) -> Result<(), Error<B::PwmError, B::PinError>> {
///     if m.output() != Output::Brake {
///         m.brake()?;
///     }
///     Ok(())
/// }
///
/// // From coast the L298N's inputs are already low: only ENA goes to full.
/// let mut ena = Pwm::new(&[P::max_duty_cycle(100), P::set_duty_cycle(0), P::set_duty_cycle(100)]);
/// let (mut in1, mut in2) = (Pin::new(&[T::set(State::Low)]), Pin::new(&[T::set(State::Low)]));
/// let pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
/// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 1, rest: RestMode::Coast })?;
/// stop(&mut motor)?;
/// stop(&mut motor)?; // nothing written
/// motor.destroy();
/// ena.done();
/// in1.done();
/// in2.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct DcMotor<B: Bridge> {
    bridge: B,
    state: B::State,
    config: Config,
    ramp: DutyRamp,
    output: Output,
    /// An output whose writes failed part-way, repeated by the next `poll`.
    pending: Option<Output>,
}

impl<B: Bridge> DcMotor<B> {
    /// Takes the bridge's pins and puts it in coast ([`Bridge::init`]),
    /// whatever the configured rest mode: nothing is driven until a command.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Output, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// let mut ena = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]);
    /// let mut in1 = Pin::new(&[T::set(State::Low)]);
    /// let mut in2 = Pin::new(&[T::set(State::Low)]);
    /// let pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
    /// let motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Brake })?;
    /// assert_eq!(motor.output(), Output::Coast);
    /// motor.destroy();
    /// ena.done();
    /// in1.done();
    /// in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn new(mut pins: B, config: Config) -> Result<Self, Error<B::PwmError, B::PinError>> {
        let state = pins.init()?;
        Ok(Self {
            bridge: pins,
            state,
            config,
            ramp: DutyRamp::new(config.ramp_permille_per_ms),
            output: Output::Coast,
            pending: None,
        })
    }

    /// Gives the pins back (the outputs keep their last levels).
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// let pins = L298nPins {
    ///     ena: Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]),
    ///     in1: Pin::new(&[T::set(State::Low)]),
    ///     in2: Pin::new(&[T::set(State::Low)]),
    /// };
    /// let motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Brake })?;
    /// let mut pins = motor.destroy();
    /// pins.ena.done();
    /// pins.in1.done();
    /// pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> B {
        self.bridge
    }

    /// Commands a duty −1..+1 (positive = forward), reached by the ramp in
    /// `poll`. NaN, infinities and values outside −1..+1 are refused
    /// ([`Error::InvalidDuty`]) and leave the target unchanged.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Error, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// # let pins = L298nPins { ena: Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]), in1: Pin::new(&[T::set(State::Low)]), in2: Pin::new(&[T::set(State::Low)]) };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Brake })?;
    /// motor.set_duty(-0.25)?;
    /// assert_eq!(motor.set_duty(f32::INFINITY), Err(Error::InvalidDuty));
    /// assert_eq!(motor.set_duty(-1.01), Err(Error::InvalidDuty));
    /// assert_eq!(motor.target_permille(), -250);
    /// motor.set_duty(-1.0)?;
    /// assert_eq!(motor.target_permille(), -1_000);
    /// # let mut pins = motor.destroy();
    /// # pins.ena.done(); pins.in1.done(); pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_duty(&mut self, duty: f32) -> Result<(), Error<B::PwmError, B::PinError>> {
        let p = duty_permille(duty).ok_or(Error::InvalidDuty)?;
        self.ramp.set_target(p);
        Ok(())
    }

    /// Commands a direction and a duty in permille (0..=1000), reached by
    /// the ramp in `poll`; above 1000 is refused ([`Error::InvalidDuty`]).
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Direction, Error, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// # let pins = L298nPins { ena: Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]), in1: Pin::new(&[T::set(State::Low)]), in2: Pin::new(&[T::set(State::Low)]) };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Brake })?;
    /// motor.set_permille(Direction::Forward, 750)?;
    /// assert_eq!(motor.target_permille(), 750);
    /// assert_eq!(motor.set_permille(Direction::Backward, u16::MAX), Err(Error::InvalidDuty));
    /// assert_eq!(motor.set_permille(Direction::Forward, 1_001), Err(Error::InvalidDuty));
    /// # let mut pins = motor.destroy();
    /// # pins.ena.done(); pins.in1.done(); pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_permille(
        &mut self,
        direction: Direction,
        permille: u16,
    ) -> Result<(), Error<B::PwmError, B::PinError>> {
        let p = signed_permille(direction, permille).ok_or(Error::InvalidDuty)?;
        self.ramp.set_target(p);
        Ok(())
    }

    /// Steps the ramp and writes the outputs that change; returns what the
    /// bridge now does. Call every main-loop pass; never waits. An output
    /// whose writes failed is written again by the next `poll`.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Output, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// // Soft reversal at 10 ‰/ms on a 100-count channel, from forward
    /// // 100 ‰ to backward 100 ‰: 10 ms to zero (ENA 0, coast at rest),
    /// // then IN1 low before IN2 high, ENA up again.
    /// let mut ena = Pwm::new(&[
    ///     P::max_duty_cycle(100), P::set_duty_cycle(0), // new
    ///     P::set_duty_cycle(10),                         // forward 100 ‰
    ///     P::set_duty_cycle(5),                          // 50 ‰
    ///     P::set_duty_cycle(0),                          // 0 ‰: coast
    ///     P::set_duty_cycle(5),                          // backward 50 ‰
    /// ]);
    /// let mut in1 = Pin::new(&[T::set(State::Low), T::set(State::High), T::set(State::Low)]);
    /// let mut in2 = Pin::new(&[T::set(State::Low), T::set(State::High)]);
    /// let pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 10, rest: RestMode::Coast })?;
    /// motor.set_duty(0.1)?;
    /// motor.poll(0)?; // clock started
    /// assert_eq!(motor.poll(10)?, Output::Forward(100));
    /// motor.set_duty(-0.1)?;
    /// assert_eq!(motor.poll(12)?, Output::Forward(100)); // settled before: clock restarted
    /// assert_eq!(motor.poll(17)?, Output::Forward(50));
    /// assert_eq!(motor.poll(22)?, Output::Coast);
    /// assert_eq!(motor.poll(27)?, Output::Backward(50));
    /// motor.destroy();
    /// ena.done();
    /// in1.done();
    /// in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn poll(&mut self, now_ms: u32) -> Result<Output, Error<B::PwmError, B::PinError>> {
        let before = self.ramp.current_permille();
        let now = self.ramp.poll(now_ms);
        if now != before {
            self.apply(Output::from_permille(now, self.config.rest))?;
        } else if let Some(retry) = self.pending {
            self.apply(retry)?;
        }
        Ok(self.output)
    }

    /// Brakes at once (the motor terminals shorted through the bridge);
    /// the ramp is reset to 0.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Output, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// // L298N fast motor stop from coast: the inputs are already low, only
    /// // ENA goes to full (255).
    /// let mut ena = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0), P::set_duty_cycle(255)]);
    /// let (mut in1, mut in2) = (Pin::new(&[T::set(State::Low)]), Pin::new(&[T::set(State::Low)]));
    /// let pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Coast })?;
    /// motor.brake()?;
    /// assert_eq!((motor.output(), motor.duty_permille()), (Output::Brake, 0));
    /// motor.destroy();
    /// ena.done();
    /// in1.done();
    /// in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn brake(&mut self) -> Result<(), Error<B::PwmError, B::PinError>> {
        self.ramp.reset(0);
        self.apply(Output::Brake)
    }

    /// Lets the motor run down freely at once (bridge off); the ramp is
    /// reset to 0.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Output, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// // L298N backward full duty, then coast: only ENA changes.
    /// let mut ena = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0), P::set_duty_cycle(255), P::set_duty_cycle(0)]);
    /// let mut in1 = Pin::new(&[T::set(State::Low)]);
    /// let mut in2 = Pin::new(&[T::set(State::Low), T::set(State::High)]);
    /// let pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 0, rest: RestMode::Brake })?;
    /// motor.set_duty(-1.0)?;
    /// motor.poll(0)?;
    /// motor.coast()?;
    /// assert_eq!((motor.output(), motor.duty_permille()), (Output::Coast, 0));
    /// motor.destroy();
    /// ena.done();
    /// in1.done();
    /// in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn coast(&mut self) -> Result<(), Error<B::PwmError, B::PinError>> {
        self.ramp.reset(0);
        self.apply(Output::Coast)
    }

    /// What the bridge was last told to do.
    ///
    /// ```
    /// # use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// # use drivers::dc_motor::{Config, Output, RestMode};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    /// # let pins = L298nPins { ena: Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]), in1: Pin::new(&[T::set(State::Low)]), in2: Pin::new(&[T::set(State::Low)]) };
    /// let motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Brake })?;
    /// assert_eq!(motor.output(), Output::Coast); // as left by `new`
    /// # let mut pins = motor.destroy();
    /// # pins.ena.done(); pins.in1.done(); pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn output(&self) -> Output {
        self.output
    }

    /// The signed duty output now, ‰ (the ramp's position).
    ///
    /// ```
    /// # use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// # use drivers::dc_motor::{Config, RestMode};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    /// # let pins = L298nPins { ena: Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]), in1: Pin::new(&[T::set(State::Low)]), in2: Pin::new(&[T::set(State::Low)]) };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 1, rest: RestMode::Brake })?;
    /// assert_eq!(motor.duty_permille(), 0);
    /// motor.set_duty(0.9)?;
    /// assert_eq!((motor.duty_permille(), motor.target_permille()), (0, 900)); // before any poll
    /// # let mut pins = motor.destroy();
    /// # pins.ena.done(); pins.in1.done(); pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn duty_permille(&self) -> i16 {
        self.ramp.current_permille()
    }

    /// The commanded signed duty, ‰.
    ///
    /// ```
    /// # use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// # use drivers::dc_motor::{Config, RestMode};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    /// # let pins = L298nPins { ena: Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]), in1: Pin::new(&[T::set(State::Low)]), in2: Pin::new(&[T::set(State::Low)]) };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Brake })?;
    /// motor.set_duty(0.333)?;
    /// assert_eq!(motor.target_permille(), 333);
    /// # let mut pins = motor.destroy();
    /// # pins.ena.done(); pins.in1.done(); pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn target_permille(&self) -> i16 {
        self.ramp.target_permille()
    }

    /// Writes `output`; when a write fails, `output` stays pending and the
    /// next `poll` writes it again (the bridge skips the inputs whose
    /// writes succeeded, see [`Bridge::apply`]).
    fn apply(&mut self, output: Output) -> Result<(), Error<B::PwmError, B::PinError>> {
        self.pending = Some(output);
        self.bridge.apply(&mut self.state, output)?;
        self.output = output;
        self.pending = None;
        Ok(())
    }
}

/// Slew-rate limit on the signed duty, ‰: the non-blocking soft start and
/// stop of both drivers, usable on its own.
///
/// `poll(now_ms)` moves the output towards the target by at most
/// `rate · (now_ms − last poll)` ‰; time differences wrap with the `u32`
/// millisecond counter (every 49.7 days). Once the output has reached its
/// target (at rest or at a steady duty) the clock stops; the first `poll`
/// after a new target only starts it again, so a long time between the
/// last poll and a new command does not turn into a jump.
///
/// ```
/// use drivers::dc_motor::DutyRamp;
///
/// let mut ramp = DutyRamp::new(2); // 2 ‰ per ms
/// ramp.set_target(500);
/// assert_eq!(ramp.poll(1_000), 0); // starts the clock
/// assert_eq!(ramp.poll(1_010), 20); // 10 ms · 2 ‰/ms
/// assert_eq!(ramp.poll(1_200), 400);
/// assert_eq!(ramp.poll(1_300), 500); // target reached, not passed
/// assert!(ramp.is_settled());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DutyRamp {
    rate_permille_per_ms: u16,
    current_permille: i16,
    target_permille: i16,
    last_ms: Option<u32>,
}

impl DutyRamp {
    /// At rest (0 ‰), limited to `rate_permille_per_ms`; 0 = no limit.
    ///
    /// ```
    /// use drivers::dc_motor::DutyRamp;
    ///
    /// let mut ramp = DutyRamp::new(0);
    /// ramp.set_target(-1_000);
    /// assert_eq!(ramp.poll(7), -1_000); // no limit: at once
    /// ```
    pub const fn new(rate_permille_per_ms: u16) -> Self {
        Self {
            rate_permille_per_ms,
            current_permille: 0,
            target_permille: 0,
            last_ms: None,
        }
    }

    /// New target, ‰, limited to −1000..=1000.
    ///
    /// ```
    /// use drivers::dc_motor::DutyRamp;
    ///
    /// let mut ramp = DutyRamp::new(1);
    /// ramp.set_target(i16::MIN);
    /// assert_eq!(ramp.target_permille(), -1_000);
    /// ```
    pub fn set_target(&mut self, permille: i16) {
        self.target_permille = permille.clamp(-FULL_PERMILLE, FULL_PERMILLE);
    }

    /// Output and target both set to `permille` at once (brake, coast).
    ///
    /// ```
    /// use drivers::dc_motor::DutyRamp;
    ///
    /// let mut ramp = DutyRamp::new(1);
    /// ramp.set_target(800);
    /// ramp.poll(0);
    /// ramp.poll(100);
    /// ramp.reset(0);
    /// assert_eq!((ramp.current_permille(), ramp.target_permille()), (0, 0));
    /// ```
    pub fn reset(&mut self, permille: i16) {
        let p = permille.clamp(-FULL_PERMILLE, FULL_PERMILLE);
        self.current_permille = p;
        self.target_permille = p;
        self.last_ms = None;
    }

    /// The duty output now, ‰.
    ///
    /// ```
    /// use drivers::dc_motor::DutyRamp;
    ///
    /// assert_eq!(DutyRamp::new(5).current_permille(), 0);
    /// ```
    pub fn current_permille(&self) -> i16 {
        self.current_permille
    }

    /// The commanded duty, ‰.
    ///
    /// ```
    /// use drivers::dc_motor::DutyRamp;
    ///
    /// let mut ramp = DutyRamp::new(5);
    /// ramp.set_target(-250);
    /// assert_eq!(ramp.target_permille(), -250);
    /// ```
    pub fn target_permille(&self) -> i16 {
        self.target_permille
    }

    /// True when the output equals the target.
    ///
    /// ```
    /// use drivers::dc_motor::DutyRamp;
    ///
    /// let mut ramp = DutyRamp::new(5);
    /// assert!(ramp.is_settled());
    /// ramp.set_target(10);
    /// assert!(!ramp.is_settled());
    /// ```
    pub fn is_settled(&self) -> bool {
        self.current_permille == self.target_permille
    }

    /// One step towards the target; returns the new output, ‰.
    ///
    /// ```
    /// use drivers::dc_motor::DutyRamp;
    ///
    /// // Reversal through zero: +300 → −300 at 3 ‰/ms takes 200 ms.
    /// let mut ramp = DutyRamp::new(3);
    /// ramp.reset(300);
    /// ramp.set_target(-300);
    /// assert_eq!(ramp.poll(u32::MAX - 9), 300); // starts the clock
    /// assert_eq!(ramp.poll(90), 0); // 100 ms later, across the wrap of the counter
    /// assert_eq!(ramp.poll(190), -300);
    /// ```
    pub fn poll(&mut self, now_ms: u32) -> i16 {
        if self.is_settled() {
            self.last_ms = None;
            return self.current_permille;
        }
        if self.rate_permille_per_ms == 0 {
            self.current_permille = self.target_permille;
            self.last_ms = None;
            return self.current_permille;
        }
        let Some(last_ms) = self.last_ms else {
            self.last_ms = Some(now_ms);
            return self.current_permille;
        };
        let elapsed_ms = now_ms.wrapping_sub(last_ms);
        if elapsed_ms == 0 {
            return self.current_permille;
        }
        self.last_ms = Some(now_ms);
        let max_step = u32::from(self.rate_permille_per_ms).saturating_mul(elapsed_ms);
        // Both ends within ±1000: the difference fits an i16 (|d| ≤ 2000).
        let diff = self.target_permille.saturating_sub(self.current_permille);
        let step = u16::try_from(max_step)
            .unwrap_or(u16::MAX)
            .min(diff.unsigned_abs());
        let step = i16::try_from(step).unwrap_or(i16::MAX);
        self.current_permille = if diff > 0 {
            self.current_permille.saturating_add(step)
        } else {
            self.current_permille.saturating_sub(step)
        };
        if self.is_settled() {
            self.last_ms = None;
        }
        self.current_permille
    }
}
