//! A tracker axis on a DC gear motor, as the firmware drives it: the core's
//! [`DcAxis`] (position loop, Hall stall watch, current watch) over the
//! motor model of [`crate::dc_motor`], with a Hall counter, a home switch
//! and a BTS7960 current sense on a 10-bit ADC at 5 V. For whole-tracker
//! runs (`examples/simulate.rs --drive dc-hall`); needs the `std` feature
//! (the axis and the test harness share the motor through `Rc`).
//!
//! Time advances as for [`crate::plant::MotorPlant`]:
//! [`SimAxis::begin_tick`] gives the axis `dt` seconds; a move runs at
//! once, [`DcAxis::poll`] every simulated millisecond over
//! [`STEPS_PER_MS`] backward-Euler steps of the model, until the loop
//! rests and the motor stands still or the tick's time is spent (the rest
//! of the move then runs in the next tick). Time the axis spends at rest is
//! not stepped: the first poll of the next tick is that much later on the
//! axis's millisecond clock.
//!
//! The Hall counter is the model's quadrature count (every edge counted, as
//! an interrupt-driven decoder counts them); it freezes while the sensor is
//! failed.

use std::cell::RefCell;
use std::convert::Infallible;
use std::rc::Rc;

use drivers::adc::AdcChannel;
use drivers::dc_motor::bts7960::{CurrentSense, SenseConfig, SenseError};
use drivers::dc_motor::{Bridge, Config as BridgeConfig, DcMotor as MotorDriver, Error, Output};
use embedded_hal::digital::{ErrorType, InputPin};
use suntracker::config::AxisConfig;
use suntracker::hw::{
    DcAxis, DcAxisConfig, DcAxisConfigError, DcAxisError, DcState, EncoderCount, TimedAxis,
    TimedAxisConfig, TimedAxisConfigError, TimedAxisError,
};
use suntracker::motion::{AxisDrive, DriveFault};

use crate::dc_motor::{Bts7960Sense, DcMotor, MotorSpec};
use crate::plant::{Injected, SimAxis};

/// Model steps per millisecond poll: 0.25 ms each, about half the Pololu
/// preset's electrical time constant τ_e = 0.46 ms. Backward Euler is
/// stable at any step (see [`crate::dc_motor`]); at this one a current
/// step's response is 55 % of its final value after τ_e instead of 63 %,
/// and 98.2 % instead of 99.3 % after 5 τ_e (2.3 ms): a lag of a
/// millisecond or two against the overcurrent watch's 100 ms. The
/// mechanical time constant (0.12 s) is 480 steps.
pub const STEPS_PER_MS: u32 = 4;
const STEP_S: f64 = 1e-3 / STEPS_PER_MS as f64;
/// Below this motor speed, braked, the motor is taken to stand still,
/// rad/s: what is left of its run-down, speed × the braked mechanical time
/// constant (0.12 s for [`MotorSpec::pololu_37d_131_12v`] with a load), is
/// 0.06 rad, under a Hall count (2π/64 = 0.098 rad), and is not stepped.
const AT_REST_RAD_S: f64 = 0.5;
/// ADC of the current sense: full scale and reference.
const ADC_FULL_SCALE: u16 = 1_023;
const ADC_VREF_V: f64 = 5.0;

/// The slew axis of the host tests and `simulate`: the Pololu 37D 131.25:1
/// gear motor at 12 V with its 64-count motor-shaft Hall encoder
/// ([`MotorSpec::pololu_37d_131_12v`]), through a further 60:1 stage of
/// 40 % efficiency (the illustrative worm figures of [`crate::dc_motor`]'s
/// own further-stage test, not a product's; a slew drive's single worm is of
/// that order): 131.25 × 60 = 7,875:1 in all ([`WORM_SLEW_GEAR_RATIO`]),
/// 64 × 7,875 = 504,000 Hall counts per output turn (1,400 a degree), at
/// most 10,000 rpm / 7,875 = 1.27 rpm = 7.62 °/s. The axis and panels add
/// 50 kg·m² at the output (assumed).
pub fn worm_slew_motor() -> MotorSpec {
    MotorSpec::pololu_37d_131_12v()
        .with_output_stage(60.0, 0.4)
        .with_output_inertia_kg_m2(50.0)
}

