//! A continuous-rotation servo with a quadrature encoder on its motor
//! shaft, seen through its PWM channel, its encoder lines (fed to a
//! `drivers::encoder::SharedEncoder` as an interrupt would, one Gray-code
//! edge at a time) and its home switch: the plant of the servo tests.
//!
//! Speed law: `sim::servo::ServoSpec` (the emulator's FS5106R model's):
//! zero within the dead band about neutral, then linear from the dead
//! band's edge to the no-load speed (at the motor) at the end of the
//! control range, the sign giving the direction (wider = positive). Its
//! hold after the last pulse does not come into play: the PWM channel
//! sends a pulse every frame. With `frame_s` the servo reads a new pulse
//! once per frame, as a hobby servo does at the start of each 50 Hz
//! period; without it, at once. Encoder edges: `sim::encoder`.

use std::cell::RefCell;
use std::convert::Infallible;
use std::rc::Rc;

use drivers::encoder::SharedEncoder;
use embedded_hal::digital::{ErrorType as PinErrorType, InputPin};
use embedded_hal::pwm::{ErrorType as PwmErrorType, SetDutyCycle};
use sim::encoder::QuadratureEncoder;
use sim::servo::{ServoSpec as SpeedLaw, FRAME_S};

/// What a servo and its mechanics are.
#[derive(Debug, Clone, Copy)]
pub struct ServoSpec {
    /// Pulse to motor speed.
    pub law: SpeedLaw,
    /// Motor turns per axis turn.
    pub gear: f64,
    /// Encoder edges per motor turn (four per line).
    pub edges_per_rev: u32,
    /// Pulse read once per frame of this length, seconds.
    pub frame_s: Option<f64>,
    /// The PWM channel's resolution: duty counts per µs of pulse.
    pub duty_per_us: f64,
}

impl ServoSpec {
    /// FEETECH FS5106R (Chowdhury et al. 2019): 1,500 µs stop, ±4 µs dead
    /// band, 95 rpm (570 °/s) at 700 / 2,300 µs, 50 Hz frames; a YMT22 of
    /// 300 lines (1,200 edges a turn) on its output shaft, which turns the
    /// axis directly; the channel counts 0.5 µs (Timer1 at clk/8).
    pub const FS5106R: ServoSpec = ServoSpec {
        law: SpeedLaw::FS5106R_6V,
        gear: 1.0,
        edges_per_rev: 1_200,
        frame_s: Some(FRAME_S),
        duty_per_us: 2.0,
    };

    /// Motor speed for a pulse, degrees per second.
    pub fn speed_deg_s(&self, pulse_us: f64) -> f64 {
        self.law.no_load_speed_deg_s(pulse_us)
    }

    /// The encoder on the motor shaft.
    pub fn encoder(&self) -> QuadratureEncoder {
        assert_eq!(self.edges_per_rev % 4, 0, "four edges a line");
        QuadratureEncoder::new(self.edges_per_rev / 4)
    }
}

/// The servo, its encoder and its axis.
#[derive(Debug)]
pub struct ServoModel {
    pub spec: ServoSpec,
    /// The pulse on the wire, µs.
    pub pulse_us: f64,
    /// The pulse the servo acts on (latched at each frame).
    pub acting_us: f64,
    frame_left_s: f64,
    pub min_pulse_us: f64,
    pub max_pulse_us: f64,
    /// Motor angle from the start, degrees.
    pub motor_deg: f64,
    /// Axis angle at the start, degrees (unknown to the controller).
    pub start_deg: f64,
    /// The home switch is closed at or below this axis angle; a hard stop
    /// 1° lower holds the axis.
    pub switch_deg: f64,
    /// Injected: the shaft is held (a jammed mechanism).
    pub stalled: bool,
}

impl ServoModel {
    pub fn new(spec: ServoSpec, start_deg: f64, switch_deg: f64) -> Rc<RefCell<ServoModel>> {
        Rc::new(RefCell::new(ServoModel {
            spec,
            pulse_us: spec.law.neutral_us,
            acting_us: spec.law.neutral_us,
            frame_left_s: 0.0,
            min_pulse_us: f64::MAX,
            max_pulse_us: 0.0,
            motor_deg: 0.0,
            start_deg,
            switch_deg,
            stalled: false,
        }))
    }

    /// The axis angle, degrees.
    pub fn output_deg(&self) -> f64 {
        self.start_deg + self.motor_deg / self.spec.gear
    }

    /// The encoder's count: whole edges of motor angle from the start.
    pub fn count(&self) -> i64 {
        self.spec.encoder().count_at(self.motor_deg)
    }

    /// The count the encoder shows as the home switch closes, coming down:
    /// the count just below the switch angle (one less than the count of
    /// an angle on a count's edge).
    pub fn switch_count(&self) -> i64 {
        let motor = (self.switch_deg - self.start_deg) * self.spec.gear;
        (motor * f64::from(self.spec.edges_per_rev) / 360.0).ceil() as i64 - 1
    }

    /// The axis angle as the encoder tells it from the switch, degrees:
    /// `home_deg` plus the counts since the switch's.
    pub fn decoded_deg(&self, home_deg: f64) -> f64 {
        let per_count = 360.0 / f64::from(self.spec.edges_per_rev) / self.spec.gear;
        home_deg + (self.count() - self.switch_count()) as f64 * per_count
    }

    /// Runs `dt_s` at the speed the servo acts on, feeding every encoder
    /// edge to `encoder`.
    pub fn advance(&mut self, dt_s: f64, encoder: &SharedEncoder) {
        match self.spec.frame_s {
            Some(frame) => {
                self.frame_left_s -= dt_s;
                if self.frame_left_s <= 0.0 {
                    self.acting_us = self.pulse_us;
                    self.frame_left_s += frame;
                }
            }
            None => self.acting_us = self.pulse_us,
        }
        let speed = if self.stalled {
            0.0
        } else {
            self.spec.speed_deg_s(self.acting_us)
        };
        let lowest_motor = (self.switch_deg - 1.0 - self.start_deg) * self.spec.gear;
        let new = (self.motor_deg + speed * dt_s).max(lowest_motor);
        for edge in self.spec.encoder().edges(self.motor_deg, new) {
            encoder.update(edge.a, edge.b);
        }
        self.motor_deg = new;
    }
}

/// The servo's PWM channel at 50 Hz.
pub struct Pwm(pub Rc<RefCell<ServoModel>>);

impl PwmErrorType for Pwm {
    type Error = Infallible;
}

impl SetDutyCycle for Pwm {
    fn max_duty_cycle(&self) -> u16 {
        (20_000.0 * self.0.borrow().spec.duty_per_us) as u16
    }
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Infallible> {
        let mut m = self.0.borrow_mut();
        m.pulse_us = f64::from(duty) / m.spec.duty_per_us;
        m.min_pulse_us = m.min_pulse_us.min(m.pulse_us);
        m.max_pulse_us = m.max_pulse_us.max(m.pulse_us);
        Ok(())
    }
}

/// The home switch: closed = high, or low with `active_low`.
pub struct Switch {
    pub model: Rc<RefCell<ServoModel>>,
    pub active_low: bool,
}

impl PinErrorType for Switch {
    type Error = Infallible;
}

impl InputPin for Switch {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        let m = self.model.borrow();
        Ok((m.output_deg() <= m.switch_deg) != self.active_low)
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        self.is_high().map(|h| !h)
    }
}
