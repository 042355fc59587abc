//! One axis of whichever kind its configuration names (`axis.c.drive`,
//! `axis.a.drive`), chosen when a board builds its axes at power-on: a
//! stepper ([`super::StepperAxis`]), a DC gear motor closed on its Hall
//! count ([`super::DcAxis`]) or a DC motor moved by time
//! ([`super::TimedAxis`]). The controller drives both axes of one type, so a
//! board that takes more than one kind by configuration hands it this enum;
//! each method passes to the axis inside.

use crate::firmware::Motion;
use crate::motion::{AxisDrive, DriveFault};

/// An axis of one of three kinds: `S` a stepper, `D` a DC axis with
/// feedback, `T` a timed axis (any [`AxisDrive`] and [`Motion`] fit each
/// place; the names say what the boards put there; `Infallible` stands for
/// a kind the image does not build).
#[derive(Debug)]
pub enum AnyAxis<S, D, T> {
    /// A stepper on its bridge or driver.
    Stepper(S),
    /// A DC gear motor on its H-bridge, closed on its Hall count.
    Dc(D),
    /// A DC motor on its H-bridge, moved by time.
    Timed(T),
}

/// A drive error of an [`AnyAxis`] (the controller takes any as a failed
/// move; a DC or timed motor's own faults come through
/// [`AxisDrive::take_fault`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnyAxisError {
    /// The stepper's pins or its switches.
    Stepper,
    /// A DC or timed axis's bridge, switch or current sense, or a motor
    /// fault.
    Motor,
}

impl<S: Motion, D: Motion, T: Motion> Motion for AnyAxis<S, D, T> {
    fn service(&mut self, now_ms: u64) -> bool {
        match self {
            AnyAxis::Stepper(s) => s.service(now_ms),
            AnyAxis::Dc(d) => d.service(now_ms),
            AnyAxis::Timed(t) => t.service(now_ms),
        }
    }
}

impl<S: AxisDrive, D: AxisDrive, T: AxisDrive> AxisDrive for AnyAxis<S, D, T> {
    type Error = AnyAxisError;
    // The associated `SELF_WATCHED` stays false: which axis watches its
    // own motor is known at run time only (`self_watched`).
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        match self {
            AnyAxis::Stepper(s) => s.move_counts(counts).map_err(|_| AnyAxisError::Stepper),
            AnyAxis::Dc(d) => d.move_counts(counts).map_err(|_| AnyAxisError::Motor),
            AnyAxis::Timed(t) => t.move_counts(counts).map_err(|_| AnyAxisError::Motor),
        }
    }
    fn pending(&self) -> i32 {
        match self {
            AnyAxis::Stepper(s) => s.pending(),
            AnyAxis::Dc(d) => d.pending(),
            AnyAxis::Timed(t) => t.pending(),
        }
    }
    fn stop(&mut self) -> Result<(), Self::Error> {
        match self {
            AnyAxis::Stepper(s) => s.stop().map_err(|_| AnyAxisError::Stepper),
            AnyAxis::Dc(d) => d.stop().map_err(|_| AnyAxisError::Motor),
            AnyAxis::Timed(t) => t.stop().map_err(|_| AnyAxisError::Motor),
        }
    }
    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        match self {
            AnyAxis::Stepper(s) => s.at_limit().map_err(|_| AnyAxisError::Stepper),
            AnyAxis::Dc(d) => d.at_limit().map_err(|_| AnyAxisError::Motor),
            AnyAxis::Timed(t) => t.at_limit().map_err(|_| AnyAxisError::Motor),
        }
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        match self {
            AnyAxis::Stepper(s) => s.encoder_deg().map_err(|_| AnyAxisError::Stepper),
            AnyAxis::Dc(d) => d.encoder_deg().map_err(|_| AnyAxisError::Motor),
            AnyAxis::Timed(t) => t.encoder_deg().map_err(|_| AnyAxisError::Motor),
        }
    }
    fn self_watched(&self) -> bool {
        match self {
            AnyAxis::Stepper(s) => s.self_watched(),
            AnyAxis::Dc(d) => d.self_watched(),
            AnyAxis::Timed(t) => t.self_watched(),
        }
    }
    fn take_fault(&mut self) -> Option<DriveFault> {
        match self {
            AnyAxis::Stepper(s) => s.take_fault(),
            AnyAxis::Dc(d) => d.take_fault(),
            AnyAxis::Timed(t) => t.take_fault(),
        }
    }
    fn fault_latched(&self) -> bool {
        match self {
            AnyAxis::Stepper(s) => s.fault_latched(),
            AnyAxis::Dc(d) => d.fault_latched(),
            AnyAxis::Timed(t) => t.fault_latched(),
        }
    }
    fn clear_fault(&mut self) {
        match self {
            AnyAxis::Stepper(s) => s.clear_fault(),
            AnyAxis::Dc(d) => d.clear_fault(),
            AnyAxis::Timed(t) => t.clear_fault(),
        }
    }
    fn rebase_counts(&mut self, counts: i32) {
        match self {
            AnyAxis::Stepper(s) => s.rebase_counts(counts),
            AnyAxis::Dc(d) => d.rebase_counts(counts),
            AnyAxis::Timed(t) => t.rebase_counts(counts),
        }
    }
    fn switch_stops(&mut self, on: bool) {
        match self {
            AnyAxis::Stepper(s) => s.switch_stops(on),
            AnyAxis::Dc(d) => d.switch_stops(on),
            AnyAxis::Timed(t) => t.switch_stops(on),
        }
    }
    fn rebase_at_rest(&mut self) {
        match self {
            AnyAxis::Stepper(s) => s.rebase_at_rest(),
            AnyAxis::Dc(d) => d.rebase_at_rest(),
            AnyAxis::Timed(t) => t.rebase_at_rest(),
        }
    }
    fn set_supply_mv(&mut self, supply_mv: u32) {
        match self {
            AnyAxis::Stepper(s) => s.set_supply_mv(supply_mv),
            AnyAxis::Dc(d) => d.set_supply_mv(supply_mv),
            AnyAxis::Timed(t) => t.set_supply_mv(supply_mv),
        }
    }
}

/// A kind an image does not build: `Infallible` in its place of an
/// [`AnyAxis`] (no value exists, so that variant is never built and its
/// arms are no code).
impl Motion for core::convert::Infallible {
    fn service(&mut self, _now_ms: u64) -> bool {
        match *self {}
    }
}

/// See the [`Motion`] impl.
impl AxisDrive for core::convert::Infallible {
    type Error = core::convert::Infallible;
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
