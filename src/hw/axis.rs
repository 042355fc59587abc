//! [`AxisDrive`] over the H-bridge stepper driver and a home limit switch.
//!
//! The driver is non-blocking: [`AxisDrive::move_counts`] only sets a new
//! target, and the board's main loop calls [`StepperAxis::poll`] as often as
//! it can (every pass, or from a timer) so that the steps come out on time.
//! [`AxisDrive::pending`] is what the driver still has to step, so the
//! controller sees a move in progress until the last step is out.

use drivers::stepper::hbridge::HBridgeStepper;
use drivers::stepper::{Error as StepperError, Event, Limit};
use embedded_hal::digital::{InputPin, OutputPin};

use crate::motion::AxisDrive;

/// Errors of a stepper axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepperAxisError<E> {
    /// The stepper driver failed (a pin write, or its configuration).
    Stepper(StepperError<E>),
    /// The home switch could not be read.
    Switch(E),
}

/// One tracker axis driven by a bipolar stepper through an H-bridge, with
/// the homing limit switch read on its own input.
///
/// Give the driver the same switch as its `min` limit (on a board, the same
/// signal wired to two inputs, or a second contact) so that it also refuses
/// to step past it: homing then stops on the switch within one step.
#[derive(Debug)]
pub struct StepperAxis<P, L, H> {
    stepper: HBridgeStepper<P, L>,
    home: H,
    home_active_low: bool,
    limit_stops: u32,
    last_event: Event,
}

impl<P, L, H, E> StepperAxis<P, L, H>
where
    P: OutputPin<Error = E>,
    L: InputPin<Error = E>,
    H: InputPin<Error = E>,
{
    /// An axis over `stepper`; `home` reads the homing switch, which is
    /// closed when its level is low if `home_active_low`.
    pub fn new(stepper: HBridgeStepper<P, L>, home: H, home_active_low: bool) -> Self {
        StepperAxis {
            stepper,
            home,
            home_active_low,
            limit_stops: 0,
            last_event: Event::Idle,
        }
    }

    /// Runs the driver: takes the step due at `now_us`, if any. Call every
    /// pass of the main loop.
    pub fn poll(&mut self, now_us: u64) -> Result<Event, StepperAxisError<E>> {
        let ev = self
            .stepper
            .poll(now_us)
            .map_err(StepperAxisError::Stepper)?;
        if let Event::LimitReached(_) = ev {
            drivers::counter::count_up(&mut self.limit_stops);
        }
        self.last_event = ev;
        Ok(ev)
    }

    /// The driver's position, steps since power-on (its own count).
    pub fn position_steps(&self) -> i32 {
        self.stepper.position()
    }

    /// True while the motor is stepping.
    pub fn is_moving(&self) -> bool {
        self.stepper.is_moving()
    }

    /// True while the coils carry current.
    pub fn is_energised(&self) -> bool {
        self.stepper.is_energised()
    }

    /// Motions the driver stopped at a limit switch.
    pub fn limit_stops(&self) -> u32 {
        self.limit_stops
    }

    /// The last event of [`StepperAxis::poll`].
    pub fn last_event(&self) -> Event {
        self.last_event
    }

    /// True when the last poll stopped at the given switch.
    pub fn stopped_at(&self, limit: Limit) -> bool {
        self.last_event == Event::LimitReached(limit)
    }

    /// Gives the driver and the switch input back.
    pub fn destroy(self) -> (HBridgeStepper<P, L>, H) {
        (self.stepper, self.home)
    }
}

impl<P, L, H, E> AxisDrive for StepperAxis<P, L, H>
where
    P: OutputPin<Error = E>,
    L: InputPin<Error = E>,
    H: InputPin<Error = E>,
{
    type Error = StepperAxisError<E>;

    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error> {
        self.stepper.move_by(counts);
        Ok(())
    }

    fn pending(&self) -> i32 {
        // The difference clamped to the i32 range, in 32 bits (no 64-bit
        // subtraction and compare at each of its callers on the AVR), and
        // called rather than written out at each of them.
        drivers::stepper::sat_sub(self.stepper.target(), self.stepper.position())
    }

    /// Decelerates to rest along the driver's ramp (a stepper stopped dead
    /// at speed would lose steps): up to the ramp's stopping distance more
    /// steps are taken after this call.
    fn stop(&mut self) -> Result<(), Self::Error> {
        self.stepper.stop();
        Ok(())
    }

    fn at_limit(&mut self) -> Result<bool, Self::Error> {
        let high = self.home.is_high().map_err(StepperAxisError::Switch)?;
        Ok(high != self.home_active_low)
    }

    /// The driver's `min` switch (the home switch, as [`StepperAxis`]
    /// asks) on or off.
    fn switch_stops(&mut self, on: bool) {
        self.stepper.set_min_limit(on);
    }

    /// The H-bridge axis has no encoder (Li et al. 2022 runs it open loop).
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error> {
        Ok(None)
    }
}
