//! The parts a board reads a linear actuator through
//! ([`crate::linear_actuator::LinearActuator`]), shared between the
//! firmware's ports and a test or a run: the H-bridge, the Hall pulse
//! counter, a switch at the retracted end, and the potentiometer on
//! a 10-bit ADC. For the core's [`suntracker::hw::LinearAxis`]; needs the
//! `std` feature (the ports share the actuator through `Rc`).
//!
//! * Hall: the model's pulses (an edge at each multiple of the pulse
//!   length) counted up or down by the bridge's last commanded direction,
//!   as a board's interrupt counts a single Hall output (it has no
//!   direction of its own); or, for a dual Hall pair in quadrature
//!   ([`ActuatorSpec::hall_quadrature`]), by the rod's own direction, as a
//!   quadrature decoder counts it. The count freezes while the sensor is
//!   failed.
//! * Potentiometer: the model's voltage (LINAK LA12 option K, 0.5–4.5 V
//!   over the stroke) plus Gaussian noise of [`PotAdc::noise_lsb`] counts
//!   rms, rounded to a 10-bit ADC at 5 V (0..=1023). The noise is an
//!   assumption: one count rms, of the order of the absolute accuracy of
//!   the 10-bit converters of the boards (a couple of counts), with a
//!   noisy 12 V motor supply beside the wiper lead.

use std::cell::RefCell;
use std::convert::Infallible;
use std::format;
use std::rc::Rc;
use std::string::String;

use drivers::adc::AdcChannel;
use drivers::dc_motor::{Bridge, Config as BridgeConfig, DcMotor as MotorDriver, Error, Output};
use drivers::linear::{ActuatorGeometry, LinearError, PotCalibration, PulseScale};
use embedded_hal::digital::{ErrorType, InputPin};
use suntracker::config::{AxisConfig, DriveKind};
use suntracker::hw::{
    DcAxisConfig, DcState, EncoderCount, HallFeedback, LinearAxis, LinearAxisConfig,
    LinearAxisError, NoCurrentSense, NoEndSwitch, PotConfig, PotError, PotFeedback,
};
use suntracker::motion::{AxisDrive, DriveFault};

use crate::dc_drive::{start_tick, DcDrive, DcDriveError};
use crate::linear_actuator::{ActuatorSpec, LinearActuator};
use crate::plant::{Injected, SimAxis};
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
    /// The rod is jammed: it moves no more, driven or not.
    pub jammed: bool,
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
            jammed: false,
        }))
    }

    /// Advances the actuator by `dt_s`, counting the Hall edges passed
    /// (a jammed rod stays put).
    pub fn step(&mut self, dt_s: f64) {
        let at = self.actuator.extension_mm();
        self.actuator.step(dt_s);
        if self.jammed {
            self.actuator.set_extension_mm(at);
        }
        self.count_edges_from(at);
    }

    /// An external force moves the rod to `extension_mm`; the counter
    /// counts the edges by the last commanded direction, right or wrong.
    pub fn slip_to(&mut self, extension_mm: f64) {
        let at = self.actuator.extension_mm();
        self.actuator.set_extension_mm(extension_mm);
        self.count_edges_from(at);
    }

    fn count_edges_from(&mut self, extension_mm: f64) {
        let mut was = self.actuator;
        was.set_extension_mm(extension_mm);
        let moved = self.actuator.hall_pulses() - was.hall_pulses();
        let edges = i32::try_from(moved.unsigned_abs()).unwrap_or(i32::MAX);
        // A quadrature pair has the rod's own direction.
        let dir = if self.actuator.spec().hall_quadrature {
            moved.signum() as i32
        } else {
            self.dir
        };
        self.count = self.count.saturating_add(edges.saturating_mul(dir));
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

/// The Hall pulse counter (a single output counted by the commanded
/// direction, a quadrature pair by the rod's).
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

/// The firmware's linear axis on Hall pulses over these ports.
pub type HallLinearAxis =
    LinearAxis<ActuatorBridge, HallFeedback<PulseCounter>, RetractedSwitch, NoCurrentSense>;

/// The firmware's linear axis on the potentiometer over these ports.
pub type PotLinearAxis =
    LinearAxis<ActuatorBridge, PotFeedback<PotAdc>, NoEndSwitch, NoCurrentSense>;

/// Errors of the simulated Hall axis (the ports never fail).
pub type HallLinearError =
    LinearAxisError<Infallible, Infallible, Infallible, Infallible, Infallible>;

/// Errors of the simulated potentiometer axis.
pub type PotLinearError =
    LinearAxisError<Infallible, Infallible, Infallible, Infallible, PotError<AdcFailed>>;

/// Errors of a [`LinearDrive`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearDriveError {
    /// Of the Hall axis.
    Hall(HallLinearError),
    /// Of the potentiometer axis.
    Pot(PotLinearError),
}

