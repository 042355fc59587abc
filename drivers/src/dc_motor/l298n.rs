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

use super::{duty_counts, write_duty, write_pin, Bridge, DcMotor, Error, Output};

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

/// A DC motor on one bridge of an L298N: [`DcMotor`] over [`L298nPins`],
/// so `L298n::new(pins, config)` and the commands of [`DcMotor`].
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
/// let mut motor: L298n<_, _> = L298n::new(pins, Config { ramp_permille_per_ms: 0, rest: RestMode::Coast })?;
/// motor.set_duty(0.4)?;
/// assert_eq!(motor.poll(0)?, Output::Forward(400));
/// motor.destroy();
/// ena.done();
/// in1.done();
/// in2.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub type L298n<P, I> = DcMotor<L298nPins<P, I>>;

/// What an L298N bridge keeps between writes: ENA's max duty and the value
/// last written to each input (`None`: unknown, written next time).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct L298nState {
    max_duty: u16,
    last_ena: Option<u16>,
    last_in1: Option<bool>,
    last_in2: Option<bool>,
}

impl<P: SetDutyCycle, I: OutputPin> Bridge for L298nPins<P, I> {
    type PwmError = P::Error;
    type PinError = I::Error;
    type State = L298nState;

    /// Reads ENA's max duty, then coasts: ENA 0, IN1 and IN2 low.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::L298nPins;
    /// use drivers::dc_motor::{Bridge, Error};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// let mut ena = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]);
    /// let mut in1 = Pin::new(&[T::set(State::Low)]);
    /// let mut in2 = Pin::new(&[T::set(State::Low)]);
    /// let mut pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
    /// pins.init()?;
    /// // A channel with max duty 0 is refused before any write.
    /// let mut zero = L298nPins { ena: Pwm::new(&[P::max_duty_cycle(0)]), in1: Pin::new(&[]), in2: Pin::new(&[]) };
    /// assert_eq!(zero.init().unwrap_err(), Error::InvalidConfig);
    /// zero.ena.done();
    /// zero.in1.done();
    /// zero.in2.done();
    /// ena.done();
    /// in1.done();
    /// in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn init(&mut self) -> Result<L298nState, Error<P::Error, I::Error>> {
        let max_duty = self.ena.max_duty_cycle();
        if max_duty == 0 {
            return Err(Error::InvalidConfig);
        }
        let mut s = L298nState {
            max_duty,
            last_ena: None,
            last_in1: None,
            last_in2: None,
        };
        write_duty(&mut self.ena, &mut s.last_ena, 0).map_err(Error::Pwm)?;
        write_pin(&mut self.in1, &mut s.last_in1, false).map_err(Error::Pin)?;
        write_pin(&mut self.in2, &mut s.last_in2, false).map_err(Error::Pin)?;
        Ok(s)
    }

    /// Forward: IN1 high, IN2 low, ENA the duty; backward the mirror; brake
    /// (fast motor stop): IN1 = IN2 = low, ENA full; coast (free running
    /// stop): ENA 0, IN1/IN2 left as they are. When IN1/IN2 change, ENA
    /// goes to 0 first, then the input going low, then the one going high.
    ///
    /// ```
    /// use drivers::dc_motor::l298n::L298nPins;
    /// use drivers::dc_motor::{Bridge, Output};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// // Forward 20 % on 8 bits (round(51) = 51), then backward 60 %
    /// // (round(153) = 153): ENA 0, IN1 low, IN2 high, ENA 153.
    /// let mut ena = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0), P::set_duty_cycle(51), P::set_duty_cycle(0), P::set_duty_cycle(153)]);
    /// let mut in1 = Pin::new(&[T::set(State::Low), T::set(State::High), T::set(State::Low)]);
    /// let mut in2 = Pin::new(&[T::set(State::Low), T::set(State::High)]);
    /// let mut pins = L298nPins { ena: ena.clone(), in1: in1.clone(), in2: in2.clone() };
    /// let mut state = pins.init()?;
    /// pins.apply(&mut state, Output::Forward(200))?;
    /// pins.apply(&mut state, Output::Backward(600))?;
    /// ena.done();
    /// in1.done();
    /// in2.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn apply(
        &mut self,
        s: &mut L298nState,
        output: Output,
    ) -> Result<(), Error<P::Error, I::Error>> {
        let (in1, in2, ena) = match output {
            Output::Forward(permille) => (true, false, duty_counts(permille, s.max_duty)),
            Output::Backward(permille) => (false, true, duty_counts(permille, s.max_duty)),
            Output::Brake => (false, false, s.max_duty),
            Output::Coast => {
                return write_duty(&mut self.ena, &mut s.last_ena, 0).map_err(Error::Pwm);
            }
        };
        if s.last_in1 != Some(in1) || s.last_in2 != Some(in2) {
            // Bridge off while its inputs change; lows before highs.
            write_duty(&mut self.ena, &mut s.last_ena, 0).map_err(Error::Pwm)?;
            if !in1 {
                write_pin(&mut self.in1, &mut s.last_in1, false).map_err(Error::Pin)?;
            }
            if !in2 {
                write_pin(&mut self.in2, &mut s.last_in2, false).map_err(Error::Pin)?;
            }
            write_pin(&mut self.in1, &mut s.last_in1, in1).map_err(Error::Pin)?;
            write_pin(&mut self.in2, &mut s.last_in2, in2).map_err(Error::Pin)?;
        }
        write_duty(&mut self.ena, &mut s.last_ena, ena).map_err(Error::Pwm)
    }
}
