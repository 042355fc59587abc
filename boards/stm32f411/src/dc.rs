//! The `dc` feature's axes, the kind chosen per axis by the configuration
//! at power-on (`axis.X.drive`):
//! - 2, `dc_hall`: a DC gear motor or slew drive on an IBT-2 module (two
//!   Infineon BTS7960 half bridges), closed on the motor's two-channel
//!   Hall encoder ([`suntracker::hw::DcAxis`]);
//! - 5, `timed`: a DC motor or linear actuator on the bridge moved by time
//!   without feedback ([`suntracker::hw::TimedAxis`], the encoder unused);
//! - 3, `linear_hall`: a linear actuator on the bridge, closed on its Hall
//!   pulses on the encoder inputs, its home switch at the retracted end
//!   ([`suntracker::hw::LinearAxis`]);
//! - 4, `linear_pot`: a linear actuator on the bridge, closed on its
//!   potentiometer, whose wiper takes an ADC input (B0 for C, in place of
//!   its home switch; B1 for A) and which reads the retracted end (no
//!   switch);
//! - 1, `servo_encoder`: a continuous-rotation servo (Chowdhury et al.'s
//!   (2019) FEETECH FS5106R) closed on a quadrature encoder on the encoder
//!   inputs ([`suntracker::hw::ServoAxis`]), its signal on the axis's
//!   RPWM pin, whose timer then runs at 50 Hz: the bridge is not fitted;
//! - 0, `stepper`: the default image's stepper on an L298N, on that
//!   image's pins (IN1–IN4: A4–A7 for C, B12–B15 for A), which this image
//!   then sets up as outputs in place of the bridge's inputs; its home
//!   switch is also its driver's low-end limit, and it has no high-end
//!   switch here (B1 is the A axis's wiper; B9 stays free): its soft limits
//!   bound it, as they bound a DC axis.
//!
//! The image's own configuration has both axes on the worm slew drive
//! ([`suntracker::mechanics::worm_slew_config`]). The pins follow the
//! configuration read at power-on ([`DcPins::start`], [`CHomeInput`]); a
//! `set` of another kind is saved and takes effect at the next power-on,
//! when a bridge's or a stepper's wiring must be the one the kind names.
//!
//! | function | peripheral | Black Pill pin |
//! |---|---|---|
//! | C axis IBT-2 RPWM / LPWM (20 kHz) | TIM3 CH1 / CH2 | A6 / A7 |
//! | C axis IBT-2 R_EN / L_EN | GPIO push-pull | A4 / A5 |
//! | C axis IBT-2 R_IS and L_IS joined, 680 Ω and 1 µF to GND | ADC1 IN0 | A0 |
//! | C axis Hall encoder channels A / B (both edges, pulled up) | EXTI9 / EXTI15 | A9 / A15 |
//! | A axis IBT-2 RPWM / LPWM (20 kHz) | TIM9 CH1 / CH2 | A2 / A3 |
//! | A axis IBT-2 R_EN / L_EN | GPIO push-pull | B12 / B13 |
//! | A axis IBT-2 R_IS and L_IS joined, 680 Ω and 1 µF to GND | ADC1 IN1 | A1 |
//! | A axis Hall encoder channels A / B (both edges, pulled up) | EXTI14 / EXTI4 | B14 / B4 |
//! | C axis servo signal (`servo_encoder`; 50 Hz) | TIM3 CH1 | A6 |
//! | A axis servo signal (`servo_encoder`; 50 Hz) | TIM9 CH1 | A2 |
//! | C axis potentiometer wiper (`linear_pot`; 3.3 V across the track) | ADC1 IN8 | B0 |
//! | A axis potentiometer wiper (`linear_pot`; 3.3 V across the track) | ADC1 IN9 | B1 |
//! | C axis L298N IN1–IN4 (`stepper`) | GPIO push-pull | A4, A5, A6, A7 |
//! | A axis L298N IN1–IN4 (`stepper`) | GPIO push-pull | B12, B13, B14, B15 |
//!
//! The home switches stay on B0 (C) and B8 (A), but B0 is a `linear_pot`
//! C axis's wiper ([`CHomeInput`]); a DC axis has no high-end switch (its
//! soft limits and its own watch bound it), so B9 is unused. A servo or
//! a linear actuator's Hall pulses take the encoder inputs, pulled up to
//! 3.3 V as for a Hall encoder; the servo's signal is a 3.3 V pulse (1,500
//! µs at rest, [`suntracker::servo_tracker::SERVO`]), which most hobby
//! servos take, else through the 74HCT buffer of the bridge's inputs. A
//! potentiometer's track goes between 3.3 V and GND, never 5 V (the ADC
//! inputs' limit is VDDA); its calibration (`axis.X.pot_retracted_counts`,
//! `pot_extended_counts`) is in this ADC's 0…4,095 counts. The bridges take USART2's pins (A1–A3), so this image has no
//! RS-485 inclinometer: its tilt comes from the ADXL345 on I²C, and it
//! cannot be built with the `modbus` feature. The other pins are the
//! default image's.
//!
//! Wiring sketch (the C axis; the A axis the same on its pins):
//!
//! ```text
//!  A6 ─ RPWM ┐                   ┌ M+ ─┐  Pololu 37D 131.25:1 gear motor
//!  A7 ─ LPWM │ IBT-2 (2×BTS7960) │     ├─ → 60:1 worm (slew drive) → C axis
//!  A4 ─ R_EN ├ (+12 V motor,     └ M− ─┘
//!  A5 ─ L_EN │  VCC 5 V; the four inputs through a 74HCT buffer)
//!  A0 ─┬ R_IS┤
//!      └ L_IS┘   A0 ─ 680 Ω ∥ 1 µF ─ GND
//!  A9 ─ Hall A   A15 ─ Hall B   (3.3 V levels: see below)
//!  B0 ─ home switch (closed at the low stop) ─ GND
//! ```
//!
//! A linear actuator on its potentiometer (the A axis; a C axis's wiper
//! on B0, which then has no switch), on the same bridge:
//!
//! ```text
//!  3V3 ─ pot track ─ GND       (the actuator's potentiometer, 10 kΩ)
//!           └ wiper ─ B1
//! ```
//!
//! A servo on its encoder (the C axis; the A axis on A2, B14/B4, B8), no
//! bridge fitted:
//!
//! ```text
//!  A6 ─ signal ─ FS5106R (its own +6 V supply, GND common with the board)
//!  A9 ─ encoder A   A15 ─ encoder B   (YMT22; 3.3 V levels)
//!  B0 ─ home switch (closed at the low stop) ─ GND
//! ```
//!
//! The IBT-2 takes its logic supply (VCC) at 5 V, and its inputs go
//! through the module's 74HC244 buffer, which at 5 V needs 0.7 · VCC =
//! 3.5 V for a high: more than a 3.3 V output gives. So RPWM, LPWM, R_EN
//! and L_EN go through a 3.3 → 5 V buffer whose inputs take TTL levels (a
//! 74HCT244 or 74AHCT125 on 5 V: a high from 2 V). The Hall outputs reach
//! the pins at 3.3 V levels: open-collector outputs on the pins'
//! pull-ups, or a 5 V encoder's push-pull outputs through a level shifter.
//!
//! **Current sense.** The BTS7960's IS pin of the conducting high side
//! sources `I_IS = I_L / k_ILIS`, k_ILIS typically 8,500 (Infineon, *BTS
//! 7960 High Current PN Half Bridge*, data sheet Rev. 1.1, section 4.4
//! "Current sense", item 4.4.6); the idle half bridge's IS leaks at most
//! 1 µA (item 4.4.8), so both IS pins share one resistor and one input.
//! With 680 Ω (the Mega's 1 kΩ would put 3.3 V at 33 A, inside what the
//! bridge conducts) the 3.3 V, 12-bit ADC reads 0.080 V per A, full scale
//! at 41 A; the 5.5 A stall current of the motor below reads 0.44 V, 546
//! codes ([`SENSE`]). The IS pin follows the PWM (its high side conducts
//! during the on-time only): the 1 µF across the resistor (0.7 ms against
//! the 50 µs period) makes the reading the average.
//!
//! **Conversions.** [`Adc1`] converts one channel at a time, started by
//! software (ST, RM0383 reference manual, chapter "Analog-to-digital
//! converter (ADC)": "ADC on-off control", "Single conversion mode"), with
//! the ADC clock at PCLK2 / 4 = 25 MHz (at most 36 MHz: the F411 data
//! sheet's f_ADC) and 84 cycles of sampling ("Channel-wise programmable
//! sampling time"), 12 more for a 12-bit result: 96 cycles, 3.84 µs a
//! conversion. A conversion that has not ended after [`ADC_WAIT_POLLS`]
//! reads of the status register is an error, not a wait without end.
//!
//! **Hall counts.** Each edge of either channel interrupts (EXTI, both
//! edges); the handler reads both channels and steps the axis's
//! [`drivers::encoder::AtomicEncoder`] (an illegal transition is counted
//! as an error, not a step). The drive of the image's configuration
//! (`sim::dc_drive::worm_slew_motor`: 64 counts a motor turn at
//! 10,000 rpm) gives at most 10,667 edges a second on each axis.