/// Which feedback the firmware reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeedbackKind {
    /// Hall pulses ([`HallFeedback`]) and the retracted-end switch.
    Hall,
    /// The potentiometer ([`PotFeedback`]), calibrated at the ends'
    /// nominal voltages.
    Pot,
}

/// How one linear axis is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearDriveSpec {
    /// The actuator's figures.
    pub actuator: ActuatorSpec,
    /// The feedback read.
    pub feedback: FeedbackKind,
    /// The mounting and the inner loop (in the feedback's counts).
    pub mount: LinearAxisConfig,
    /// How the potentiometer is read (with [`FeedbackKind::Pot`]).
    pub pot: PotConfig,
    /// The bridge driver's ramp and rest.
    pub bridge: BridgeConfig,
    /// ADC noise, counts rms.
    pub noise_lsb: f64,
    /// Seed of the ADC noise.
    pub seed: u64,
}

#[derive(Debug)]
enum Firmware {
    Hall(HallLinearAxis),
    Pot(PotLinearAxis),
}

/// One linear axis: the actuator and the firmware's [`LinearAxis`] over
/// it, polled every simulated millisecond while it moves (time at rest is
/// not stepped, as for [`crate::dc_drive::DcDrive`]).
#[derive(Debug)]
pub struct LinearDrive {
    hw: SharedActuator,
    fw: Firmware,
    spec: LinearDriveSpec,
    axis_config: AxisConfig,
    now_ms: u32,
    budget_ms: u32,
    travel_deg: f64,
}

fn build(
    hw: &SharedActuator,
    spec: &LinearDriveSpec,
    axis: &AxisConfig,
) -> Result<Firmware, String> {
    let motor = MotorDriver::new(ActuatorBridge(Rc::clone(hw)), spec.bridge)
        .map_err(|e| format!("bridge: {e:?}"))?;
    let a = &spec.actuator;
    match spec.feedback {
        FeedbackKind::Hall => {
            let scale = PulseScale::new((1.0 / a.mm_per_pulse) as f32)
                .map_err(|e| format!("pulse scale: {e}"))?;
            let feedback = HallFeedback::new(PulseCounter(Rc::clone(hw)), scale);
            let switch = RetractedSwitch(Rc::clone(hw));
            LinearAxis::new(motor, feedback, switch, false, None, spec.mount, axis)
                .map(Firmware::Hall)
                .map_err(|e| format!("linear axis: {e:?}"))
        }
        FeedbackKind::Pot => {
            let stroke_mm = a.stroke_mm as f32;
            let calibration = PotCalibration::new(
                adc_counts(a.pot_retracted_v),
                adc_counts(a.pot_extended_v),
                stroke_mm,
            )
            .map_err(|e| format!("potentiometer: {e}"))?;
            let pot = PotFeedback::new(PotAdc(Rc::clone(hw)), calibration, stroke_mm, spec.pot)
                .map_err(|e| format!("potentiometer: {e:?}"))?;
            LinearAxis::new(motor, pot, NoEndSwitch, false, None, spec.mount, axis)
                .map(Firmware::Pot)
                .map_err(|e| format!("linear axis: {e:?}"))
        }
    }
}

/// Calls `$f` on the firmware axis, whichever it is, mapping its error.
macro_rules! on_fw {
    ($fw:expr, $ax:ident => $e:expr) => {
        match $fw {
            Firmware::Hall($ax) => $e.map_err(LinearDriveError::Hall),
            Firmware::Pot($ax) => $e.map_err(LinearDriveError::Pot),
        }
    };
    ($fw:expr, $ax:ident -> $e:expr) => {
        match $fw {
            Firmware::Hall($ax) => $e,
            Firmware::Pot($ax) => $e,
        }
    };
}