/// [`worm_slew_motor`]'s gear ratio, for `AxisConfig::gear_ratio` (with 64
/// counts per motor revolution and no microsteps).
pub const WORM_SLEW_GEAR_RATIO: f32 = 7_875.0;

/// The controller's configuration of a [`worm_slew_motor`] axis over
/// `min_deg..=max_deg`, homed at `min_deg`: 64 counts a motor turn,
/// 7,875:1 (1,400 counts a degree), no backlash, 7 °/s, deadband 0.05°.
pub fn worm_slew_axis_config(min_deg: f32, max_deg: f32) -> AxisConfig {
    AxisConfig {
        counts_per_motor_rev: 64,
        microsteps: 1,
        gear_ratio: WORM_SLEW_GEAR_RATIO,
        min_deg,
        max_deg,
        home_deg: min_deg,
        backlash_deg: 0.0,
        max_speed_deg_s: 7.0,
        deadband_deg: 0.05,
        continuous: 0,
        drive: suntracker::config::DriveKind::DcHall as u8,
        max_current_ma: WORM_SLEW_LOOP.max_current_ma as u16,
        overcurrent_ms: WORM_SLEW_LOOP.overcurrent_ms as u16,
        back_speed_deg_s: 7.0,
        #[cfg(feature = "linear")]
        linear: suntracker::config::LinearMount::DEFAULT,
    }
}

/// The position loop and watch of [`worm_slew_motor`]'s axis, the core's
/// [`suntracker::mechanics::WORM_SLEW_LOOP`] (a Mega's DC axis on this drive runs
/// the same).
pub use suntracker::mechanics::WORM_SLEW_LOOP;

/// The hardware one axis shares between the firmware's ports and the run.
#[derive(Debug, Clone, Copy)]
struct Hardware {
    motor: DcMotor,
    /// The home switch closes at or below this output angle, degrees.
    switch_deg: f64,
    /// The mechanical end stops, degrees.
    ends_deg: (f64, f64),
    injected: Injected,
}

impl Hardware {
    fn switch_closed(&self) -> bool {
        self.injected.switch_stuck_closed
            || (!self.injected.switch_stuck_open
                && self.motor.output_angle_deg() <= self.switch_deg)
    }
}

type Shared = Rc<RefCell<Hardware>>;

/// The H-bridge: its output goes to the motor model.
#[derive(Debug)]
pub struct SimBridge(Shared);

impl Bridge for SimBridge {
    type PwmError = Infallible;
    type PinError = Infallible;
    type State = ();
    fn init(&mut self) -> Result<(), Error<Infallible, Infallible>> {
        self.0.borrow_mut().motor.set_output(Output::Coast);
        Ok(())
    }
    fn apply(&mut self, _: &mut (), output: Output) -> Result<(), Error<Infallible, Infallible>> {
        self.0.borrow_mut().motor.set_output(output);
        Ok(())
    }
}

/// The Hall counter.
#[derive(Debug)]
pub struct SimHall(Shared);

impl EncoderCount for SimHall {
    fn count(&self) -> i32 {
        let c = self.0.borrow().motor.hall_count();
        i32::try_from(c).unwrap_or(if c < 0 { i32::MIN } else { i32::MAX })
    }
}

/// The home switch (active high).
#[derive(Debug)]
pub struct SimSwitch(Shared);

impl ErrorType for SimSwitch {
    type Error = Infallible;
}