use core::cell::RefCell;
use core::convert::Infallible;

use cortex_m::interrupt::{free, Mutex};
use drivers::adc::AdcChannel;
use drivers::dc_motor::bts7960::{Bts7960Pins, CurrentSense, SenseConfig};
use drivers::dc_motor::{Config as BridgeConfig, DcMotor, RestMode};
use drivers::encoder::AtomicEncoder;
use drivers::linear::{PotCalibration, PulseScale};
use drivers::servo::ContinuousServo;
use drivers::stepper::hbridge::{BridgePins, HBridgeStepper};
use drivers::stepper::LimitSwitches;
use embedded_hal::pwm::SetDutyCycle;
use stm32f4xx_hal as hal;
use suntracker::config::{AxisConfig, DriveKind, DriveSet};
use suntracker::hw::{
    AnyAxis, DcAxis, HallFeedback, LinearAxis, NoEndSwitch, PotFeedback, ServoAxis, StepperAxis,
    TimedAxis,
};
use suntracker::mechanics;
use suntracker::servo_tracker::{POSITION_LOOP, SERVO};

use hal::gpio::{Analog, Edge, ErasedPin, ExtiPin, Input, Output, PA15, PA9, PB0, PB14, PB4};
use hal::pac::{self, interrupt};
use hal::rcc::Enable;
use hal::syscfg::SysCfg;
use hal::timer::pwm::ErasedChannel;