impl LinearDrive {
    /// An axis of `spec` with the rod at `extension_mm`; `axis` is the
    /// controller's configuration of it.
    pub fn new(
        spec: LinearDriveSpec,
        axis: &AxisConfig,
        extension_mm: f64,
    ) -> Result<Self, String> {
        let actuator = LinearActuator::new(spec.actuator, extension_mm);
        let hw = ActuatorHardware::shared(actuator, spec.noise_lsb, spec.seed);
        Self::over(hw, spec, axis)
    }

    fn over(hw: SharedActuator, spec: LinearDriveSpec, axis: &AxisConfig) -> Result<Self, String> {
        let fw = build(&hw, &spec, axis)?;
        Ok(LinearDrive {
            hw,
            fw,
            spec,
            axis_config: *axis,
            now_ms: 0,
            budget_ms: 0,
            travel_deg: 0.0,
        })
    }

    /// The rod's extension, mm.
    pub fn extension_mm(&self) -> f64 {
        self.hw.borrow().actuator.extension_mm()
    }

    fn resting(&self) -> bool {
        on_fw!(&self.fw, ax -> {
            ax.feedback_lost()
                || matches!(ax.inner().state(), DcState::Idle { .. } | DcState::Faulted(_))
        })
    }

    fn step_ms(&mut self) {
        let now = self.now_ms;
        // Faults are kept by the axis for `take_fault`.
        on_fw!(&mut self.fw, ax -> { let _ = ax.poll(now); });
        let before = self.output_deg();
        self.hw.borrow_mut().step(1.0e-3);
        self.travel_deg += (self.output_deg() - before).abs();
        self.now_ms = self.now_ms.wrapping_add(1);
        self.budget_ms = self.budget_ms.saturating_sub(1);
    }

    fn run(&mut self) {
        // The spindle holds the rod the moment the bridge brakes.
        while self.budget_ms > 0 && !self.resting() {
            self.step_ms();
        }
    }
}

/// The same hardware after a power cycle: the rod where it is, the
/// firmware's axis new (its RAM, the Hall reference with it, is lost).
impl Clone for LinearDrive {
    fn clone(&self) -> Self {
        let hw = Rc::new(RefCell::new(self.hw.borrow().clone()));
        let mut copy = Self::over(hw, self.spec, &self.axis_config)
            .unwrap_or_else(|e| unreachable!("accepted when this drive was made: {e}"));
        copy.now_ms = self.now_ms;
        copy.travel_deg = self.travel_deg;
        copy
    }
}

