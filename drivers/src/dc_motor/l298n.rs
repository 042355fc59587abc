//! ST L298 full bridge (the L298N module): one PWM enable, two direction
//! inputs per motor.
//!
//! STMicroelectronics, *L298 Dual Full-Bridge Driver* data sheet, Figure 6
//! "Bidirectional DC motor control" and its truth table (inputs C, D of one
//! bridge, here IN1, IN2; enable Ven, here ENA):
//!
//! | ENA | IN1 | IN2 | motor                                  |
//! |-----|-----|-----|----------------------------------------|
//! | H   | H   | L   | forward                                |
//! | H   | L   | H   | backward                               |
//! | H   | IN1 = IN2 | | fast motor stop (brake)               |
//! | L   | X   | X   | free running motor stop (coast)        |
//!
//! ENA is driven with PWM, so the duty is the fraction of each period the
//! bridge conducts; brake holds ENA at full duty with IN1 = IN2 = L (both
//! lower transistors on). The data sheet's application information,
//! section 2 "Suggestions": the brake (fast motor stop) current must never
//! exceed the 2 A absolute maximum rating, so a fast-running heavy axis
//! should ramp down (or coast) before braking.
//!
//! When IN1/IN2 must change, ENA is first set to 0 (no bridge conducting),
//! then the input going low is written, then the one going high, then ENA
//! gets the new duty: the bridge is never reversed while it conducts.

use embedded_hal::digital::OutputPin;
use embedded_hal::pwm::SetDutyCycle;

use super::{
    duty_counts, duty_permille, signed_permille, write_duty, write_pin, Config, Direction,
    DutyRamp, Error, Output,
};

/// The bridge's three control inputs.
///
/// ```
/// use drivers::dc_motor::l298n::L298nPins;
/// use embedded_hal_mock::eh1::digital::Mock as Pin;
/// use embedded_hal_mock::eh1::pwm::Mock as Pwm;
///
/// // Bridge A of the module: ENA, IN1, IN2 (bridge B: ENB, IN3, IN4).
/// let L298nPins { mut ena, mut in1, mut in2 } = L298nPins { ena: Pwm::new(&[]), in1: Pin::new(&[]), in2: Pin::new(&[]) };
/// ena.done();
/// in1.done();
/// in2.done();
/// ```
#[derive(Debug)]
pub struct L298nPins<P, I> {
    /// ENA (or ENB): the bridge enable, driven with PWM.
    pub ena: P,
    /// IN1 (or IN3): input C of the data sheet's Figure 6.
    pub in1: I,
    /// IN2 (or IN4): input D.
    pub in2: I,
}

/// A DC motor on one bridge of an L298N.
///
/// ```
/// use drivers::dc_motor::l298n::{L298n, L298nPins};
/// use drivers::dc_motor::{Config, Output, RestMode};
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
/// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
///
/// // `new`: ENA 0, IN1 low, IN2 low (coast). Forward 40 % without a ramp on
/// // a 1000-count channel: ENA is already 0, IN1 goes high, ENA 400.
/// let mut ena = Pwm::new(&[P::max_duty_cycle(1_000), P::set_duty_cycle(0), P::set_duty_cycle(400)]);
/// let mut in1 = Pin::new(&[T::set(State::Low), T::set(State::High)]);
/// let mut in2 = Pin::new(&[T::set(State::Low)]);
/// let pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
/// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 0, rest: RestMode::Coast })?;
/// motor.set_duty(0.4)?;
/// assert_eq!(motor.poll(0)?, Output::Forward(400));
/// motor.destroy();
/// ena.done();
/// in1.done();
/// in2.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct L298n<P, I> {
    pins: L298nPins<P, I>,
    config: Config,
    max_duty: u16,
    ramp: DutyRamp,
    output: Output,
    /// An output whose writes failed part-way, repeated by the next `poll`.
    pending: Option<Output>,
    last_ena: Option<u16>,
    last_in1: Option<bool>,
    last_in2: Option<bool>,
}

impl<P: SetDutyCycle, I: OutputPin> L298n<P, I> {
    /// Reads ENA's max duty, then coasts: ENA 0, IN1 and IN2 low.
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
    pub fn new(pins: L298nPins<P, I>, config: Config) -> Result<Self, Error<P::Error, I::Error>> {
        let max_duty = pins.ena.max_duty_cycle();
        if max_duty == 0 {
            return Err(Error::InvalidConfig);
        }
        let mut m = Self {
            pins,
            config,
            max_duty,
            ramp: DutyRamp::new(config.ramp_permille_per_ms),
            output: Output::Coast,
            pending: None,
            last_ena: None,
            last_in1: None,
            last_in2: None,
        };
        write_duty(&mut m.pins.ena, &mut m.last_ena, 0).map_err(Error::Pwm)?;
        write_pin(&mut m.pins.in1, &mut m.last_in1, false).map_err(Error::Pin)?;
        write_pin(&mut m.pins.in2, &mut m.last_in2, false).map_err(Error::Pin)?;
        Ok(m)
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
    pub fn destroy(self) -> L298nPins<P, I> {
        self.pins
    }

    /// Commands a duty −1..+1 (positive = forward), reached by the ramp in
    /// `poll`; NaN, infinities and values outside −1..+1 are refused.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Error, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// # let pins = L298nPins { ena: Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]), in1: Pin::new(&[T::set(State::Low)]), in2: Pin::new(&[T::set(State::Low)]) };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Brake })?;
    /// assert_eq!(motor.set_duty(f32::INFINITY), Err(Error::InvalidDuty));
    /// assert_eq!(motor.set_duty(-1.01), Err(Error::InvalidDuty));
    /// motor.set_duty(-1.0)?;
    /// assert_eq!(motor.target_permille(), -1_000);
    /// # let mut pins = motor.destroy();
    /// # pins.ena.done(); pins.in1.done(); pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_duty(&mut self, duty: f32) -> Result<(), Error<P::Error, I::Error>> {
        let p = duty_permille(duty).ok_or(Error::InvalidDuty)?;
        self.ramp.set_target(p);
        Ok(())
    }