use crate::Switch;

/// The drive kinds this image builds an axis of: every kind.
pub const DRIVES: DriveSet = DriveSet::ALL;

/// The bridges' PWM frequency: above hearing, as the ATmega2560's
/// bridges run.
pub const PWM_HZ: u32 = 20_000;

/// A servo axis's timer: one pulse every 20 ms
/// ([`suntracker::servo_tracker::SERVO`]'s period).
pub const SERVO_FRAME_HZ: u32 = 50;

/// The current sense of both axes: k_ILIS 8,500 (typical), R_IS 680 Ω,
/// the 3.3 V reference (module docs).
pub const SENSE: SenseConfig = SenseConfig {
    k_ilis: 8_500,
    r_is_ohm: 680,
    vref_mv: 3_300,
};

/// Status register reads a conversion may take: 96 ADC cycles are 384
/// core cycles at 100 MHz, and each read takes several.
pub const ADC_WAIT_POLLS: u32 = 1_000;

/// The C axis's current sense channel (A0).
const C_SENSE_CHANNEL: u8 = 0;
/// The A axis's current sense channel (A1).
const A_SENSE_CHANNEL: u8 = 1;
/// A `linear_pot` C axis's potentiometer wiper (B0, ADC1 IN8).
const C_POT_CHANNEL: u8 = 8;
/// A `linear_pot` A axis's potentiometer wiper (B1, ADC1 IN9).
const A_POT_CHANNEL: u8 = 9;

/// The C axis's Hall count.
static ENCODER_C: AtomicEncoder = AtomicEncoder::new();
/// The A axis's Hall count.
static ENCODER_A: AtomicEncoder = AtomicEncoder::new();

/// The Hall inputs, owned by their interrupt handlers once set up.
struct HallPins {
    c_a: PA9<Input>,
    c_b: PA15<Input>,
    /// `None` where B14 is a stepper's IN3.
    a_a: Option<PB14<Input>>,
    a_b: PB4<Input>,
}

/// The Hall inputs, for their handlers.
static HALLS: Mutex<RefCell<Option<HallPins>>> = Mutex::new(RefCell::new(None));

