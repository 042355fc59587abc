//! The board's DC axes (`axis.c.drive` / `axis.a.drive` 2, `dc_hall`): a
//! DC gear motor (slew drive) on the axis, driven through an IBT-2 module
//! (two Infineon BTS7960 half bridges) and closed on the motor's
//! two-channel Hall encoder ([`suntracker::hw::DcAxis`]). The `dc`
//! feature's image has both axes so by default ([`dc_config`]); any image
//! takes them by configuration. A timed axis (`drive` 5, `timed`: a gear
//! motor or linear actuator without feedback, moved for the time a move
//! takes at its calibrated speeds, [`suntracker::hw::TimedAxis`]) is wired
//! the same but for the encoder ([`timed_axis`]). A linear actuator
//! ([`suntracker::hw::LinearAxis`]) is wired the same on its Hall pulses
//! (`drive` 3, `linear_hall`: the pulse outputs on the encoder inputs, the
//! home switch at the retracted end; [`linear_hall_axis`]) or with its
//! potentiometer's wiper on A4 (C) or A5 (A) in place of the encoder and
//! the home switch (`drive` 4, `linear_pot`; [`linear_pot_axis`]).
//!
//! | function | pin | Mega header |
//! |---|---|---|
//! | C axis IBT-2 RPWM / LPWM (20 kHz, Timer1 OC1A / OC1B) | PB5 / PB6 | D11 / D12 |
//! | A axis IBT-2 RPWM / LPWM (20 kHz, Timer4 OC4B / OC4C) | PH4 / PH5 | D7 / D8 |
//! | C axis IBT-2 R_EN / L_EN | PA0 / PA1 | D22 / D23 |
//! | A axis IBT-2 R_EN / L_EN | PA4 / PA5 | D26 / D27 |
//! | C axis IBT-2 R_IS and L_IS joined, 1 kΩ to GND | ADC2 (PF2) | A2 |
//! | A axis IBT-2 R_IS and L_IS joined, 1 kΩ to GND | ADC3 (PF3) | A3 |
//! | C axis Hall encoder channels A / B (PCINT20 / 21) | PK4 / PK5 | A12 / A13 |
//! | A axis Hall encoder channels A / B (PCINT22 / 23) | PK6 / PK7 | A14 / A15 |
//! | C axis linear actuator potentiometer wiper (`linear_pot`) | ADC4 (PF4) | A4 |
//! | A axis linear actuator potentiometer wiper (`linear_pot`) | ADC5 (PF5) | A5 |
//!
//! A DC axis takes two of its stepper bridge's four pins (PA0–PA3 for C,
//! PA4–PA7 for A) as its enables and leaves the other two alone, so one axis
//! can be a stepper and the other a DC motor; the timers' outputs (D7, D8,
//! D11, D12, driven low at duty 0) and the encoder inputs (A12–A15, pulled
//! up) are set up in every image. The home switches, the weather contacts,
//! the supply and pyranometer inputs, the GPS, the I²C bus, the RS-485
//! port (USART2 D16/D17, driver enable D6 = PH3, which Timer4 leaves to
//! the port: its OC4A output stays disconnected) and the anemometer (D2)
//! are those of the stepper axes (a DC axis has no high-end switch: its
//! soft limits and its own watch bound it).
//!
//! Wiring sketch (one axis; the A axis is the same on its pins):
//!
//! ```text
//!  Mega D11 ─ RPWM ┐                 ┌ M+ ─┐  Pololu 37D 131.25:1 gear motor
//!  Mega D12 ─ LPWM │ IBT-2 (2×BTS7960)│    ├─ → 60:1 worm (slew drive) → C axis
//!  Mega D22 ─ R_EN ├ (+12 V motor)    └ M− ─┘
//!  Mega D23 ─ L_EN │
//!  Mega A2 ─┬ R_IS ┤
//!           └ L_IS ┘   A2 ─ 1 kΩ ─ GND
//!  Mega A12 ─ Hall A   Mega A13 ─ Hall B   (encoder Vcc 5 V, GND)
//!  Mega D37 ─ home switch (closed at the low stop) ─ GND
//! ```
//!
//! The BTS7960 (Infineon, *BTS 7960 High Current PN Half Bridge*, data
//! sheet Rev. 1.1, section 4.4 "Current sense") sources `I_IS = I_L /
//! k_ILIS` from the IS pin of the conducting high side, k_ILIS typically
//! 8,500 (item 4.4.6, characterised with R_IS = 1 kΩ); the idle half
//! bridge's IS leaks at most 1 µA (item 4.4.8), so R_IS and L_IS share one
//! resistor and one ADC input: 1 kΩ gives 0.118 V per A, 5.5 A (the motor's
//! stall current at 12 V) 0.65 V, 132 codes of the 5 V, 10-bit ADC
//! ([`SenseConfig::DATASHEET_1K_5V`]). The IS pin follows the PWM (its
//! high side conducts during the on-time only): a capacitor across the
//! resistor (1 µF: 1 ms against the 50 µs period) makes the reading the
//! average, as the emulator's and the simulator's models read it.
//!
//! The drive is `sim::dc_drive::worm_slew_motor`'s: the Pololu 37D
//! 131.25:1 gear motor at 12 V (10,000 rpm, 5.5 A stall at the motor) with
//! its 64-count motor-shaft Hall encoder (16 pulses a turn on each of two
//! channels, every edge counted by [`suntracker_avr::PinChangeEncoders`]),
//! then a 60:1 worm: 7,875:1 in all, 504,000 counts an output turn (1,400
//! a degree), 7.62 °/s at most. Each axis's position loop and watches are
//! [`suntracker::mechanics::dc_hall_loop`] of its configuration: for this
//! drive the simulator's `WORM_SLEW_LOOP`, whose figures it explains, with
//! the configuration's current limit (`axis.X.max_current_ma`, 3,000 mA)
//! and time (`axis.X.overcurrent_ms`, 100 ms).