impl InputPin for SimSwitch {
    fn is_high(&mut self) -> Result<bool, Infallible> {
        Ok(self.0.borrow().switch_closed())
    }
    fn is_low(&mut self) -> Result<bool, Infallible> {
        Ok(!self.0.borrow().switch_closed())
    }
}

/// The BTS7960's IS pin on a 10-bit ADC at 5 V (data-sheet sense ratio,
/// 1 kΩ: [`Bts7960Sense::TYPICAL_1K_5V`]).
#[derive(Debug)]
pub struct SimIsPin(Shared);

impl AdcChannel for SimIsPin {
    type Error = Infallible;
    fn read_raw(&mut self) -> Result<u16, Infallible> {
        let m = self.0.borrow().motor;
        Ok(Bts7960Sense::TYPICAL_1K_5V.adc_counts(
            m.output(),
            m.current_a(),
            ADC_VREF_V,
            ADC_FULL_SCALE,
        ))
    }
    fn full_scale(&self) -> u16 {
        ADC_FULL_SCALE
    }
}

/// The firmware's Hall-closed axis over the simulated parts.
pub type SimDcAxis = DcAxis<SimBridge, SimHall, SimSwitch, CurrentSense<SimIsPin>>;

/// The firmware's timed axis (no feedback) over the simulated parts.
pub type SimTimedAxis = TimedAxis<SimBridge, SimSwitch, CurrentSense<SimIsPin>>;

/// Errors of the simulated Hall-closed drive (the ports themselves never
/// fail).
pub type DcDriveError = DcAxisError<Infallible, Infallible, Infallible, SenseError<Infallible>>;

/// The simulated parts one axis's firmware is built over.
#[derive(Debug)]
pub struct Ports {
    /// The bridge driver over the simulated bridge.
    pub motor: MotorDriver<SimBridge>,
    /// The Hall counter.
    pub hall: SimHall,
    /// The home switch.
    pub switch: SimSwitch,
    /// The BTS7960's current sense on its ADC channel, at the data sheet's
    /// ratio.
    pub sense: CurrentSense<SimIsPin>,
}

/// A firmware axis a simulated DC drive runs: built over the [`Ports`],
/// polled every simulated millisecond.
pub trait FirmwareAxis: AxisDrive + Sized {
    /// Its settings.
    type Config: Copy + core::fmt::Debug + PartialEq;
    /// Why the settings are refused.
    type ConfigError: core::fmt::Debug;
    /// The axis over `ports`.
    fn build(
        ports: Ports,
        config: Self::Config,
        axis: &AxisConfig,
    ) -> Result<Self, Self::ConfigError>;
    /// One main-loop pass at `now_ms`.
    fn poll_ms(&mut self, now_ms: u32);
    /// True when the axis has nothing more to do until the next command.
    fn resting(&self) -> bool;
    /// The motor supply as the board measures it, mV; the default ignores
    /// it.
    fn supply_measured(&mut self, supply_mv: u32) {
        let _ = supply_mv;
    }
}

impl FirmwareAxis for SimDcAxis {
    type Config = DcAxisConfig;
    type ConfigError = DcAxisConfigError;
    fn build(
        ports: Ports,
        config: DcAxisConfig,
        axis: &AxisConfig,
    ) -> Result<Self, DcAxisConfigError> {
        DcAxis::new(
            ports.motor,
            ports.hall,
            ports.switch,
            false,
            Some(ports.sense),
            config,
            axis,
        )
    }
    fn poll_ms(&mut self, now_ms: u32) {
        // Faults are kept by the axis for `take_fault`; the ports never
        // fail.
        let _ = self.poll(now_ms);
    }
    fn resting(&self) -> bool {
        matches!(self.state(), DcState::Idle { .. } | DcState::Faulted(_))
    }
}