/// Steps an axis's count after an edge on `line` (its pending bit is
/// cleared): the C axis for lines 9 and 15, the A axis for 14 and 4.
fn hall_edge(line: u8) {
    free(|cs| {
        let Ok(mut halls) = HALLS.borrow(cs).try_borrow_mut() else {
            return;
        };
        let Some(h) = halls.as_mut() else {
            return;
        };
        let c = match line {
            9 if h.c_a.check_interrupt() => {
                h.c_a.clear_interrupt_pending_bit();
                true
            }
            15 if h.c_b.check_interrupt() => {
                h.c_b.clear_interrupt_pending_bit();
                true
            }
            14 => {
                let a_a = h.a_a.as_mut().filter(|pin| pin.check_interrupt());
                let Some(a_a) = a_a else {
                    return;
                };
                a_a.clear_interrupt_pending_bit();
                false
            }
            4 if h.a_b.check_interrupt() => {
                h.a_b.clear_interrupt_pending_bit();
                false
            }
            _ => return,
        };
        if c {
            ENCODER_C.update(h.c_a.is_high(), h.c_b.is_high());
        } else if let Some(a_a) = &h.a_a {
            ENCODER_A.update(a_a.is_high(), h.a_b.is_high());
        }
    });
}

/// The C axis's Hall channel A (A9); called by the board's `EXTI9_5`
/// handler, which also counts the anemometer (A8).
pub(crate) fn on_exti9() {
    hall_edge(9);
}

/// The A axis's Hall channel B (B4).
// `#[export_name]` binding: see the board's `USART1` handler.
#[allow(unsafe_code)]
#[interrupt]
fn EXTI4() {
    hall_edge(4);
}

/// The A axis's Hall channel A (B14) and the C axis's channel B (A15).
// `#[export_name]` binding: see the board's `USART1` handler.
#[allow(unsafe_code)]
#[interrupt]
fn EXTI15_10() {
    hall_edge(14);
    hall_edge(15);
}

/// A bridge input's PWM channel: TIM3's (C axis) or TIM9's (A axis), as
/// one type so that both axes are of one type.
pub enum Pwm {
    /// TIM3 CH1 or CH2.
    Tim3(ErasedChannel<pac::TIM3>),
    /// TIM9 CH1 or CH2.
    Tim9(ErasedChannel<pac::TIM9>),
}

impl embedded_hal::pwm::ErrorType for Pwm {
    type Error = Infallible;
}

impl SetDutyCycle for Pwm {
    fn max_duty_cycle(&self) -> u16 {
        match self {
            Pwm::Tim3(ch) => ch.max_duty_cycle(),
            Pwm::Tim9(ch) => ch.max_duty_cycle(),
        }
    }
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Infallible> {
        match self {
            Pwm::Tim3(ch) => ch.set_duty_cycle(duty),
            Pwm::Tim9(ch) => ch.set_duty_cycle(duty),
        }
    }
}

/// Why a conversion failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdcError {
    /// The end of conversion did not come within [`ADC_WAIT_POLLS`] reads.
    Timeout,
}

/// ADC1, converting one channel at a time (module docs).
pub struct Adc1 {
    adc: pac::ADC1,
}

impl Adc1 {
    /// Clocks ADC1 (PCLK2 / 4), sets 84 sampling cycles on channels 0, 1,
    /// 8 and 9, and switches it on (RM0383, "ADC on-off control": the converter
    /// needs its stabilisation time t_STAB after ADON, which passes long
    /// before the loop's first conversion).
    pub fn start(adc: pac::ADC1, common: &pac::ADC_COMMON, rcc: &mut hal::rcc::Rcc) -> Self {
        pac::ADC1::enable(rcc);
        common.ccr().modify(|_, w| w.adcpre().div4());
        adc.smpr2().modify(|_, w| {
            w.smp0().cycles84();
            w.smp1().cycles84();
            w.smp8().cycles84();
            w.smp9().cycles84()
        });
        // One conversion in the regular sequence; 12 bits, right aligned
        // (the reset values of CR1 and CR2's ALIGN).
        adc.sqr1().modify(|_, w| w.l().set(0));
        adc.cr2().modify(|_, w| w.adon().set_bit());
        Adc1 { adc }
    }

    /// One conversion of `channel` (0..=15), 0..=4,095.
    pub fn convert(&mut self, channel: u8) -> Result<u16, AdcError> {
        // SAFETY: SQ1 takes any channel number of its five bits (0..=18
        // are channels; the board passes 0, 1, 8 and 9).
        #[allow(unsafe_code)]
        self.adc
            .sqr3()
            .modify(|_, w| unsafe { w.sq1().bits(channel & 0x1f) });
        self.adc.cr2().modify(|_, w| w.swstart().set_bit());
        for _ in 0..ADC_WAIT_POLLS {
            if self.adc.sr().read().eoc().bit_is_set() {
                // Reading DR clears EOC.
                return Ok(self.adc.dr().read().data().bits());
            }
        }
        Err(AdcError::Timeout)
    }
}