use core::cell::RefCell;

use drivers::dc_motor::bts7960::{Bts7960Pins, CurrentSense, SenseConfig};
use drivers::dc_motor::{Config as BridgeConfig, DcMotor, RestMode};
use drivers::encoder::SharedEncoder;
use drivers::linear::{PotCalibration, PulseScale};
use suntracker::config::{AxisConfig, Config};
use suntracker::hw::{
    AnyAxis, DcAxis, HallFeedback, LinearAxis, NoEndSwitch, PotFeedback, TimedAxis,
};

use crate::axes::MegaAxis;
use crate::refused;
use suntracker::mechanics;
use suntracker_avr::{
    chip, Adc, MotorPwm, OutputPin, PinChangeEncoders, PortInputPin, PortOutputPin,
    SharedAdcChannel, Timer1MotorPwm, Timer3Pwm, Timer4MotorPwm, Usart0,
};

/// The C axis's current sense (A2).
pub const C_SENSE_CHANNEL: u8 = 2;
/// The A axis's current sense (A3).
pub const A_SENSE_CHANNEL: u8 = 3;
/// The C axis's linear actuator potentiometer (A4).
pub const C_POT_CHANNEL: u8 = 4;
/// The A axis's linear actuator potentiometer (A5).
pub const A_POT_CHANNEL: u8 = 5;
/// The board's configuration with the DC axes (the `dc` feature's
/// defaults): [`mechanics::worm_slew_config`].
pub fn dc_config() -> Config {
    mechanics::worm_slew_config()
}

/// One axis's bridge inputs.
type Pins<'p> = Bts7960Pins<MotorPwm<'p>, MotorPwm<'p>, PortOutputPin<'p, chip::PORTA>>;

/// One axis's current sense.
type Sense<'p> = CurrentSense<SharedAdcChannel<'p>>;

/// One axis's home switch.
type Home<'p> = PortInputPin<'p, chip::PORTC>;

/// A DC axis of this board (the loop runs it through the core's
/// [`suntracker::firmware::Motion`] at its millisecond count).
pub type MegaDcAxis<'p> = DcAxis<Pins<'p>, &'static SharedEncoder, Home<'p>, Sense<'p>>;

/// A timed axis of this board.
pub type MegaTimedAxis<'p> = TimedAxis<Pins<'p>, Home<'p>, Sense<'p>>;

/// A linear actuator axis of this board on Hall pulses (its encoder
/// inputs).
pub type MegaLinearHallAxis<'p> =
    LinearAxis<Pins<'p>, HallFeedback<&'static SharedEncoder>, Home<'p>, Sense<'p>>;

/// A linear actuator axis of this board on its potentiometer.
pub type MegaLinearPotAxis<'p> =
    LinearAxis<Pins<'p>, PotFeedback<SharedAdcChannel<'p>>, NoEndSwitch, Sense<'p>>;

/// The timers the axes' drives take: Timer1 and Timer4 for the DC
/// bridges, Timer3 for the servos.
pub struct MotorTimers {
    /// The C axis's bridge.
    pub tc1: chip::TC1,
    /// The servos' signals ([`crate::servo`]).
    pub tc3: chip::TC3,
    /// The A axis's bridge.
    pub tc4: chip::TC4,
}

/// The motor timers, the encoders' pin-change counter and the shared ADC
/// the axes borrow.
pub struct DcParts {
    /// Timer1: the C axis's RPWM / LPWM.
    pub timer1: Timer1MotorPwm,
    /// Timer3: the servo axes' signals, C on OC3A (D5), A on OC3C (D3).
    pub timer3: Timer3Pwm,
    /// Timer4: the A axis's RPWM / LPWM.
    pub timer4: Timer4MotorPwm,
    /// Both axes' Hall encoders.
    pub encoders: PinChangeEncoders,
    /// The ADC, shared by the current senses and the board's own readings.
    pub adc: RefCell<Adc>,
}

