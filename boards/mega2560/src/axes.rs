//! The board's two axes, each of the kind its configuration names
//! (`axis.c.drive`, `axis.a.drive`), built at power-on: a stepper on its
//! H-bridge (0, `stepper`: Li et al.'s (2022) build, the pins in the crate's
//! table), a DC gear motor on an IBT-2 closed on its Hall encoder (2,
//! `dc_hall`: [`crate::dc`]) or a DC motor on the same IBT-2 moved by time
//! without feedback (5, `timed`: [`crate::dc::timed_axis`]). The console
//! refuses the other kinds ([`DRIVES`]); a kind changed by `set` is built
//! at the next power-on (`save`, then reset).

use drivers::stepper::hbridge::{BridgePins, HBridgeStepper};
use drivers::stepper::LimitSwitches;
use suntracker::config::{AxisConfig, DriveKind, DriveSet};
use suntracker::firmware::Motion;
use suntracker::hw::StepperAxis;
use suntracker::mechanics::bridge_config;
use suntracker::motion::{AxisDrive, DriveFault};
use suntracker_avr::{chip, InputPin, OutputPin, PortInputPin, PortOutputPin};

use crate::dc::{self, DcBoard, MegaDcAxis, MegaTimedAxis};

/// The drive kinds this board builds an axis of.
pub const DRIVES: DriveSet = DriveSet::STEPPER
    .with(DriveKind::DcHall)
    .with(DriveKind::Timed);

/// A stepper axis of this board: its bridge on port A, its switches on port C.
pub type MegaStepperAxis<'p> = StepperAxis<
    PortOutputPin<'p, chip::PORTA>,
    PortInputPin<'p, chip::PORTC>,
    PortInputPin<'p, chip::PORTC>,
>;

/// One axis of this board, of the kind its configuration names.
pub enum MegaAxis<'p> {
    /// A stepper on its H-bridge.
    Stepper(MegaStepperAxis<'p>),
    /// A DC gear motor on an IBT-2 with its Hall encoder.
    Dc(MegaDcAxis<'p>),
    /// A DC motor on an IBT-2, moved by time.
    Timed(MegaTimedAxis<'p>),
}

/// A drive error of either kind (the controller takes any as a failed
/// move; a DC motor's own faults come through [`AxisDrive::take_fault`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MegaAxisError {
    /// The stepper's pins or its home switch.
    Stepper,
    /// A DC or timed axis's bridge, switch or current sense, or a motor
    /// fault.
    Dc,
}

impl Motion for MegaAxis<'_> {
    fn service(&mut self, now_us: u64) -> bool {
        match self {
            MegaAxis::Stepper(s) => s.service(now_us),
            MegaAxis::Dc(d) => d.service(now_us),
            MegaAxis::Timed(t) => t.service(now_us),
        }
    }
}

impl AxisDrive for MegaAxis<'_> {
    type Error = MegaAxisError;
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        match self {
            MegaAxis::Stepper(s) => s.move_counts(counts).map_err(|_| MegaAxisError::Stepper),
            MegaAxis::Dc(d) => d.move_counts(counts).map_err(|_| MegaAxisError::Dc),
            MegaAxis::Timed(t) => t.move_counts(counts).map_err(|_| MegaAxisError::Dc),
        }
    }
    fn pending(&self) -> i32 {
        match self {
            MegaAxis::Stepper(s) => s.pending(),
            MegaAxis::Dc(d) => d.pending(),
            MegaAxis::Timed(t) => t.pending(),
        }
    }
    fn stop(&mut self) -> Result<(), Self::Error> {
        match self {
            MegaAxis::Stepper(s) => s.stop().map_err(|_| MegaAxisError::Stepper),
            MegaAxis::Dc(d) => d.stop().map_err(|_| MegaAxisError::Dc),
            MegaAxis::Timed(t) => t.stop().map_err(|_| MegaAxisError::Dc),
        }
    }
    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        match self {
            MegaAxis::Stepper(s) => s.at_limit().map_err(|_| MegaAxisError::Stepper),
            MegaAxis::Dc(d) => d.at_limit().map_err(|_| MegaAxisError::Dc),
            MegaAxis::Timed(t) => t.at_limit().map_err(|_| MegaAxisError::Dc),
        }
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        match self {
            MegaAxis::Stepper(s) => s.encoder_deg().map_err(|_| MegaAxisError::Stepper),
            MegaAxis::Dc(d) => d.encoder_deg().map_err(|_| MegaAxisError::Dc),
            MegaAxis::Timed(t) => t.encoder_deg().map_err(|_| MegaAxisError::Dc),
        }
    }
    // The associated `SELF_WATCHED` stays false: which axis watches its
    // own motor is known at run time only.
    fn self_watched(&self) -> bool {
        matches!(self, MegaAxis::Dc(_) | MegaAxis::Timed(_))
    }
    fn take_fault(&mut self) -> Option<DriveFault> {
        match self {
            MegaAxis::Stepper(s) => s.take_fault(),
            MegaAxis::Dc(d) => d.take_fault(),
            MegaAxis::Timed(t) => t.take_fault(),
        }
    }
    fn fault_latched(&self) -> bool {
        match self {
            MegaAxis::Stepper(s) => s.fault_latched(),
            MegaAxis::Dc(d) => d.fault_latched(),
            MegaAxis::Timed(t) => t.fault_latched(),
        }
    }
    fn clear_fault(&mut self) {
        match self {
            MegaAxis::Stepper(s) => s.clear_fault(),
            MegaAxis::Dc(d) => d.clear_fault(),
            MegaAxis::Timed(t) => t.clear_fault(),
        }
    }
    fn rebase_counts(&mut self, counts: i32) {
        match self {
            MegaAxis::Stepper(s) => s.rebase_counts(counts),
            MegaAxis::Dc(d) => d.rebase_counts(counts),
            MegaAxis::Timed(t) => t.rebase_counts(counts),
        }
    }
    fn switch_stops(&mut self, on: bool) {
        match self {
            MegaAxis::Stepper(s) => s.switch_stops(on),
            MegaAxis::Dc(d) => d.switch_stops(on),
            MegaAxis::Timed(t) => t.switch_stops(on),
        }
    }
}

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

/// The axis `index` of the kind `config.drive` names; `None` for a kind
/// this board does not build (not in [`DRIVES`]) or a drive that refuses
/// its settings.
pub fn axis<'p>(board: &'p DcBoard<'p>, index: usize, config: &AxisConfig) -> Option<MegaAxis<'p>> {
    match DriveKind::from_code(config.drive)? {
        DriveKind::Stepper => stepper_axis(board.porta, board.portc, index).map(MegaAxis::Stepper),
        DriveKind::DcHall => dc::dc_axis(board, index, config).map(MegaAxis::Dc),
        DriveKind::Timed => dc::timed_axis(board, index, config).map(MegaAxis::Timed),
        _ => None,
    }
}