/// One channel of the shared [`Adc1`].
pub struct SenseInput<'a> {
    adc: &'a RefCell<Adc1>,
    channel: u8,
}

impl AdcChannel for SenseInput<'_> {
    type Error = AdcError;
    fn read_raw(&mut self) -> Result<u16, AdcError> {
        // Only the loop converts; a second borrow cannot happen, and is
        // an error rather than a panic should it.
        let mut adc = self.adc.try_borrow_mut().map_err(|_| AdcError::Timeout)?;
        adc.convert(self.channel)
    }
    fn full_scale(&self) -> u16 {
        4_095
    }
}

/// One axis's bridge inputs.
type Pins = Bts7960Pins<Pwm, Pwm, ErasedPin<Output>>;
/// One axis's current sense.
type Sense<'a> = CurrentSense<SenseInput<'a>>;

/// A DC axis of this image.
pub type BlackPillDcAxis<'a> = DcAxis<Pins, &'static AtomicEncoder, Switch<'a>, Sense<'a>>;
/// A timed axis of this image.
pub type BlackPillTimedAxis<'a> = TimedAxis<Pins, Switch<'a>, Sense<'a>>;
/// A linear actuator on its Hall pulses.
pub type BlackPillLinearHallAxis<'a> =
    LinearAxis<Pins, HallFeedback<&'static AtomicEncoder>, Switch<'a>, Sense<'a>>;
/// A linear actuator on its potentiometer.
pub type BlackPillLinearPotAxis<'a> =
    LinearAxis<Pins, PotFeedback<SenseInput<'a>>, NoEndSwitch, Sense<'a>>;
/// A continuous servo on its encoder.
pub type BlackPillServoAxis<'a> = ServoAxis<'static, Pwm, AtomicEncoder, Switch<'a>>;
/// A stepper on its H-bridge, its home switch also its driver's low-end
/// limit (no high-end switch here: module docs).
pub type BlackPillStepperAxis<'a> = StepperAxis<ErasedPin<Output>, Switch<'a>, Switch<'a>>;
/// An axis of this image, of the kind its configuration names
/// ([`DRIVES`]).
pub type BlackPillAxis<'a> = AnyAxis<
    BlackPillStepperAxis<'a>,
    BlackPillDcAxis<'a>,
    BlackPillTimedAxis<'a>,
    BlackPillLinearHallAxis<'a>,
    BlackPillLinearPotAxis<'a>,
    BlackPillServoAxis<'a>,
>;

/// One axis's pins, as its kind needs them.
pub enum AxisPins {
    /// An IBT-2 bridge's inputs (or a servo's signal on RPWM) and its
    /// current sense channel.
    Bridge {
        rpwm: Pwm,
        lpwm: Pwm,
        r_en: ErasedPin<Output>,
        l_en: ErasedPin<Output>,
        channel: u8,
    },
    /// A stepper's H-bridge IN1–IN4, as in the default image.
    Stepper(BridgePins<ErasedPin<Output>>),
}

/// The pins and timers the axes take (module docs), set up: each axis's
/// timer at [`PWM_HZ`], or [`SERVO_FRAME_HZ`] for a servo, with duty 0,
/// the enables low, the sense inputs and B1 analog, the Hall inputs
/// pulled up and interrupting on both edges; a stepper axis's four
/// outputs low instead of its bridge's inputs (and, on the A axis, of
/// the Hall input B14).
pub struct DcPins {
    /// The C axis's bridge.
    pub c: AxisPins,
    /// The A axis's bridge.
    pub a: AxisPins,
}

/// The parts of [`DcPins::start`] from the board's GPIO ports. The ones
/// only a bridge's or a stepper's inputs take (A2–A7, B12, B13, B15) are
/// outputs already, low (the output register's reset value): the board
/// makes them so at once, so that nothing drives a motor while the
/// configuration is read, before [`DcPins::start`] gives each axis its
/// pins. B14 is the A axis's Hall input or its stepper's IN3, and stays
/// an input until the kind is known.
pub struct DcPinsIn {
    pub pa0: hal::gpio::PA0,
    pub pa1: hal::gpio::PA1,
    pub pa2: hal::gpio::PA2<Output>,
    pub pa3: hal::gpio::PA3<Output>,
    pub pa4: hal::gpio::PA4<Output>,
    pub pa5: hal::gpio::PA5<Output>,
    pub pa6: hal::gpio::PA6<Output>,
    pub pa7: hal::gpio::PA7<Output>,
    pub pa9: hal::gpio::PA9,
    pub pa15: hal::gpio::PA15<hal::gpio::Alternate<0>>,
    pub pb1: hal::gpio::PB1,
    pub pb4: hal::gpio::PB4<hal::gpio::Alternate<0>>,
    pub pb12: hal::gpio::PB12<Output>,
    pub pb13: hal::gpio::PB13<Output>,
    pub pb14: hal::gpio::PB14,
    pub pb15: hal::gpio::PB15<Output>,
}