impl DcParts {
    /// Starts the bridges' timers (duty 0), the servos' (both outputs
    /// disconnected, no pulse until a servo axis is built), the encoders'
    /// interrupt (pull-ups on: the Hall outputs are then never left
    /// floating) and the ADC.
    pub fn start(
        timers: MotorTimers,
        adc: chip::ADC,
        portb: &chip::PORTB,
        porte: &chip::PORTE,
        porth: &chip::PORTH,
        portk: &chip::PORTK,
        exint: &chip::EXINT,
    ) -> Self {
        DcParts {
            timer1: Timer1MotorPwm::start(timers.tc1, portb),
            timer3: Timer3Pwm::start_with(timers.tc3, porte, None, None),
            timer4: Timer4MotorPwm::start(timers.tc4, porth),
            encoders: PinChangeEncoders::start(exint, portk, true),
            adc: RefCell::new(Adc::new(adc)),
        }
    }
}

/// What the axes borrow: the motor parts and the ports of their enables
/// and switches.
pub struct DcBoard<'p> {
    /// Timers, encoders, ADC.
    pub parts: &'p DcParts,
    /// The bridges' enables.
    pub porta: &'p chip::PORTA,
    /// The home switches.
    pub portc: &'p chip::PORTC,
}

/// The bridge of axis `index` (0: C on Timer1 and the enables PA0/PA1; 1:
/// A on Timer4 and PA4/PA5) with `bridge`'s ramp, braking at rest, its Hall
/// encoder (PK4/PK5, PK6/PK7), home switch (PC0, PC1) and current sense
/// (A2, A3); `None` when the bridge or the sense refuse their settings
/// (they take the board's). Not inlined: one copy for both kinds.
#[inline(never)]
fn axis_parts<'p>(
    board: &'p DcBoard<'p>,
    index: usize,
    ramp_permille_per_ms: u16,
) -> Option<(
    DcMotor<Pins<'p>>,
    &'static SharedEncoder,
    Home<'p>,
    Sense<'p>,
)> {
    let DcBoard {
        parts,
        porta,
        portc,
    } = *board;
    let bridge = BridgeConfig {
        ramp_permille_per_ms,
        rest: RestMode::Brake,
    };
    let (pins, hall, home, channel) = if index == 0 {
        let (rpwm, lpwm) = parts.timer1.channels();
        let pins = Bts7960Pins {
            rpwm,
            lpwm,
            r_en: OutputPin::<_, 0>::new(porta, false).erase(),
            l_en: OutputPin::<_, 1>::new(porta, false).erase(),
        };
        let home = suntracker_avr::InputPin::<_, 0>::new(portc, true).erase();
        (pins, parts.encoders.encoder_c(), home, C_SENSE_CHANNEL)
    } else {
        let (rpwm, lpwm) = parts.timer4.channels();
        let pins = Bts7960Pins {
            rpwm,
            lpwm,
            r_en: OutputPin::<_, 4>::new(porta, false).erase(),
            l_en: OutputPin::<_, 5>::new(porta, false).erase(),
        };
        let home = suntracker_avr::InputPin::<_, 1>::new(portc, true).erase();
        (pins, parts.encoders.encoder_a(), home, A_SENSE_CHANNEL)
    };
    let motor = DcMotor::new(pins, bridge).ok()?;
    let sense = CurrentSense::new(
        SharedAdcChannel::new(&parts.adc, channel),
        SenseConfig::DATASHEET_1K_5V,
    )
    .ok()?;
    Some((motor, hall, home, sense))
}

/// The DC axis `index` ([`axis_parts`]: C on Timer1, PA0/PA1, A2,
/// PK4/PK5 and the home switch PC0; A on Timer4, PA4/PA5, A3, PK6/PK7 and
/// PC1), its bridge ramping
/// [`mechanics::WORM_SLEW_RAMP_PERMILLE_PER_MS`], with the loop of its
/// configuration `config` ([`suntracker::mechanics::dc_hall_loop`]);
/// the board halted (`refused`) when a part or the loop refuse their
/// settings (none does for a configuration that passed its checks).
#[inline(never)]
pub fn dc_axis<'p>(
    board: &'p DcBoard<'p>,
    index: usize,
    config: &AxisConfig,
    log: &mut Usart0,
) -> MegaAxis<'p> {
    let Some((motor, hall, home, sense)) =
        axis_parts(board, index, mechanics::WORM_SLEW_RAMP_PERMILLE_PER_MS)
    else {
        refused(log)
    };
    let lp = mechanics::dc_hall_loop(config);
    match DcAxis::new(motor, hall, home, true, Some(sense), lp, config) {
        Ok(axis) => AnyAxis::Dc(axis),
        Err(_) => refused(log),
    }
}

