//! STEP/DIR(/ENABLE) stepper driver chips (A4988, DRV8825, TMC2208 in legacy mode).
//!
//! Per step: set DIR if it changed and wait the DIR setup time, raise STEP,
//! wait the minimum high time, lower STEP. These waits are the only blocking
//! calls in `poll` (`DelayNs::delay_ns`, ≤ a few µs); the STEP low time and
//! everything longer (the ramp intervals, the wake-up after ENABLE) are
//! scheduled, not waited for. ENABLE is asserted when a move starts and
//! de-asserted when the axis is idle (no holding current).
//!
//! Minimum timings (datasheets): A4988 STEP high ≥ 1 µs, low ≥ 1 µs, DIR setup
//! and hold ≥ 200 ns; DRV8825 STEP high ≥ 1.9 µs, low ≥ 1.9 µs, setup and
//! hold ≥ 650 ns.

use embedded_hal::delay::DelayNs;
use embedded_hal::digital::{InputPin, OutputPin};

use super::planner::{Due, Planner};
use super::ramp::{Ramp, RampError};
use super::{Direction, Error, Event, LimitSwitches};

/// Pulse timing of a driver chip.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PulseTiming {
    /// Minimum STEP high time, ns.
    pub step_high_ns: u32,
    /// Minimum STEP low time, ns.
    pub step_low_ns: u32,
    /// DIR setup before the rising STEP edge (and hold after it), ns.
    pub dir_setup_ns: u32,
    /// Time from ENABLE asserted to the first step, µs (scheduled, not blocking).
    pub wake_us: u32,
}

impl PulseTiming {
    /// Allegro A4988.
    pub const A4988: Self = Self {
        step_high_ns: 1_000,
        step_low_ns: 1_000,
        dir_setup_ns: 200,
        wake_us: 0,
    };
    /// TI DRV8825 (wake-up from sleep 1.7 ms, used when nSLEEP is tied to ENABLE).
    pub const DRV8825: Self = Self {
        step_high_ns: 1_900,
        step_low_ns: 1_900,
        dir_setup_ns: 650,
        wake_us: 1_700,
    };
}

/// Configuration of a STEP/DIR axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Speed profile (in microsteps as set on the chip's MS pins).
    pub ramp: Ramp,
    /// Chip timing.
    pub timing: PulseTiming,
    /// DIR low means forward.
    pub invert_dir: bool,
    /// ENABLE is active low (A4988 ¬ENABLE, DRV8825 nENBL).
    pub enable_active_low: bool,
    /// Keep enabled this long after the last step, µs.
    pub settle_us: u32,
}

/// STEP, DIR and the optional ENABLE pin.
#[derive(Debug)]
pub struct StepDirPins<P> {
    /// STEP input of the chip.
    pub step: P,
    /// DIR input of the chip.
    pub dir: P,
    /// ENABLE input of the chip, if wired.
    pub enable: Option<P>,
}

/// A stepper behind a STEP/DIR driver chip.
#[derive(Debug)]
pub struct StepDirStepper<P, L, D> {
    pins: StepDirPins<P>,
    limits: LimitSwitches<L>,
    delay: D,
    planner: Planner,
    config: Config,
    dir_state: Option<Direction>,
    enabled: bool,
    ready_at_us: u64,
    disable_at_us: Option<u64>,
}