impl DcPins {
    /// Sets the pins and timers up for the axes `configs` name (a servo
    /// axis's timer at [`SERVO_FRAME_HZ`]) and hands the Hall inputs to
    /// their interrupts (unmasked by the caller: `EXTI4`, `EXTI9_5`,
    /// `EXTI15_10`).
    pub fn start(
        p: DcPinsIn,
        tim3: pac::TIM3,
        tim9: pac::TIM9,
        syscfg: &mut SysCfg,
        exti: &mut pac::EXTI,
        rcc: &mut hal::rcc::Rcc,
        configs: &[AxisConfig; 2],
    ) -> Self {
        use hal::prelude::*;
        use hal::timer::PwmExt;
        let is = |axis: usize, kind: DriveKind| configs[axis].drive == kind as u8;
        let (mut tim3, (c_r, c_l, ..)) = tim3.pwm_hz(PWM_HZ.Hz(), rcc);
        let (mut tim9, (a_r, a_l)) = tim9.pwm_hz(PWM_HZ.Hz(), rcc);
        // A servo's frames: each timer's period set apart, by a constant,
        // so that the HAL's prescaler and reload arithmetic folds (a
        // frequency chosen at run time leaves it a reload check that
        // panics).
        if is(0, DriveKind::ServoEncoder) {
            tim3.set_period(SERVO_FRAME_HZ.Hz());
        }
        if is(1, DriveKind::ServoEncoder) {
            tim9.set_period(SERVO_FRAME_HZ.Hz());
        }
        let c = if is(0, DriveKind::Stepper) {
            AxisPins::Stepper(BridgePins {
                in1: p.pa4.erase(),
                in2: p.pa5.erase(),
                in3: p.pa6.erase(),
                in4: p.pa7.erase(),
            })
        } else {
            let mut c_r = c_r.with(p.pa6);
            let mut c_l = c_l.with(p.pa7);
            // Duty 0 before the outputs are connected (the compare
            // registers' reset value, written so that it does not depend
            // on it).
            c_r.set_duty(0);
            c_l.set_duty(0);
            c_r.enable();
            c_l.enable();
            AxisPins::Bridge {
                rpwm: Pwm::Tim3(c_r.erase()),
                lpwm: Pwm::Tim3(c_l.erase()),
                r_en: p.pa4.erase(),
                l_en: p.pa5.erase(),
                channel: C_SENSE_CHANNEL,
            }
        };
        let (a, a_hall_a) = if is(1, DriveKind::Stepper) {
            let pins = AxisPins::Stepper(BridgePins {
                in1: p.pb12.erase(),
                in2: p.pb13.erase(),
                in3: p.pb14.into_push_pull_output().erase(),
                in4: p.pb15.erase(),
            });
            (pins, None)
        } else {
            let mut a_r = a_r.with(p.pa2);
            let mut a_l = a_l.with(p.pa3);
            a_r.set_duty(0);
            a_l.set_duty(0);
            a_r.enable();
            a_l.enable();
            let pins = AxisPins::Bridge {
                rpwm: Pwm::Tim9(a_r.erase()),
                lpwm: Pwm::Tim9(a_l.erase()),
                r_en: p.pb12.erase(),
                l_en: p.pb13.erase(),
                channel: A_SENSE_CHANNEL,
            };
            (pins, Some(p.pb14.into_pull_up_input()))
        };
        let _ = p.pa0.into_analog();
        let _ = p.pa1.into_analog();
        let _ = p.pb1.into_analog();
        let mut halls = HallPins {
            c_a: p.pa9.into_pull_up_input(),
            c_b: p.pa15.into_pull_up_input(),
            a_a: a_hall_a,
            a_b: p.pb4.into_pull_up_input(),
        };
        // The decoders start from the levels as they are (a first edge
        // is then a step, not an illegal jump from 00).
        ENCODER_C.update(halls.c_a.is_high(), halls.c_b.is_high());
        if let Some(a_a) = &halls.a_a {
            ENCODER_A.update(a_a.is_high(), halls.a_b.is_high());
        }
        // Armed and handed over in one critical section: an edge between
        // the two would find no pins, leave its pending bit set and
        // interrupt again without end.
        free(|cs| {
            arm(&mut halls.c_a, syscfg, exti);
            arm(&mut halls.c_b, syscfg, exti);
            if let Some(a_a) = &mut halls.a_a {
                arm(a_a, syscfg, exti);
            }
            arm(&mut halls.a_b, syscfg, exti);
            if let Ok(mut slot) = HALLS.borrow(cs).try_borrow_mut() {
                *slot = Some(halls);
            }
        });
        DcPins { c, a }
    }
}

