//! The parts a board reads a linear actuator through
//! ([`crate::linear_actuator::LinearActuator`]), shared between the
//! firmware's ports and a test or a run: the H-bridge, the single-Hall
//! pulse counter, a switch at the retracted end, and the potentiometer on
//! a 10-bit ADC. For the core's [`suntracker::hw::LinearAxis`]; needs the
//! `std` feature (the ports share the actuator through `Rc`).
//!
//! * Hall: the model's pulses (an edge at each multiple of the pulse
//!   length) counted up or down by the bridge's last commanded direction,
//!   as a board's interrupt counts a single Hall output (it has no
//!   direction of its own). The count freezes while the sensor is failed.
//! * Potentiometer: the model's voltage (LINAK LA12 option K, 0.5–4.5 V
//!   over the stroke) plus Gaussian noise of [`PotAdc::noise_lsb`] counts
//!   rms, rounded to a 10-bit ADC at 5 V (0..=1023). The noise is an
//!   assumption: one count rms, of the order of the absolute accuracy of
//!   the 10-bit converters of the boards (a couple of counts), with a
//!   noisy 12 V motor supply beside the wiper lead.

use std::cell::RefCell;
use std::convert::Infallible;
use std::rc::Rc;

use drivers::adc::AdcChannel;
use drivers::dc_motor::{Bridge, Error, Output};
use embedded_hal::digital::{ErrorType, InputPin};
use suntracker::hw::EncoderCount;

use crate::linear_actuator::LinearActuator;
use crate::rng::SplitMix64;

/// ADC full scale (10 bits) and reference, V.
pub const ADC_FULL_SCALE: u16 = 1_023;
/// The ADC's reference, V.
pub const ADC_VREF_V: f64 = 5.0;

/// An actuator and what its sensors have counted.
#[derive(Debug, Clone)]
pub struct ActuatorHardware {
    /// The actuator model.
    pub actuator: LinearActuator,
    /// Last commanded direction: +1 extending, −1 retracting.
    dir: i32,
    /// Hall edges counted by direction.
    count: i32,
    /// ADC noise, counts rms.
    noise_lsb: f64,
    rng: SplitMix64,
    /// The ADC fails every conversion.
    pub adc_fails: bool,
    /// The ADC reads this count (a broken wiper at a rail).
    pub adc_stuck: Option<u16>,
    /// The retracted-end switch reads closed / never closes.
    pub switch_stuck: Option<bool>,
}

/// The shared hardware.
pub type SharedActuator = Rc<RefCell<ActuatorHardware>>;

impl ActuatorHardware {
    /// `actuator` with ADC noise of `noise_lsb` counts rms drawn from
    /// `seed`; the counter at 0.
    pub fn shared(actuator: LinearActuator, noise_lsb: f64, seed: u64) -> SharedActuator {
        Rc::new(RefCell::new(ActuatorHardware {
            actuator,
            dir: 1,
            count: 0,
            noise_lsb: if noise_lsb.is_finite() {
                noise_lsb.max(0.0)
            } else {
                0.0
            },
            rng: SplitMix64::new(seed),
            adc_fails: false,
            adc_stuck: None,
            switch_stuck: None,
        }))
    }

    /// Advances the actuator by `dt_s`, counting the Hall edges passed.
    pub fn step(&mut self, dt_s: f64) {
        let before = self.actuator.hall_pulses();
        self.actuator.step(dt_s);
        let edges = (self.actuator.hall_pulses() - before).unsigned_abs();
        let edges = i32::try_from(edges).unwrap_or(i32::MAX);
        self.count = self.count.saturating_add(edges.saturating_mul(self.dir));
    }

    /// The potentiometer's reading now (noise drawn), counts.
    fn pot_counts(&mut self) -> u16 {
        let v = self.actuator.pot_voltage_v();
        let raw = v / ADC_VREF_V * f64::from(ADC_FULL_SCALE) + self.rng.normal(self.noise_lsb);
        libm::round(raw.clamp(0.0, f64::from(ADC_FULL_SCALE))) as u16
    }
}

/// The H-bridge: its output goes to the actuator.
#[derive(Debug)]
pub struct ActuatorBridge(pub SharedActuator);

impl Bridge for ActuatorBridge {
    type PwmError = Infallible;
    type PinError = Infallible;
    type State = ();
    fn init(&mut self) -> Result<(), Error<Infallible, Infallible>> {
        self.0.borrow_mut().actuator.set_output(Output::Coast);
        Ok(())
    }
    fn apply(&mut self, _: &mut (), output: Output) -> Result<(), Error<Infallible, Infallible>> {
        let mut hw = self.0.borrow_mut();
        match output {
            Output::Forward(_) => hw.dir = 1,
            Output::Backward(_) => hw.dir = -1,
            Output::Brake | Output::Coast => {}
        }
        hw.actuator.set_output(output);
        Ok(())
    }
}

/// The Hall pulse counter (counted by the commanded direction).
#[derive(Debug)]
pub struct PulseCounter(pub SharedActuator);

impl EncoderCount for PulseCounter {
    fn count(&self) -> i32 {
        self.0.borrow().count
    }
}

/// A switch closed with the rod fully retracted (active high).
#[derive(Debug)]
pub struct RetractedSwitch(pub SharedActuator);

impl ErrorType for RetractedSwitch {
    type Error = Infallible;
}

impl InputPin for RetractedSwitch {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        let hw = self.0.borrow();
        Ok(hw.switch_stuck.unwrap_or(hw.actuator.extension_mm() <= 0.0))
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        self.is_high().map(|h| !h)
    }
}

/// The ADC failed a conversion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AdcFailed;

/// The potentiometer on a 10-bit ADC at 5 V, with noise.
#[derive(Debug)]
pub struct PotAdc(pub SharedActuator);

impl PotAdc {
    /// The noise, counts rms.
    pub fn noise_lsb(&self) -> f64 {
        self.0.borrow().noise_lsb
    }
}

impl AdcChannel for PotAdc {
    type Error = AdcFailed;
    fn read_raw(&mut self) -> Result<u16, AdcFailed> {
        let mut hw = self.0.borrow_mut();
        if hw.adc_fails {
            return Err(AdcFailed);
        }
        Ok(match hw.adc_stuck {
            Some(raw) => raw,
            None => hw.pot_counts(),
        })
    }
    fn full_scale(&self) -> u16 {
        ADC_FULL_SCALE
    }
}

/// The potentiometer's counts at `volts` on this ADC, rounded: the
/// calibration a board would measure at the ends without noise.
pub fn adc_counts(volts: f64) -> u16 {
    libm::round((volts / ADC_VREF_V * f64::from(ADC_FULL_SCALE)).clamp(0.0, 1_023.0)) as u16
}