impl FirmwareAxis for SimTimedAxis {
    type Config = TimedAxisConfig;
    type ConfigError = TimedAxisConfigError;
    fn build(
        ports: Ports,
        config: TimedAxisConfig,
        axis: &AxisConfig,
    ) -> Result<Self, TimedAxisConfigError> {
        TimedAxis::new(
            ports.motor,
            ports.switch,
            false,
            Some(ports.sense),
            config,
            axis,
        )
    }
    fn poll_ms(&mut self, now_ms: u32) {
        // The ports never fail.
        let _ = self.poll(now_ms);
    }
    fn resting(&self) -> bool {
        self.pending() == 0
    }
    fn supply_measured(&mut self, supply_mv: u32) {
        self.set_supply_mv(supply_mv);
    }
}

/// How one DC axis is built: the motor, the bridge, the firmware's
/// settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DcDriveSpec<C> {
    /// The gear motor and its stages.
    pub motor: MotorSpec,
    /// The bridge driver's ramp and rest.
    pub bridge: BridgeConfig,
    /// The firmware axis's settings.
    pub firmware: C,
}

/// One DC axis: the motor model and the firmware's axis over it
/// ([`SimDcAxis`] by default, or [`SimTimedAxis`]).
pub struct DcDrive<A: FirmwareAxis = SimDcAxis> {
    hw: Shared,
    axis: A,
    spec: DcDriveSpec<A::Config>,
    axis_config: AxisConfig,
    /// The axis's millisecond clock (its board's monotonic counter).
    now_ms: u32,
    /// Milliseconds left in this tick.
    budget_ms: u32,
    travel_deg: f64,
    /// A main-loop pass with no poll: from this ms of the axis's clock,
    /// for this many.
    long_pass: Option<(u32, u32)>,
}

impl<A: FirmwareAxis + core::fmt::Debug> core::fmt::Debug for DcDrive<A> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("DcDrive")
            .field("output_deg", &self.hw.borrow().motor.output_angle_deg())
            .field("axis", &self.axis)
            .finish_non_exhaustive()
    }
}

impl<A: FirmwareAxis> DcDrive<A> {
    /// An axis at `start_deg` whose home switch closes at or below
    /// `switch_deg`, with hard stops 1° beyond the switch and at `max_deg` +
    /// 1° (as [`crate::plant::MotorPlant`]'s); `axis` gives the firmware's
    /// counts per degree and home angle.
    pub fn new(
        spec: DcDriveSpec<A::Config>,
        axis: &AxisConfig,
        switch_deg: f64,
        max_deg: f64,
        start_deg: f64,
    ) -> Result<Self, A::ConfigError> {
        let mut motor = DcMotor::new(spec.motor);
        motor.set_output_angle_deg(start_deg);
        let ends_deg = (switch_deg - 1.0, max_deg + 1.0);
        motor.set_hard_stops_deg(Some(ends_deg));
        Self::over(
            Hardware {
                motor,
                switch_deg,
                ends_deg,
                injected: Injected::default(),
            },
            spec,
            axis,
        )
    }

    fn over(
        hw: Hardware,
        spec: DcDriveSpec<A::Config>,
        axis: &AxisConfig,
    ) -> Result<Self, A::ConfigError> {
        let hw = Rc::new(RefCell::new(hw));
        let ports = Ports {
            // The simulated bridge never fails.
            motor: MotorDriver::new(SimBridge(Rc::clone(&hw)), spec.bridge)
                .unwrap_or_else(|_| unreachable!("the simulated bridge never fails")),
            hall: SimHall(Rc::clone(&hw)),
            switch: SimSwitch(Rc::clone(&hw)),
            // The data sheet's sense configuration is valid.
            sense: CurrentSense::new(SimIsPin(Rc::clone(&hw)), SenseConfig::DATASHEET_1K_5V)
                .unwrap_or_else(|_| unreachable!("the data sheet's sense configuration is valid")),
        };
        let fw = A::build(ports, spec.firmware, axis)?;
        Ok(DcDrive {
            hw,
            axis: fw,
            spec,
            axis_config: *axis,
            now_ms: 0,
            budget_ms: 0,
            travel_deg: 0.0,
            long_pass: None,
        })
    }