impl AxisDrive for LinearDrive {
    type Error = LinearDriveError;
    const SELF_WATCHED: bool = true;
    fn move_counts(&mut self, counts: i32) -> Result<(), LinearDriveError> {
        on_fw!(&mut self.fw, ax => ax.move_counts(counts))?;
        self.run();
        Ok(())
    }
    fn pending(&self) -> i32 {
        on_fw!(&self.fw, ax -> ax.pending())
    }
    fn stop(&mut self) -> Result<(), LinearDriveError> {
        on_fw!(&mut self.fw, ax => ax.stop())?;
        self.run();
        Ok(())
    }
    fn at_limit(&mut self) -> Result<bool, LinearDriveError> {
        on_fw!(&mut self.fw, ax => ax.at_limit())
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, LinearDriveError> {
        on_fw!(&mut self.fw, ax => ax.encoder_deg())
    }
    fn take_fault(&mut self) -> Option<DriveFault> {
        on_fw!(&mut self.fw, ax -> ax.take_fault())
    }
    fn fault_latched(&self) -> bool {
        on_fw!(&self.fw, ax -> ax.fault_latched())
    }
    fn clear_fault(&mut self) {
        on_fw!(&mut self.fw, ax -> AxisDrive::clear_fault(ax));
    }
    fn switch_stops(&mut self, on: bool) {
        on_fw!(&mut self.fw, ax -> ax.switch_stops(on));
    }
    fn rebase_at_rest(&mut self) {
        on_fw!(&mut self.fw, ax -> ax.rebase_at_rest());
    }
}

impl SimAxis for LinearDrive {
    /// As [`DcDrive`]'s: the idle time passes on the axis's clock, one
    /// poll, then pending motion runs.
    fn begin_tick(&mut self, dt_s: f64) {
        let has_time = start_tick(&mut self.now_ms, &mut self.budget_ms, dt_s);
        if has_time {
            self.step_ms();
        }
        self.run();
    }
    /// The axis angle of the rod's extension.
    fn output_deg(&self) -> f64 {
        let hw = self.hw.borrow();
        // The model keeps the rod within the stroke, where every length
        // has an angle.
        hw.actuator
            .axis_deg(&self.spec.mount.geometry)
            .map_or(f64::NAN, f64::from)
    }
    fn travel_deg(&self) -> f64 {
        self.travel_deg
    }
    /// A stall or an obstruction jams the rod; a failed feedback is a
    /// Hall sensor that gives no more pulses, or a potentiometer's wiper
    /// that reads the upper rail.
    fn inject(&mut self, injected: Injected) {
        let mut hw = self.hw.borrow_mut();
        hw.jammed = injected.stalled || injected.obstructed;
        match self.spec.feedback {
            FeedbackKind::Hall => hw.actuator.set_hall_failed(injected.feedback_failed),
            FeedbackKind::Pot => {
                hw.adc_stuck = injected.feedback_failed.then_some(ADC_FULL_SCALE);
            }
        }
        hw.switch_stuck = if injected.switch_stuck_closed {
            Some(true)
        } else if injected.switch_stuck_open {
            Some(false)
        } else {
            None
        };
    }
    /// An external force turns the axis by `deg` (the spindle is
    /// self-locking; the event is a loose mounting).
    fn slip(&mut self, deg: f64) {
        let g = self.spec.mount.geometry;
        let to = (self.output_deg() + deg) as f32;
        let Ok(length) = g.length_mm(to) else {
            return;
        };
        let ext = f64::from(length - g.retracted_mm);
        let before = self.output_deg();
        self.hw.borrow_mut().slip_to(ext);
        self.travel_deg += (self.output_deg() - before).abs();
    }
}

/// A tracker with a slew drive on the C axis and a linear actuator on the
/// A axis (the whole-tracker run takes both axes of one type).
#[derive(Debug, Clone)]
pub enum SlewTilt {
    /// The C axis: a DC gear motor closed on its Hall count.
    Slew(DcDrive),
    /// The A axis: a linear actuator.
    Tilt(LinearDrive),
}

/// Errors of either axis of a [`SlewTilt`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlewTiltError {
    /// Of the slew drive.
    Slew(DcDriveError),
    /// Of the linear actuator.
    Tilt(LinearDriveError),
}

/// Calls `$e` on the axis, whichever it is.
macro_rules! on_axis {
    ($axis:expr, $ax:ident => $e:expr) => {
        match $axis {
            SlewTilt::Slew($ax) => $e.map_err(SlewTiltError::Slew),
            SlewTilt::Tilt($ax) => $e.map_err(SlewTiltError::Tilt),
        }
    };
    ($axis:expr, $ax:ident -> $e:expr) => {
        match $axis {
            SlewTilt::Slew($ax) => $e,
            SlewTilt::Tilt($ax) => $e,
        }
    };
}

