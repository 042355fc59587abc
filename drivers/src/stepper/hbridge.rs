//! Bipolar stepper through an H-bridge (L298N class, or discrete bridges behind
//! optocouplers as in seed *li-2022*), four `OutputPin`s.
//!
//! Pins: `IN1` = coil A+, `IN2` = coil A−, `IN3` = coil B+, `IN4` = coil B−
//! (a high input drives that coil end high). Coil table, half-step phase 0..7
//! (1 = high), forward = increasing phase:
//!
//! | phase | IN1 IN2 IN3 IN4 | coils       | used by      |
//! |-------|-----------------|-------------|--------------|
//! | 0     | 1 0 0 0         | A+          | wave, half   |
//! | 1     | 1 0 1 0         | A+ B+       | full, half   |
//! | 2     | 0 0 1 0         | B+          | wave, half   |
//! | 3     | 0 1 1 0         | A− B+       | full, half   |
//! | 4     | 0 1 0 0         | A−          | wave, half   |
//! | 5     | 0 1 0 1         | A− B−       | full, half   |
//! | 6     | 0 0 0 1         | B−          | wave, half   |
//! | 7     | 1 0 0 1         | A+ B−       | full, half   |
//!
//! Wave drive (one phase on) uses the even phases, full step (two phases on,
//! full torque) the odd ones, half step all eight; wave and full steps move
//! two phases per step. Every step writes all four pins, the ones going low
//! first and then the ones going high (break before make, so no bridge leg is
//! ever commanded high on both sides). Releasing the coils sets all four low:
//! no holding current while idle (e.g. all night).

use embedded_hal::digital::{InputPin, OutputPin};

use super::planner::{Due, Planner};
use super::ramp::Ramp;
use super::{Direction, Error, Event, LimitSwitches};

/// Half-step coil table, `[IN1, IN2, IN3, IN4]`.
const PHASES: [[bool; 4]; 8] = [
    [true, false, false, false],
    [true, false, true, false],
    [false, false, true, false],
    [false, true, true, false],
    [false, true, false, false],
    [false, true, false, true],
    [false, false, false, true],
    [true, false, false, true],
];

/// Drive sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepMode {
    /// One coil at a time (even phases), least current.
    Wave,
    /// Two coils at a time (odd phases), full torque.
    Full,
    /// Alternating one and two coils, twice the resolution.
    Half,
}

impl StepMode {
    fn phase_increment(self) -> u8 {
        match self {
            StepMode::Half => 1,
            StepMode::Wave | StepMode::Full => 2,
        }
    }

    fn first_phase(self) -> u8 {
        match self {
            StepMode::Full => 1,
            StepMode::Wave | StepMode::Half => 0,
        }
    }
}

/// Configuration of an H-bridge stepper.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Drive sequence.
    pub mode: StepMode,
    /// Speed profile (in steps of `mode`).
    pub ramp: Ramp,
    /// Keep the coils energised this long after the last step before releasing
    /// them (lets the rotor settle); 0 = release in the same `poll`.
    pub settle_us: u32,
    /// Release the coils when idle (no holding current).
    pub release_when_idle: bool,
}

/// The four bridge inputs.
#[derive(Debug)]
pub struct BridgePins<P> {
    /// IN1, coil A+.
    pub in1: P,
    /// IN2, coil A−.
    pub in2: P,
    /// IN3, coil B+.
    pub in3: P,
    /// IN4, coil B−.
    pub in4: P,
}

/// A bipolar stepper behind an H-bridge.
#[derive(Debug)]
pub struct HBridgeStepper<P, L> {
    pins: BridgePins<P>,
    limits: LimitSwitches<L>,
    planner: Planner,
    config: Config,
    phase: u8,
    energised: bool,
    /// The coils have been energised at `phase` since power-on: the rotor
    /// rests there (before that its phase is unknown).
    rotor_at_phase: bool,
    release_at_us: Option<u64>,
}