/// The timed axis `index` on the pins of [`axis_parts`] (its encoder
/// unused), its bridge without a duty ramp (a run's time assumes full duty
/// from its start: [`TimedAxis`]), with the runs of its configuration
/// `config` ([`suntracker::mechanics::timed_runs`]: forward at
/// `max_speed_deg_s`, backward at `back_speed_deg_s`) and
/// [`mechanics::WORM_SLEW_LAG_MS`], scaled by the measured supply against
/// `calibration_supply_mv` (`supply.calibration_mv`; 0: not scaled);
/// the board halted (`refused`) when a part or the runs refuse their
/// settings (none does for a configuration that passed its checks).
#[inline(never)]
pub fn timed_axis<'p>(
    board: &'p DcBoard<'p>,
    index: usize,
    config: &AxisConfig,
    calibration_supply_mv: u16,
    log: &mut Usart0,
) -> MegaAxis<'p> {
    let Some((motor, _, home, sense)) = axis_parts(board, index, 0) else {
        refused(log)
    };
    let runs = mechanics::timed_runs(config, calibration_supply_mv, mechanics::WORM_SLEW_LAG_MS);
    match TimedAxis::new(motor, home, true, Some(sense), runs, config) {
        Ok(axis) => AnyAxis::Timed(axis),
        Err(_) => refused(log),
    }
}

/// The linear actuator axis `index` on Hall pulses (`linear_hall`) on the
/// pins of [`axis_parts`] (the Hall outputs on its encoder inputs, the
/// home switch at the retracted end), its bridge ramping
/// [`mechanics::LINEAR_RAMP_PERMILLE_PER_MS`], with the mounting and loop
/// of its configuration ([`mechanics::linear_mount`]); the board halted
/// (`refused`) when a part or the mounting refuse their settings (none
/// does for a configuration that passed its checks).
#[inline(never)]
pub fn linear_hall_axis<'p>(
    board: &'p DcBoard<'p>,
    index: usize,
    config: &AxisConfig,
    log: &mut Usart0,
) -> MegaAxis<'p> {
    let parts = axis_parts(board, index, mechanics::LINEAR_RAMP_PERMILLE_PER_MS);
    let mount = mechanics::linear_mount(config).ok();
    let scale = PulseScale::new(config.linear.pulses_per_mm).ok();
    let (Some((motor, hall, home, sense)), Some(mount), Some(scale)) = (parts, mount, scale) else {
        refused(log)
    };
    let pulses = HallFeedback::new(hall, scale);
    match LinearAxis::new(motor, pulses, home, true, Some(sense), mount, config) {
        Ok(axis) => AnyAxis::LinearHall(axis),
        Err(_) => refused(log),
    }
}

/// The linear actuator axis `index` on its potentiometer (`linear_pot`)
/// on the pins of [`axis_parts`] but the encoder and home switch (the
/// wiper on A4 for C, A5 for A: [`C_POT_CHANNEL`], [`A_POT_CHANNEL`];
/// homed at the retracted end, which the potentiometer reads), read as
/// [`mechanics::LINEAR_POT_READING`] says; the board halted
/// (`refused`) when a part or the mounting refuse their settings, or the
/// potentiometer's first reading lies outside its calibrated span (a
/// broken wiper or lead: the board halts with "axis configuration
/// refused" rather than drive blind).
#[inline(never)]
pub fn linear_pot_axis<'p>(
    board: &'p DcBoard<'p>,
    index: usize,
    config: &AxisConfig,
    log: &mut Usart0,
) -> MegaAxis<'p> {
    let m = &config.linear;
    let channel = if index == 0 {
        C_POT_CHANNEL
    } else {
        A_POT_CHANNEL
    };
    let parts = axis_parts(board, index, mechanics::LINEAR_RAMP_PERMILLE_PER_MS);
    let mount = mechanics::linear_mount(config).ok();
    let pot = PotCalibration::new(m.pot_retracted_counts, m.pot_extended_counts, m.stroke_mm)
        .ok()
        .and_then(|calibration| {
            PotFeedback::new(
                SharedAdcChannel::new(&board.parts.adc, channel),
                calibration,
                m.stroke_mm,
                mechanics::LINEAR_POT_READING,
            )
            .ok()
        });
    let (Some((motor, _, _, sense)), Some(mount), Some(pot)) = (parts, mount, pot) else {
        refused(log)
    };
    // No switch: its input reads low, open only as an active-high switch.
    match LinearAxis::new(motor, pot, NoEndSwitch, false, Some(sense), mount, config) {
        Ok(axis) => AnyAxis::LinearPot(axis),
        Err(_) => refused(log),
    }
}