impl<P, L, D, E> StepDirStepper<P, L, D>
where
    P: OutputPin<Error = E>,
    L: InputPin<Error = E>,
    D: DelayNs,
{
    /// Creates the driver at position 0, disabled. Refuses a ramp whose
    /// shortest interval cannot hold one STEP pulse plus DIR hold.
    pub fn new(
        pins: StepDirPins<P>,
        limits: LimitSwitches<L>,
        delay: D,
        config: Config,
    ) -> Result<Self, Error<E>> {
        let planner = Planner::new(config.ramp).map_err(Error::InvalidConfig)?;
        let t = config.timing;
        let pulse_ns = u64::from(t.step_high_ns) + u64::from(t.step_low_ns.max(t.dir_setup_ns));
        let min_interval_ns = 1_000 * u64::from(config.ramp.interval_us(u32::MAX));
        if pulse_ns > min_interval_ns {
            return Err(Error::InvalidConfig(RampError::PulseTooLong));
        }
        Ok(Self {
            pins,
            limits,
            delay,
            planner,
            config,
            dir_state: None,
            enabled: false,
            ready_at_us: 0,
            disable_at_us: None,
        })
    }

    /// Gives the pins and the delay back.
    pub fn destroy(self) -> (StepDirPins<P>, LimitSwitches<L>, D) {
        (self.pins, self.limits, self.delay)
    }

    /// Position in (micro)steps.
    pub fn position(&self) -> i32 {
        self.planner.position()
    }

    /// True while moving.
    pub fn is_moving(&self) -> bool {
        self.planner.is_moving()
    }

    /// True while ENABLE is asserted.
    pub fn is_enabled(&self) -> bool {
        self.enabled
    }

    /// Redefines the position (after homing); refused (false) while moving.
    pub fn set_position(&mut self, position: i32) -> bool {
        self.planner.set_position(position)
    }

    /// Go to an absolute position.
    pub fn move_to(&mut self, target: i32) {
        self.disable_at_us = None;
        self.planner.move_to(target);
    }

    /// Go by a relative number of steps.
    pub fn move_by(&mut self, delta: i32) {
        self.disable_at_us = None;
        self.planner.move_by(delta);
    }

    /// Decelerate to rest along the ramp.
    pub fn stop(&mut self) {
        self.planner.stop();
    }

    /// Drive the state machine; call often.
    pub fn poll(&mut self, now_us: u64) -> Result<Event, Error<E>> {
        match self.planner.due(now_us) {
            Due::Idle => {
                if let Some(t) = self.disable_at_us {
                    if now_us >= t {
                        self.disable()?;
                    }
                }
                Ok(Event::Idle)
            }
            Due::Wait => Ok(Event::Waiting),
            Due::Step(dir) => {
                if let Some(limit) = self.limits.blocking(dir).map_err(Error::Comm)? {
                    self.planner.halt();
                    self.disable()?;
                    return Ok(Event::LimitReached(limit));
                }
                if !self.enabled {
                    self.enable()?;
                    self.ready_at_us = now_us.saturating_add(u64::from(self.config.timing.wake_us));
                }
                if now_us < self.ready_at_us {
                    return Ok(Event::Waiting);
                }
                if self.dir_state != Some(dir) {
                    let high = (dir == Direction::Forward) != self.config.invert_dir;
                    set(&mut self.pins.dir, high)?;
                    self.dir_state = Some(dir);
                    self.delay.delay_ns(self.config.timing.dir_setup_ns);
                }
                self.pins.step.set_high().map_err(Error::Comm)?;
                self.delay.delay_ns(self.config.timing.step_high_ns);
                self.pins.step.set_low().map_err(Error::Comm)?;
                if self.planner.stepped(now_us) {
                    if self.config.settle_us == 0 {
                        self.disable()?;
                    } else {
                        self.disable_at_us =
                            Some(now_us.saturating_add(u64::from(self.config.settle_us)));
                    }
                    Ok(Event::Arrived)
                } else {
                    Ok(Event::Stepped)
                }
            }
        }
    }

    fn enable(&mut self) -> Result<(), Error<E>> {
        let level = !self.config.enable_active_low;
        if let Some(p) = self.pins.enable.as_mut() {
            set(p, level)?;
        }
        self.enabled = true;
        Ok(())
    }

    /// De-asserts ENABLE (outputs off, no holding current).
    pub fn disable(&mut self) -> Result<(), Error<E>> {
        self.disable_at_us = None;
        let level = self.config.enable_active_low;
        if let Some(p) = self.pins.enable.as_mut() {
            set(p, level)?;
        }
        self.enabled = false;
        Ok(())
    }
}

fn set<P: OutputPin>(p: &mut P, high: bool) -> Result<(), Error<P::Error>> {
    if high {
        p.set_high().map_err(Error::Comm)
    } else {
        p.set_low().map_err(Error::Comm)
    }
}
