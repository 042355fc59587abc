//! The board's two axes, each of the kind its configuration names
//! (`axis.c.drive`, `axis.a.drive`), built at power-on: a stepper on its
//! H-bridge (0, `stepper`: Li et al.'s (2022) build, the pins in the crate's
//! table), a DC gear motor on an IBT-2 closed on its Hall encoder (2,
//! `dc_hall`: [`crate::dc`]), a DC motor on the same IBT-2 moved by time
//! without feedback (5, `timed`: [`crate::dc::timed_axis`]) or a linear
//! actuator on the same IBT-2, read by its Hall pulses (3, `linear_hall`:
//! [`crate::dc::linear_hall_axis`]) or its potentiometer (4, `linear_pot`:
//! [`crate::dc::linear_pot_axis`]), or a continuous servo closed on its
//! encoder (1, `servo_encoder`: [`crate::servo`]). The board builds every
//! kind ([`DRIVES`]); a kind changed by `set` is built at the next
//! power-on (`save`, then reset).

use drivers::stepper::hbridge::{BridgePins, HBridgeStepper};
use drivers::stepper::LimitSwitches;
use suntracker::config::{AxisConfig, DriveKind, DriveSet};
use suntracker::hw::{AnyAxis, StepperAxis};
use suntracker::mechanics::bridge_config;
use suntracker_avr::{chip, InputPin, OutputPin, PortInputPin, PortOutputPin, Usart0};

use crate::dc::{self, DcBoard, MegaDcAxis, MegaLinearHallAxis, MegaLinearPotAxis, MegaTimedAxis};
use crate::refused;
use crate::servo::{self, MegaServoAxis};

/// The drive kinds this board builds an axis of.
pub const DRIVES: DriveSet = DriveSet::STEPPER
    .with(DriveKind::ServoEncoder)
    .with(DriveKind::DcHall)
    .with(DriveKind::Timed)
    .with(DriveKind::LinearHall)
    .with(DriveKind::LinearPot);

/// A stepper axis of this board: its bridge on port A, its switches on port C.
pub type MegaStepperAxis<'p> = StepperAxis<
    PortOutputPin<'p, chip::PORTA>,
    PortInputPin<'p, chip::PORTC>,
    PortInputPin<'p, chip::PORTC>,
>;

/// One axis of this board, of the kind its configuration names.
pub type MegaAxis<'p> = AnyAxis<
    MegaStepperAxis<'p>,
    MegaDcAxis<'p>,
    MegaTimedAxis<'p>,
    MegaLinearHallAxis<'p>,
    MegaLinearPotAxis<'p>,
    MegaServoAxis<'p>,
>;

/// The stepper axis `index` (0: C, its bridge on PA0–PA3, its limit
/// switches on PC0/PC2; 1: A on PA4–PA7 and PC1/PC3), the lower switch
/// also the home switch (active low, pulled up); `None` when the driver
/// refuses the board's bridge settings (it takes them).
#[inline(never)]
fn stepper_axis<'p>(
    porta: &'p chip::PORTA,
    portc: &'p chip::PORTC,
    index: usize,
) -> Option<MegaStepperAxis<'p>> {
    let (pins, limits, home) = if index == 0 {
        let pins = BridgePins {
            in1: OutputPin::<_, 0>::new(porta, false).erase(),
            in2: OutputPin::<_, 1>::new(porta, false).erase(),
            in3: OutputPin::<_, 2>::new(porta, false).erase(),
            in4: OutputPin::<_, 3>::new(porta, false).erase(),
        };
        let limits = LimitSwitches {
            min: Some(InputPin::<_, 0>::new(portc, true).erase()),
            max: Some(InputPin::<_, 2>::new(portc, true).erase()),
            active_low: true,
        };
        (pins, limits, InputPin::<_, 0>::new(portc, true).erase())
    } else {
        let pins = BridgePins {
            in1: OutputPin::<_, 4>::new(porta, false).erase(),
            in2: OutputPin::<_, 5>::new(porta, false).erase(),
            in3: OutputPin::<_, 6>::new(porta, false).erase(),
            in4: OutputPin::<_, 7>::new(porta, false).erase(),
        };
        let limits = LimitSwitches {
            min: Some(InputPin::<_, 1>::new(portc, true).erase()),
            max: Some(InputPin::<_, 3>::new(portc, true).erase()),
            active_low: true,
        };
        (pins, limits, InputPin::<_, 1>::new(portc, true).erase())
    };
    HBridgeStepper::new(pins, limits, bridge_config())
        .ok()
        .map(|s| StepperAxis::new(s, home, true))
}

/// The stepper axis `index` as one of this board's axes, or the board
/// halted (`refused`).
#[inline(never)]
fn stepper<'p>(board: &'p DcBoard<'p>, index: usize, log: &mut Usart0) -> MegaAxis<'p> {
    match stepper_axis(board.porta, board.portc, index) {
        Some(axis) => AnyAxis::Stepper(axis),
        None => refused(log),
    }
}

/// The axis `index` of the kind `config.drive` names (a timed axis's runs
/// calibrated at `calibration_supply_mv`, `supply.calibration_mv`); the
/// board halted (`refused`) for a kind this board does not build (not in
/// [`DRIVES`]) or a drive that refuses its settings. Not inlined: one
/// copy, called for each axis.
///
/// Each builder returns the axis itself, written straight into its place
/// in the caller's array, and halts there when refused: returned as an
/// `Option`, each axis was copied once more on the way (a frame of the
/// axis's size, 292 B, on the power-on's stack, the deepest there is).
#[inline(never)]
pub fn axis<'p>(
    board: &'p DcBoard<'p>,
    index: usize,
    config: &AxisConfig,
    calibration_supply_mv: u16,
    log: &mut Usart0,
) -> MegaAxis<'p> {
    // Each kind built in a function of its own, not inlined (its
    // temporaries on the stack only while it runs, not all kinds' at once
    // in this frame: 1,315 B of it on the ATmega2560 when they were).
    match DriveKind::from_code(config.drive) {
        Some(DriveKind::Stepper) => stepper(board, index, log),
        Some(DriveKind::ServoEncoder) => servo::servo_axis(board, index, config, log),
        Some(DriveKind::DcHall) => dc::dc_axis(board, index, config, log),
        Some(DriveKind::Timed) => dc::timed_axis(board, index, config, calibration_supply_mv, log),
        Some(DriveKind::LinearHall) => dc::linear_hall_axis(board, index, config, log),
        Some(DriveKind::LinearPot) => dc::linear_pot_axis(board, index, config, log),
        _ => refused(log),
    }
}