    /// Commands a direction and a duty in permille (0..=1000); above 1000
    /// is refused.
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
    /// # let mut pins = motor.destroy();
    /// # pins.ena.done(); pins.in1.done(); pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn set_permille(
        &mut self,
        direction: Direction,
        permille: u16,
    ) -> Result<(), Error<P::Error, I::Error>> {
        let p = signed_permille(direction, permille).ok_or(Error::InvalidDuty)?;
        self.ramp.set_target(p);
        Ok(())
    }

    /// Steps the ramp and writes the outputs that change; returns what the
    /// bridge now does. Never waits.
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
    pub fn poll(&mut self, now_ms: u32) -> Result<Output, Error<P::Error, I::Error>> {
        let before = self.ramp.current_permille();
        let now = self.ramp.poll(now_ms);
        if now != before {
            self.apply(Output::from_permille(now, self.config.rest))?;
        } else if let Some(retry) = self.pending {
            self.apply(retry)?;
        }
        Ok(self.output)
    }

    /// Brakes at once (fast motor stop): ENA full, IN1 = IN2 = low; the
    /// ramp is reset to 0.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Output, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// // From coast the inputs are already low: only ENA goes to full (255).
    /// let mut ena = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0), P::set_duty_cycle(255)]);
    /// let (mut in1, mut in2) = (Pin::new(&[T::set(State::Low)]), Pin::new(&[T::set(State::Low)]));
    /// let pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
    /// let mut motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Coast })?;
    /// motor.brake()?;
    /// assert_eq!(motor.output(), Output::Brake);
    /// motor.destroy();
    /// ena.done();
    /// in1.done();
    /// in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn brake(&mut self) -> Result<(), Error<P::Error, I::Error>> {
        self.ramp.reset(0);
        self.apply(Output::Brake)
    }

    /// Free running stop at once: ENA 0 (IN1/IN2 left as they are); the
    /// ramp is reset to 0.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// use drivers::dc_motor::{Config, Output, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// // Backward full duty, then coast: only ENA changes.
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
    pub fn coast(&mut self) -> Result<(), Error<P::Error, I::Error>> {
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
    /// assert_eq!(motor.output(), Output::Coast);
    /// # let mut pins = motor.destroy();
    /// # pins.ena.done(); pins.in1.done(); pins.in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn output(&self) -> Output {
        self.output
    }

    /// The signed duty output now, ‰.
    ///
    /// ```
    /// # use drivers::dc_motor::l298n::{L298n, L298nPins};
    /// # use drivers::dc_motor::{Config, RestMode};
    /// # use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// # use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    /// # let pins = L298nPins { ena: Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]), in1: Pin::new(&[T::set(State::Low)]), in2: Pin::new(&[T::set(State::Low)]) };
    /// let motor = L298n::new(pins, Config { ramp_permille_per_ms: 2, rest: RestMode::Brake })?;
    /// assert_eq!(motor.duty_permille(), 0);
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
    /// next `poll` writes it again (each output is still written only when
    /// its recorded value differs, so the ones that succeeded are skipped).
    fn apply(&mut self, output: Output) -> Result<(), Error<P::Error, I::Error>> {
        self.pending = Some(output);
        self.write_output(output)?;
        self.pending = None;
        Ok(())
    }

    fn write_output(&mut self, output: Output) -> Result<(), Error<P::Error, I::Error>> {
        let (in1, in2, ena) = match output {
            Output::Forward(permille) => (true, false, duty_counts(permille, self.max_duty)),
            Output::Backward(permille) => (false, true, duty_counts(permille, self.max_duty)),
            Output::Brake => (false, false, self.max_duty),
            Output::Coast => {
                write_duty(&mut self.pins.ena, &mut self.last_ena, 0).map_err(Error::Pwm)?;
                self.output = output;
                return Ok(());
            }
        };
        let p = &mut self.pins;
        if self.last_in1 != Some(in1) || self.last_in2 != Some(in2) {
            // Bridge off while its inputs change; lows before highs.
            write_duty(&mut p.ena, &mut self.last_ena, 0).map_err(Error::Pwm)?;
            if !in1 {
                write_pin(&mut p.in1, &mut self.last_in1, false).map_err(Error::Pin)?;
            }
            if !in2 {
                write_pin(&mut p.in2, &mut self.last_in2, false).map_err(Error::Pin)?;
            }
            write_pin(&mut p.in1, &mut self.last_in1, in1).map_err(Error::Pin)?;
            write_pin(&mut p.in2, &mut self.last_in2, in2).map_err(Error::Pin)?;
        }
        write_duty(&mut p.ena, &mut self.last_ena, ena).map_err(Error::Pwm)?;
        self.output = output;
        Ok(())
    }
}