/// A Hall input interrupting on both edges.
fn arm<P: ExtiPin>(pin: &mut P, syscfg: &mut SysCfg, exti: &mut pac::EXTI) {
    pin.make_interrupt_source(syscfg);
    pin.trigger_on_edge(exti, Edge::RisingFalling);
    pin.enable_interrupt(exti);
    pin.clear_interrupt_pending_bit();
}

/// B0: the C axis's home switch (pulled up), or the wiper of a C axis
/// that is a linear actuator on its potentiometer (`linear_pot`: homed by
/// the potentiometer, no switch) on ADC1 IN8, as `c` names.
pub enum CHomeInput {
    /// The home switch, closed to GND at the low end.
    Switch(ErasedPin<Input>),
    /// The potentiometer's wiper.
    Wiper(PB0<Analog>),
}

impl CHomeInput {
    /// B0 set up for the C axis of the configuration `c`.
    pub fn start(pb0: PB0, c: &AxisConfig) -> Self {
        if c.drive == DriveKind::LinearPot as u8 {
            CHomeInput::Wiper(pb0.into_analog())
        } else {
            CHomeInput::Switch(pb0.into_pull_up_input().erase())
        }
    }

    /// The home switch, when B0 is one.
    fn switch(&self) -> Option<Switch<'_>> {
        match self {
            CHomeInput::Switch(pin) => Some(Switch(pin)),
            CHomeInput::Wiper(_) => None,
        }
    }
}