impl AxisDrive for SlewTilt {
    type Error = SlewTiltError;
    const SELF_WATCHED: bool = true;
    fn move_counts(&mut self, counts: i32) -> Result<(), SlewTiltError> {
        on_axis!(self, ax => ax.move_counts(counts))
    }
    fn pending(&self) -> i32 {
        on_axis!(self, ax -> ax.pending())
    }
    fn stop(&mut self) -> Result<(), SlewTiltError> {
        on_axis!(self, ax => ax.stop())
    }
    fn at_limit(&mut self) -> Result<bool, SlewTiltError> {
        on_axis!(self, ax => ax.at_limit())
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, SlewTiltError> {
        on_axis!(self, ax => ax.encoder_deg())
    }
    fn take_fault(&mut self) -> Option<DriveFault> {
        on_axis!(self, ax -> ax.take_fault())
    }
    fn fault_latched(&self) -> bool {
        on_axis!(self, ax -> ax.fault_latched())
    }
    fn clear_fault(&mut self) {
        on_axis!(self, ax -> AxisDrive::clear_fault(ax));
    }
    fn rebase_counts(&mut self, counts: i32) {
        on_axis!(self, ax -> ax.rebase_counts(counts));
    }
    fn switch_stops(&mut self, on: bool) {
        on_axis!(self, ax -> ax.switch_stops(on));
    }
    fn rebase_at_rest(&mut self) {
        on_axis!(self, ax -> ax.rebase_at_rest());
    }
}

impl SimAxis for SlewTilt {
    fn begin_tick(&mut self, dt_s: f64) {
        on_axis!(self, ax -> ax.begin_tick(dt_s));
    }
    fn output_deg(&self) -> f64 {
        on_axis!(self, ax -> ax.output_deg())
    }
    fn travel_deg(&self) -> f64 {
        on_axis!(self, ax -> ax.travel_deg())
    }
    fn inject(&mut self, injected: Injected) {
        on_axis!(self, ax -> ax.inject(injected));
    }
    fn slip(&mut self, deg: f64) {
        on_axis!(self, ax -> ax.slip(deg));
    }
    fn set_supply_v(&mut self, supply_v: f64) {
        on_axis!(self, ax -> ax.set_supply_v(supply_v));
    }
}

/// The tilt (A) axis of `simulate --drive linear-hall|linear-pot`: an
/// LA12 of 100 mm stroke, 245 mm retracted (assumed, as
/// [`ActuatorGeometry::LA12_EXAMPLE`]), between pivots 237 mm and 110 mm
/// from the hinge: γ = acos((237² + 110² − L²) / (2 · 237 · 110)) runs
/// from 80.90° (L = 245) to 166.77° (L = 345), 85.9° of sweep, the most a
/// 345/245 length ratio gives with γ short of 170° (the panel's zenith
/// angle runs from about 0° to 90° while tracking, see the book's
/// Simulation chapter). The offset 172.90° puts the stroke at axis angles
/// −92.0° … −6.13°: the controller takes the mount's second solution
/// (C + 180°, −A), the horizon at the retracted end, where a mm is 0.5° of
/// tilt, and the zenith at the extended end, where it is 3.3°.
pub const LA12_TILT_MOUNT: ActuatorGeometry = ActuatorGeometry {
    a_mm: 237.0,
    b_mm: 110.0,
    offset_deg: 172.9,
    retracted_mm: 245.0,
    stroke_mm: 100.0,
};

/// The inner loop on Hall pulses (counts of half a pulse, 2 a mm): full
/// duty beyond 5 mm, 40 % at the target (10.4 mm/s free); done on the
/// target's edge; the spindle stops the rod when braked (no stopping
/// lead); stall after 1 s without a pulse (a pulse every 0.1 s at 40 %);
/// two pulses at rest are unexpected motion; an approach slower than
/// 5 mm/s (a third of the 14 mm/s at rated load) plus 3 s is too slow.
pub const LA12_HALL_LOOP: DcAxisConfig = DcAxisConfig {
    max_duty_permille: 1_000,
    min_duty_permille: 400,
    slow_band_counts: 10,
    deadband_counts: 1,
    brake_lead_ms: 0,
    settle_ms: 100,
    max_reapproaches: 2,
    stall_ms: 1_000,
    drive_threshold_permille: 100,
    max_idle_counts: 4,
    // No current sense: the watch is the pulses'.
    max_current_ma: 6_000,
    overcurrent_ms: 200,
    min_speed_cps: 10,
    move_margin_ms: 3_000,
};

/// The same on [`ActuatorSpec::LA12_DUAL_HALL_12V`]'s quadrature pair
/// (counts of half a state shift, 10.67 a mm): the same distances and
/// speeds in its counts (full duty beyond 5 mm, 2 mm at rest unexpected,
/// slower than 5 mm/s too slow); a shift every 18 ms at 40 %.
pub const LA12_DUAL_HALL_LOOP: DcAxisConfig = DcAxisConfig {
    slow_band_counts: 53,
    max_idle_counts: 21,
    min_speed_cps: 53,
    ..LA12_HALL_LOOP
};

/// The same on the potentiometer (tenths of a mm): done within 0.1 mm
/// (0.33° at the extended end: under the 0.5° command after which the
/// controller expects the encoder to move), 2 mm at rest is unexpected
/// motion, slower than 5 mm/s too slow.
pub const LA12_POT_LOOP: DcAxisConfig = DcAxisConfig {
    slow_band_counts: 50,
    deadband_counts: 1,
    max_idle_counts: 20,
    min_speed_cps: 50,
    ..LA12_HALL_LOOP
};

/// Sixteen conversions a poll (one count rms of noise becomes a quarter,
/// 0.03 mm), a hysteresis of 0.1 mm, readings within 8 counts outside the
/// span taken as the end.
pub const LA12_POT_READING: PotConfig = PotConfig {
    samples: 16,
    hysteresis_mm: 0.1,
    end_margin_counts: 8,
};

/// [`LA12_TILT_MOUNT`]'s A axis on `feedback` as the controller sees it:
/// 100 counts a degree, limits at the stroke's ends (homed at the
/// retracted end; on Hall pulses at the first edge above the switch,
/// 0.1875 mm out), no backlash.
pub fn la12_tilt_axis_config(feedback: FeedbackKind) -> Result<AxisConfig, LinearError> {
    let g = LA12_TILT_MOUNT;
    let lo = g.axis_deg(g.retracted_mm)?;
    let hi = g.axis_deg(g.retracted_mm + g.stroke_mm)?;
    let home = match feedback {
        FeedbackKind::Hall => {
            let first_edge_mm = ActuatorSpec::LA12_DUAL_HALL_12V.mm_per_pulse as f32;
            g.axis_deg(g.retracted_mm + first_edge_mm)?
        }
        FeedbackKind::Pot => lo,
    };
    Ok(AxisConfig {
        counts_per_motor_rev: 36_000,
        microsteps: 1,
        gear_ratio: 1.0,
        min_deg: lo,
        max_deg: hi,
        home_deg: home,
        backlash_deg: 0.0,
        max_speed_deg_s: 10.0,
        deadband_deg: 0.05,
        continuous: 0,
        drive: match feedback {
            FeedbackKind::Hall => DriveKind::LinearHall,
            FeedbackKind::Pot => DriveKind::LinearPot,
        } as u8,
        max_current_ma: LA12_HALL_LOOP.max_current_ma as u16,
        overcurrent_ms: LA12_HALL_LOOP.overcurrent_ms as u16,
        back_speed_deg_s: 10.0,
        // The mount and the feedback's scale as the configuration's keys
        // give them (`axis.a.pivot_a_mm` … `pot_extended_counts`).
        #[cfg(feature = "linear")]
        linear: suntracker::config::LinearMount {
            pivot_a_mm: g.a_mm,
            pivot_b_mm: g.b_mm,
            pivot_offset_deg: g.offset_deg,
            retracted_mm: g.retracted_mm,
            stroke_mm: g.stroke_mm,
            pulses_per_mm: (1.0 / ActuatorSpec::LA12_DUAL_HALL_12V.mm_per_pulse) as f32,
            pot_retracted_counts: adc_counts(ActuatorSpec::LA12_L1_12V.pot_retracted_v),
            pot_extended_counts: adc_counts(ActuatorSpec::LA12_L1_12V.pot_extended_v),
        },
    })
}

/// The A axis of `simulate` on [`LA12_TILT_MOUNT`]: on Hall pulses
/// [`ActuatorSpec::LA12_DUAL_HALL_12V`] (homed at its first state shift
/// above the switch), on the potentiometer [`ActuatorSpec::LA12_L1_12V`];
/// the bridge ramping 5 ‰/ms and braking at rest, one count rms of ADC
/// noise drawn from `seed`.
pub fn la12_tilt_spec(feedback: FeedbackKind, seed: u64) -> LinearDriveSpec {
    let (actuator, switch_extension_mm, end_tolerance_mm, loop_config) = match feedback {
        FeedbackKind::Hall => {
            let a = ActuatorSpec::LA12_DUAL_HALL_12V;
            (a, a.mm_per_pulse as f32, 0.0, LA12_DUAL_HALL_LOOP)
        }
        // An ADC count is 0.12 mm, the hysteresis 0.1 mm.
        FeedbackKind::Pot => (ActuatorSpec::LA12_L1_12V, 0.0, 0.3, LA12_POT_LOOP),
    };
    LinearDriveSpec {
        actuator,
        feedback,
        mount: LinearAxisConfig {
            geometry: LA12_TILT_MOUNT,
            switch_extension_mm,
            end_tolerance_mm,
            loop_config,
        },
        pot: LA12_POT_READING,
        bridge: BridgeConfig {
            ramp_permille_per_ms: 5,
            rest: drivers::dc_motor::RestMode::Brake,
        },
        noise_lsb: 1.0,
        seed,
    }
}
