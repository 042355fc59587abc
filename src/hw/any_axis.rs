//! One axis of whichever kind its configuration names (`axis.c.drive`,
//! `axis.a.drive`), chosen when a board builds its axes at power-on: a
//! stepper ([`super::StepperAxis`]), a DC gear motor closed on its Hall
//! count ([`super::DcAxis`]), a DC motor moved by time
//! ([`super::TimedAxis`]), a linear actuator ([`super::LinearAxis`]) or a
//! continuous servo closed on its encoder ([`super::ServoAxis`]). The
//! controller drives both axes of one type, so a
//! board that takes more than one kind by configuration hands it this enum;
//! each method passes to the axis inside.

use core::convert::Infallible;

use crate::firmware::Motion;
use crate::motion::{AxisDrive, DriveFault};

/// An axis of one of six kinds: `S` a stepper, `D` a DC axis with
/// feedback, `T` a timed axis, `H` a linear actuator on Hall pulses, `P`
/// one on its potentiometer, `V` a continuous servo on its encoder (any
/// [`AxisDrive`] and [`Motion`] fit each place; the names say what the
/// boards put there; `Infallible`, the default of the last three places,
/// stands for a kind the image does not build).
#[derive(Debug)]
pub enum AnyAxis<S, D, T, H = Infallible, P = Infallible, V = Infallible> {
    /// A stepper on its bridge or driver.
    Stepper(S),
    /// A DC gear motor on its H-bridge, closed on its Hall count.
    Dc(D),
    /// A DC motor on its H-bridge, moved by time.
    Timed(T),
    /// A linear actuator on its H-bridge, closed on its Hall pulses.
    LinearHall(H),
    /// A linear actuator on its H-bridge, closed on its potentiometer.
    LinearPot(P),
    /// A continuous-rotation servo, closed on its quadrature encoder.
    ServoEncoder(V),
}

/// A drive error of an [`AnyAxis`] (the controller takes any as a failed
/// move; a DC, timed or linear motor's own faults come through
/// [`AxisDrive::take_fault`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnyAxisError {
    /// The stepper's pins or its switches.
    Stepper,
    /// The servo's PWM channel or its home switch.
    Servo,
    /// A DC, timed or linear axis's bridge, switch, current sense or
    /// feedback, or a motor fault.
    Motor,
}

/// `$e` on the axis inside `$axis` (bound to `$a`), whichever kind it is.
macro_rules! each {
    ($axis:expr, $a:ident => $e:expr) => {
        match $axis {
            AnyAxis::Stepper($a) => $e,
            AnyAxis::Dc($a) => $e,
            AnyAxis::Timed($a) => $e,
            AnyAxis::LinearHall($a) => $e,
            AnyAxis::LinearPot($a) => $e,
            AnyAxis::ServoEncoder($a) => $e,
        }
    };
}

/// `$e`, a `Result`, on the axis inside `$axis`, its error mapped to the
/// kind's [`AnyAxisError`].
macro_rules! each_mapped {
    ($axis:expr, $a:ident => $e:expr) => {
        match $axis {
            AnyAxis::Stepper($a) => $e.map_err(|_| AnyAxisError::Stepper),
            AnyAxis::Dc($a) => $e.map_err(|_| AnyAxisError::Motor),
            AnyAxis::Timed($a) => $e.map_err(|_| AnyAxisError::Motor),
            AnyAxis::LinearHall($a) => $e.map_err(|_| AnyAxisError::Motor),
            AnyAxis::LinearPot($a) => $e.map_err(|_| AnyAxisError::Motor),
            AnyAxis::ServoEncoder($a) => $e.map_err(|_| AnyAxisError::Servo),
        }
    };
}

impl<S: Motion, D: Motion, T: Motion, H: Motion, P: Motion, V: Motion> Motion
    for AnyAxis<S, D, T, H, P, V>
{
    fn service(&mut self, now_ms: u64) -> bool {
        each!(self, a => a.service(now_ms))
    }
    fn due_in_ms(&self, now_ms: u64) -> Option<u32> {
        each!(self, a => a.due_in_ms(now_ms))
    }
}

impl<S, D, T, H, P, V> AxisDrive for AnyAxis<S, D, T, H, P, V>
where
    S: AxisDrive,
    D: AxisDrive,
    T: AxisDrive,
    H: AxisDrive,
    P: AxisDrive,
    V: AxisDrive,
{
    type Error = AnyAxisError;
    // The associated `SELF_WATCHED` stays false: which axis watches its
    // own motor is known at run time only (`self_watched`).
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        each_mapped!(self, a => a.move_counts(counts))
    }
    fn pending(&self) -> i32 {
        each!(self, a => a.pending())
    }
    fn stop(&mut self) -> Result<(), Self::Error> {
        each_mapped!(self, a => a.stop())
    }
    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        each_mapped!(self, a => a.at_limit())
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        each_mapped!(self, a => a.encoder_deg())
    }
    fn self_watched(&self) -> bool {
        each!(self, a => a.self_watched())
    }
    fn take_fault(&mut self) -> Option<DriveFault> {
        each!(self, a => a.take_fault())
    }
    fn fault_latched(&self) -> bool {
        each!(self, a => a.fault_latched())
    }
    fn clear_fault(&mut self) {
        each!(self, a => a.clear_fault())
    }
    fn rebase_counts(&mut self, counts: i32) {
        each!(self, a => a.rebase_counts(counts))
    }
    fn switch_stops(&mut self, on: bool) {
        each!(self, a => a.switch_stops(on))
    }
    fn rebase_at_rest(&mut self) {
        each!(self, a => a.rebase_at_rest())
    }
    fn set_supply_mv(&mut self, supply_mv: u32) {
        each!(self, a => a.set_supply_mv(supply_mv))
    }
}

/// A kind an image does not build: `Infallible` in its place of an
/// [`AnyAxis`] (no value exists, so that variant is never built and its
/// arms are no code).
impl Motion for Infallible {
    fn service(&mut self, _now_ms: u64) -> bool {
        match *self {}
    }
}

/// See the [`Motion`] impl.
impl AxisDrive for Infallible {
    type Error = Infallible;
    fn move_counts(&mut self, _counts: i32) -> Result<(), Self::Error> {
        match *self {}
    }
    fn pending(&self) -> i32 {
        match *self {}
    }
    fn stop(&mut self) -> Result<(), Self::Error> {
        match *self {}
    }
    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        match *self {}
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        match *self {}
    }
}