    /// The firmware's axis.
    pub fn axis(&self) -> &A {
        &self.axis
    }

    /// The motor current now, A.
    pub fn current_a(&self) -> f64 {
        self.hw.borrow().motor.current_a()
    }

    fn at_rest(&self) -> bool {
        let m = self.hw.borrow().motor;
        m.motor_speed_rad_s().abs() < AT_REST_RAD_S && duty_free(m.output())
    }

    /// A main-loop pass of `length_ms` that starts `after_ms` from now on
    /// the axis's clock (a GPS burst, a console line, a tick): the axis is
    /// not polled in it while the motor runs on.
    pub fn long_pass(&mut self, after_ms: u32, length_ms: u32) {
        self.long_pass = Some((self.now_ms.wrapping_add(after_ms), length_ms));
    }

    /// One millisecond: a poll (none in a long pass), then the model's
    /// steps.
    fn step_ms(&mut self) {
        let in_long_pass = self
            .long_pass
            .is_some_and(|(from_ms, length_ms)| self.now_ms.wrapping_sub(from_ms) < length_ms);
        if !in_long_pass {
            self.axis.poll_ms(self.now_ms);
        }
        let mut hw = self.hw.borrow_mut();
        let before = hw.motor.output_angle_deg();
        for _ in 0..STEPS_PER_MS {
            hw.motor.step(STEP_S);
        }
        self.travel_deg += (hw.motor.output_angle_deg() - before).abs();
        drop(hw);
        self.now_ms = self.now_ms.wrapping_add(1);
        self.budget_ms = self.budget_ms.saturating_sub(1);
    }

    /// Runs while the firmware axis is busy or the motor turns, within the
    /// budget.
    fn run(&mut self) {
        while self.budget_ms > 0 {
            if self.axis.resting() && self.at_rest() {
                break;
            }
            self.step_ms();
        }
    }
}

/// The motor supply read by a 10-bit ADC at 5 V behind a 4:1 divider (20 V
/// full scale, 19.6 mV a count), mV.
pub fn supply_adc_mv(supply_v: f64) -> u32 {
    let counts = libm::round((supply_v / 4.0 / 5.0 * 1_023.0).clamp(0.0, 1_023.0));
    // At most 20,000 mV.
    libm::round(counts * 20_000.0 / 1_023.0) as u32
}

/// Starts a tick of `dt_s` seconds on an axis's millisecond clock: the
/// budget left of the last tick passes (time at rest is not stepped), the
/// new one is `dt_s` in whole milliseconds (negative: 0; beyond the `u32`
/// range: its largest). True when the tick has time for a poll.
pub(crate) fn start_tick(now_ms: &mut u32, budget_ms: &mut u32, dt_s: f64) -> bool {
    *now_ms = now_ms.wrapping_add(*budget_ms);
    let ms = (dt_s.max(0.0) * 1e3).round();
    *budget_ms = if ms < f64::from(u32::MAX) {
        ms as u32
    } else {
        u32::MAX
    };
    *budget_ms > 0
}

/// No duty applied (braked or coasting).
fn duty_free(output: Output) -> bool {
    matches!(output, Output::Brake | Output::Coast)
}

/// The same hardware after a power cycle: the motor where it is, the
/// firmware's axis new (its RAM is lost).
impl<A: FirmwareAxis> Clone for DcDrive<A> {
    fn clone(&self) -> Self {
        let hw = *self.hw.borrow();
        let mut copy = Self::over(hw, self.spec, &self.axis_config)
            .unwrap_or_else(|e| unreachable!("accepted when this drive was made: {e:?}"));
        copy.now_ms = self.now_ms;
        copy.travel_deg = self.travel_deg;
        copy
    }
}