impl<P, L, E> HBridgeStepper<P, L>
where
    P: OutputPin<Error = E>,
    L: InputPin<Error = E>,
{
    /// Creates the driver at position 0 with the coils off. No pin is touched
    /// until the first `poll` or `release`.
    pub fn new(
        pins: BridgePins<P>,
        limits: LimitSwitches<L>,
        config: Config,
    ) -> Result<Self, Error<E>> {
        let planner = Planner::new(config.ramp).map_err(Error::InvalidConfig)?;
        Ok(Self {
            pins,
            limits,
            planner,
            config,
            phase: config.mode.first_phase(),
            energised: false,
            rotor_at_phase: false,
            release_at_us: None,
        })
    }

    /// Gives the pins back.
    pub fn destroy(self) -> (BridgePins<P>, LimitSwitches<L>) {
        (self.pins, self.limits)
    }

    /// Position in steps of the configured mode.
    pub fn position(&self) -> i32 {
        self.planner.position()
    }

    /// Target in steps.
    pub fn target(&self) -> i32 {
        self.planner.target()
    }

    /// True while moving.
    pub fn is_moving(&self) -> bool {
        self.planner.is_moving()
    }

    /// True while the coils carry current.
    pub fn is_energised(&self) -> bool {
        self.energised
    }

    /// Current half-step phase 0..7 (the row of the coil table).
    pub fn phase(&self) -> u8 {
        self.phase
    }

    /// Redefines the position (after homing); refused (false) while moving.
    pub fn set_position(&mut self, position: i32) -> bool {
        self.planner.set_position(position)
    }

    /// Go to an absolute position.
    pub fn move_to(&mut self, target: i32) {
        self.release_at_us = None;
        self.planner.move_to(target);
    }

    /// Go by a relative number of steps.
    pub fn move_by(&mut self, delta: i32) {
        self.release_at_us = None;
        self.planner.move_by(delta);
    }

    /// Decelerate to rest along the ramp.
    pub fn stop(&mut self) {
        self.planner.stop();
    }

    /// Drive the state machine; call often (every main-loop pass).
    pub fn poll(&mut self, now_us: u64) -> Result<Event, Error<E>> {
        match self.planner.due(now_us) {
            Due::Idle => {
                if let Some(t) = self.release_at_us {
                    if now_us >= t {
                        self.release()?;
                    }
                }
                Ok(Event::Idle)
            }
            Due::Wait => Ok(Event::Waiting),
            Due::Step(dir) => {
                if let Some(limit) = self.limits.blocking(dir).map_err(Error::Comm)? {
                    self.planner.halt();
                    self.release()?;
                    return Ok(Event::LimitReached(limit));
                }
                if !self.energised && self.rotor_at_phase {
                    // Released after a move: the rotor rests at `phase`.
                    // Hold it there first, then step. Energising the next
                    // phase straight from all-low passes through that
                    // phase's first coil alone, which (depending on the
                    // direction) can lie three half-phases from the rotor.
                    self.write_phase()?;
                }
                let inc = self.config.mode.phase_increment();
                self.phase = match dir {
                    Direction::Forward => (self.phase + inc) % 8,
                    Direction::Backward => (self.phase + 8 - inc) % 8,
                };
                self.write_phase()?;
                if self.planner.stepped(now_us) {
                    if self.config.release_when_idle {
                        if self.config.settle_us == 0 {
                            self.release()?;
                        } else {
                            self.release_at_us =
                                Some(now_us.saturating_add(u64::from(self.config.settle_us)));
                        }
                    }
                    Ok(Event::Arrived)
                } else {
                    Ok(Event::Stepped)
                }
            }
        }
    }

    /// Switches all four bridge inputs low: no coil current.
    pub fn release(&mut self) -> Result<(), Error<E>> {
        self.release_at_us = None;
        for p in [
            &mut self.pins.in1,
            &mut self.pins.in2,
            &mut self.pins.in3,
            &mut self.pins.in4,
        ] {
            p.set_low().map_err(Error::Comm)?;
        }
        self.energised = false;
        Ok(())
    }

    fn write_phase(&mut self) -> Result<(), Error<E>> {
        let levels = PHASES
            .get(usize::from(self.phase))
            .copied()
            .unwrap_or([false; 4]);
        let mut pins = [
            &mut self.pins.in1,
            &mut self.pins.in2,
            &mut self.pins.in3,
            &mut self.pins.in4,
        ];
        // Break before make: lows first, then highs.
        for (p, &high) in pins.iter_mut().zip(levels.iter()) {
            if !high {
                p.set_low().map_err(Error::Comm)?;
            }
        }
        for (p, &high) in pins.iter_mut().zip(levels.iter()) {
            if high {
                p.set_high().map_err(Error::Comm)?;
            }
        }
        self.energised = true;
        self.rotor_at_phase = true;
        Ok(())
    }
}