/// The axis on `pins` of the kind `config.drive` names, its home switch
/// `home` (active low; `None` where B0 is a wiper), its count `encoder`
/// (the Hall encoder, a linear actuator's Hall pulses or a servo's
/// encoder; unused by a timed or potentiometer axis) and its
/// potentiometer's channel `pot_channel` (`linear_pot`):
/// - `dc_hall`: a DC axis ramping
///   [`mechanics::WORM_SLEW_RAMP_PERMILLE_PER_MS`] with the loop of its
///   configuration ([`mechanics::dc_hall_loop`]);
/// - `timed`: a timed axis without a ramp with the runs of its
///   configuration ([`mechanics::timed_runs`],
///   [`mechanics::WORM_SLEW_LAG_MS`]; not scaled by a supply measurement:
///   this board reads none);
/// - `linear_hall` and `linear_pot`: a linear actuator ramping
///   [`mechanics::LINEAR_RAMP_PERMILLE_PER_MS`] with the mounting of its
///   configuration ([`mechanics::linear_mount`]), its potentiometer read
///   as [`mechanics::LINEAR_POT_READING`] says;
/// - `servo_encoder`: the servo's signal on the bridge's RPWM pin, its
///   timer at 50 Hz ([`DcPins::start`]), with
///   [`suntracker::servo_tracker::SERVO`]'s pulses and
///   [`suntracker::servo_tracker::POSITION_LOOP`];
/// - `stepper`: the default image's stepper on IN1–IN4 with
///   [`mechanics::bridge_config`], its home switch its low-end limit.
///
/// `None` for pins of another kind, a part that refuses its settings
/// (none does for a configuration that passed its checks) or a
/// potentiometer whose first reading lies outside its calibrated span (a
/// broken wiper or lead: the board halts rather than drive blind).
fn axis<'a>(
    pins: AxisPins,
    encoder: &'static AtomicEncoder,
    home: Option<Switch<'a>>,
    pot_channel: u8,
    adc: &'a RefCell<Adc1>,
    config: &AxisConfig,
) -> Option<BlackPillAxis<'a>> {
    let kind = DriveKind::from_code(config.drive)?;
    let (rpwm, lpwm, r_en, l_en, channel) = match pins {
        AxisPins::Bridge {
            rpwm,
            lpwm,
            r_en,
            l_en,
            channel,
        } => (rpwm, lpwm, r_en, l_en, channel),
        AxisPins::Stepper(pins) if kind == DriveKind::Stepper => {
            let home = home?;
            let limits = LimitSwitches {
                min: Some(home),
                max: None,
                active_low: true,
            };
            let stepper = HBridgeStepper::new(pins, limits, mechanics::bridge_config()).ok()?;
            return Some(AnyAxis::Stepper(StepperAxis::new(stepper, home, true)));
        }
        AxisPins::Stepper(_) => return None,
    };
    let ramp_permille_per_ms = match kind {
        DriveKind::DcHall => mechanics::WORM_SLEW_RAMP_PERMILLE_PER_MS,
        DriveKind::LinearHall | DriveKind::LinearPot => mechanics::LINEAR_RAMP_PERMILLE_PER_MS,
        DriveKind::Timed => 0,
        DriveKind::ServoEncoder => {
            let servo = ContinuousServo::new(rpwm, SERVO).ok()?;
            return Some(AnyAxis::ServoEncoder(ServoAxis::new(
                servo,
                encoder,
                home?,
                true,
                POSITION_LOOP,
                config,
            )));
        }
        DriveKind::Stepper => return None,
    };
    let bridge = Bts7960Pins {
        rpwm,
        lpwm,
        r_en,
        l_en,
    };
    let motor = DcMotor::new(
        bridge,
        BridgeConfig {
            ramp_permille_per_ms,
            rest: RestMode::Brake,
        },
    )
    .ok()?;
    let input = SenseInput { adc, channel };
    let sense = Some(CurrentSense::new(input, SENSE).ok()?);
    match kind {
        DriveKind::DcHall => {
            let lp = mechanics::dc_hall_loop(config);
            DcAxis::new(motor, encoder, home?, true, sense, lp, config)
                .ok()
                .map(AnyAxis::Dc)
        }
        DriveKind::LinearHall => {
            let mount = mechanics::linear_mount(config).ok()?;
            let scale = PulseScale::new(config.linear.pulses_per_mm).ok()?;
            let pulses = HallFeedback::new(encoder, scale);
            LinearAxis::new(motor, pulses, home?, true, sense, mount, config)
                .ok()
                .map(AnyAxis::LinearHall)
        }
        DriveKind::LinearPot => {
            let m = &config.linear;
            let mount = mechanics::linear_mount(config).ok()?;
            let calibration =
                PotCalibration::new(m.pot_retracted_counts, m.pot_extended_counts, m.stroke_mm)
                    .ok()?;
            let wiper = SenseInput {
                adc,
                channel: pot_channel,
            };
            let pot = PotFeedback::new(
                wiper,
                calibration,
                m.stroke_mm,
                mechanics::LINEAR_POT_READING,
            )
            .ok()?;
            // No switch: the potentiometer reads the retracted end.
            LinearAxis::new(motor, pot, NoEndSwitch, false, sense, mount, config)
                .ok()
                .map(AnyAxis::LinearPot)
        }
        // Timed (a stepper and a servo returned above).
        _ => {
            let runs = mechanics::timed_runs(config, 0, mechanics::WORM_SLEW_LAG_MS);
            TimedAxis::new(motor, home?, true, sense, runs, config)
                .ok()
                .map(AnyAxis::Timed)
        }
    }
}

/// Both axes, each of the kind its configuration names: C on TIM3, A0,
/// A9/A15, its wiper on B0 or its home switch there (`c_home`); A on
/// TIM9, A1, B14/B4, its wiper on B1 and its home switch `a_home`; `None`
/// when either refuses (module docs).
pub fn axes<'a>(
    pins: DcPins,
    c_home: &'a CHomeInput,
    a_home: Switch<'a>,
    adc: &'a RefCell<Adc1>,
    configs: &[AxisConfig; 2],
) -> Option<[BlackPillAxis<'a>; 2]> {
    let c = axis(
        pins.c,
        &ENCODER_C,
        c_home.switch(),
        C_POT_CHANNEL,
        adc,
        &configs[0],
    )?;
    let a = axis(
        pins.a,
        &ENCODER_A,
        Some(a_home),
        A_POT_CHANNEL,
        adc,
        &configs[1],
    )?;
    Some([c, a])
}