/// Errors of the simulated timed drive.
pub type TimedDriveError =
    TimedAxisError<Infallible, Infallible, Infallible, SenseError<Infallible>>;

/// A drive whose firmware axis is `$axis` moves at once within the tick's
/// time, and passes on the axis's own faults.
macro_rules! drive_over {
    ($axis:ty, $error:ty) => {
        impl AxisDrive for DcDrive<$axis> {
            type Error = $error;
            const SELF_WATCHED: bool = true;
            fn move_counts(&mut self, counts: i32) -> Result<(), $error> {
                self.axis.move_counts(counts)?;
                self.run();
                Ok(())
            }
            fn pending(&self) -> i32 {
                self.axis.pending()
            }
            fn stop(&mut self) -> Result<(), $error> {
                self.axis.stop()?;
                self.run();
                Ok(())
            }
            fn at_limit(&mut self) -> Result<bool, $error> {
                self.axis.at_limit()
            }
            fn encoder_deg(&mut self) -> Result<Option<f32>, $error> {
                self.axis.encoder_deg()
            }
            fn take_fault(&mut self) -> Option<DriveFault> {
                self.axis.take_fault()
            }
            fn fault_latched(&self) -> bool {
                self.axis.fault_latched()
            }
            fn clear_fault(&mut self) {
                AxisDrive::clear_fault(&mut self.axis);
            }
            fn rebase_counts(&mut self, counts: i32) {
                self.axis.rebase_counts(counts);
            }
            fn switch_stops(&mut self, on: bool) {
                self.axis.switch_stops(on);
            }
        }
    };
}

drive_over!(SimDcAxis, DcDriveError);
drive_over!(SimTimedAxis, TimedDriveError);

impl<A: FirmwareAxis> SimAxis for DcDrive<A>
where
    DcDrive<A>: AxisDrive,
{
    /// The idle time of the tick before passes on the axis's clock; one
    /// poll looks at the counts (a back-driven axis), then pending motion
    /// runs.
    fn begin_tick(&mut self, dt_s: f64) {
        if start_tick(&mut self.now_ms, &mut self.budget_ms, dt_s) {
            self.step_ms();
        }
        self.run();
    }
    fn output_deg(&self) -> f64 {
        self.hw.borrow().motor.output_angle_deg()
    }
    fn travel_deg(&self) -> f64 {
        self.travel_deg
    }
    /// A stall or an obstruction jams the output where it is (the motor
    /// pushes into it and draws its stall current); a failed feedback is a
    /// failed Hall sensor.
    fn inject(&mut self, injected: Injected) {
        let mut hw = self.hw.borrow_mut();
        let jammed = injected.stalled || injected.obstructed;
        let was_jammed = hw.injected.stalled || hw.injected.obstructed;
        if jammed != was_jammed {
            let at = hw.motor.output_angle_deg();
            let stops = if jammed { (at, at) } else { hw.ends_deg };
            hw.motor.set_hard_stops_deg(Some(stops));
        }
        if injected.feedback_failed != hw.injected.feedback_failed {
            hw.motor.set_hall_failed(injected.feedback_failed);
        }
        hw.injected = injected;
    }
    /// The speed at a duty follows the supply (a battery's charge, a long
    /// cable); the firmware axis is told the supply as a board measures it
    /// ([`supply_adc_mv`]).
    fn set_supply_v(&mut self, supply_v: f64) {
        self.hw.borrow_mut().motor.set_supply_v(supply_v);
        self.axis.supply_measured(supply_adc_mv(supply_v));
    }
    /// An external force turns the resting axis by `deg` (the Hall sensor
    /// counts it).
    fn slip(&mut self, deg: f64) {
        let mut hw = self.hw.borrow_mut();
        let to = hw.motor.output_angle_deg() + deg;
        hw.motor.set_output_angle_deg(to);
        self.travel_deg += deg.abs();
    }
}
