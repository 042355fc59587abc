//! H-bridge stepper: exact pin transactions written from the coil table
//! (IN1 = A+, IN2 = A−, IN3 = B+, IN4 = B−; half-step phases
//! 0 A+, 1 A+B+, 2 B+, 3 A−B+, 4 A−, 5 A−B−, 6 B−, 7 A+B−), lows written before highs.

use drivers::stepper::hbridge::{BridgePins, Config, HBridgeStepper, StepMode};
use drivers::stepper::ramp::{Ramp, RampError};
use drivers::stepper::{Error, Event, Limit, LimitSwitches};
use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};

use State::{High as H, Low as L};

const RAMP: Ramp = Ramp {
    start_speed_sps: 100,
    max_speed_sps: 1000,
    accel_sps2: 10_000,
};

fn pins(in1: &[State], in2: &[State], in3: &[State], in4: &[State]) -> BridgePins<Pin> {
    let p = |s: &[State]| Pin::new(&s.iter().map(|&x| T::set(x)).collect::<Vec<_>>());
    BridgePins {
        in1: p(in1),
        in2: p(in2),
        in3: p(in3),
        in4: p(in4),
    }
}

fn config(mode: StepMode) -> Config {
    Config {
        mode,
        ramp: RAMP,
        settle_us: 0,
        release_when_idle: true,
    }
}

fn done(d: HBridgeStepper<Pin, Pin>) {
    let (mut p, l) = d.destroy();
    for pin in [&mut p.in1, &mut p.in2, &mut p.in3, &mut p.in4] {
        pin.done();
    }
    for mut pin in [l.min, l.max].into_iter().flatten() {
        pin.done();
    }
}

#[test]
fn half_step_forward_three_steps_then_release() {
    // Phases 1 (A+B+), 2 (B+), 3 (A−B+), then all low.
    let p = pins(&[H, L, L, L], &[L, L, H, L], &[H, H, H, L], &[L, L, L, L]);
    let mut m = HBridgeStepper::new(p, LimitSwitches::none(), config(StepMode::Half)).unwrap();
    m.move_to(3);
    assert_eq!(m.poll(0).unwrap(), Event::Stepped);
    // Interval after step 1: level min(1, 2) = 1: v = isqrt(100² + 2·10000·1) = isqrt(30000) = 173,
    // 1e6 / 173 = 5780.3 -> 5780 µs.
    assert_eq!(m.poll(5_779).unwrap(), Event::Waiting);
    assert_eq!(m.poll(5_780).unwrap(), Event::Stepped);
    // After step 2: level min(2, 1) = 1 again (deceleration mirrors acceleration).
    assert_eq!(m.poll(11_559).unwrap(), Event::Waiting);
    assert_eq!(m.poll(11_560).unwrap(), Event::Arrived);
    assert_eq!((m.position(), m.phase(), m.is_energised()), (3, 3, false));
    assert_eq!(m.poll(20_000).unwrap(), Event::Idle);
    done(m);
}

#[test]
fn wave_backward_two_steps() {
    // Start phase 0; backward by two half-phases: 6 (B−), 4 (A−); release.
    let p = pins(&[L, L, L], &[L, H, L], &[L, L, L], &[H, L, L]);
    let mut m = HBridgeStepper::new(p, LimitSwitches::none(), config(StepMode::Wave)).unwrap();
    m.move_by(-2);
    assert_eq!(m.poll(0).unwrap(), Event::Stepped);
    // Two-step move: level min(1, 1) = 1 -> 5780 µs.
    assert_eq!(m.poll(5_780).unwrap(), Event::Arrived);
    assert_eq!((m.position(), m.phase()), (-2, 4));
    done(m);
}

#[test]
fn full_step_forward_two_steps() {
    // Start phase 1 (A+B+); forward: 3 (A−B+), 5 (A−B−); release.
    let p = pins(&[L, L, L], &[H, H, L], &[H, L, L], &[L, H, L]);
    let mut m = HBridgeStepper::new(p, LimitSwitches::none(), config(StepMode::Full)).unwrap();
    m.move_to(2);
    assert_eq!(m.poll(0).unwrap(), Event::Stepped);
    assert_eq!(m.poll(5_780).unwrap(), Event::Arrived);
    assert_eq!((m.position(), m.phase()), (2, 5));
    done(m);
}

#[test]
fn settle_time_holds_then_releases() {
    // One full step (phase 3), held 2000 µs, then all low.
    let p = pins(&[L, L], &[H, L], &[H, L], &[L, L]);
    let mut cfg = config(StepMode::Full);
    cfg.settle_us = 2_000;
    let mut m = HBridgeStepper::new(p, LimitSwitches::none(), cfg).unwrap();
    m.move_to(1);
    assert_eq!(m.poll(100).unwrap(), Event::Arrived);
    assert!(m.is_energised());
    assert_eq!(m.poll(2_099).unwrap(), Event::Idle);
    assert!(m.is_energised());
    assert_eq!(m.poll(2_100).unwrap(), Event::Idle);
    assert!(!m.is_energised());
    done(m);
}

#[test]
fn max_limit_switch_stops_motion() {
    // Active-low switch: step 1 reads high (free), step 2 reads low (pressed):
    // no second step, coils released, position stays 1. Backward then works
    // (min switch absent) and reads no switch.
    // Phase 1 (A+B+); limit -> release; hold phase 1 again, then phase 0
    // (A+); arrival -> release.
    let p = pins(
        &[H, L, H, H, L],
        &[L, L, L, L, L],
        &[H, L, H, L, L],
        &[L, L, L, L, L],
    );
    let limits = LimitSwitches {
        min: None,
        max: Some(Pin::new(&[T::get(H), T::get(L)])),
        active_low: true,
    };
    let mut m = HBridgeStepper::new(p, limits, config(StepMode::Half)).unwrap();
    m.move_to(10);
    assert_eq!(m.poll(0).unwrap(), Event::Stepped);
    assert_eq!(m.poll(1_000_000).unwrap(), Event::LimitReached(Limit::Max));
    assert_eq!((m.position(), m.target(), m.is_moving()), (1, 1, false));
    assert_eq!(m.poll(1_000_001).unwrap(), Event::Idle);
    m.move_by(-1);
    assert_eq!(m.poll(2_000_000).unwrap(), Event::Arrived);
    assert_eq!(m.position(), 0);
    done(m);
}

#[test]
fn a_released_rotor_is_held_before_the_next_step() {
    // Full step: forward one step to phase 3 (A−B+), released on arrival.
    // Then backward one step: the coils are energised at phase 3 again
    // (IN2, IN3 high: passing A− alone, phase 4, beside the rotor) before
    // phase 1 (A+B+: IN2 low, then IN1 high, passing B+ alone, phase 2).
    // Energising phase 1 straight from all-low would pass A+ alone
    // (phase 0), three half-phases from a rotor at 3.
    // Per pin: step to 3, release, hold 3, step to 1, release (every
    // phase write sets all four pins, lows first).
    let p = pins(
        &[L, L, L, H, L],
        &[H, L, H, L, L],
        &[H, L, H, H, L],
        &[L, L, L, L, L],
    );
    let mut m = HBridgeStepper::new(p, LimitSwitches::none(), config(StepMode::Full)).unwrap();
    m.move_to(1);
    assert_eq!(m.poll(0).unwrap(), Event::Arrived);
    assert_eq!((m.phase(), m.is_energised()), (3, false));
    m.move_to(0);
    assert_eq!(m.poll(1_000_000).unwrap(), Event::Arrived);
    assert_eq!((m.position(), m.phase(), m.is_energised()), (0, 1, false));
    done(m);
}

#[test]
fn invalid_ramp_is_refused() {
    let mut cfg = config(StepMode::Half);
    cfg.ramp.start_speed_sps = 2_000;
    let p = pins(&[], &[], &[], &[]);
    for mut c in [p.in1.clone(), p.in2.clone(), p.in3.clone(), p.in4.clone()] {
        c.done();
    }
    let r = HBridgeStepper::<Pin, Pin>::new(p, LimitSwitches::none(), cfg);
    assert!(matches!(
        r,
        Err(Error::InvalidConfig(RampError::StartAboveMax))
    ));
}

/// A pin that only records its level (for the two-axis loop, where the exact
/// transactions are covered above).
#[derive(Debug, Default)]
struct LevelPin {
    high: bool,
    writes: u32,
}

impl embedded_hal::digital::ErrorType for LevelPin {
    type Error = core::convert::Infallible;
}
impl embedded_hal::digital::OutputPin for LevelPin {
    fn set_low(&mut self) -> Result<(), Self::Error> {
        self.high = false;
        self.writes += 1;
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Self::Error> {
        self.high = true;
        self.writes += 1;
        Ok(())
    }
}
impl embedded_hal::digital::InputPin for LevelPin {
    fn is_high(&mut self) -> Result<bool, Self::Error> {
        Ok(self.high)
    }
    fn is_low(&mut self) -> Result<bool, Self::Error> {
        Ok(!self.high)
    }
}

#[test]
fn one_loop_drives_two_axes() {
    let bridge = || BridgePins {
        in1: LevelPin::default(),
        in2: LevelPin::default(),
        in3: LevelPin::default(),
        in4: LevelPin::default(),
    };
    let mut az = HBridgeStepper::<LevelPin, LevelPin>::new(
        bridge(),
        LimitSwitches::none(),
        config(StepMode::Half),
    )
    .unwrap();
    let mut el = HBridgeStepper::<LevelPin, LevelPin>::new(
        bridge(),
        LimitSwitches::none(),
        config(StepMode::Full),
    )
    .unwrap();
    az.move_to(400);
    el.move_to(-150);
    let mut now = 0u64;
    let (mut az_done, mut el_done) = (None, None);
    while now < 5_000_000 && (az_done.is_none() || el_done.is_none()) {
        if az.poll(now).unwrap() == Event::Arrived {
            az_done = Some(now);
        }
        if el.poll(now).unwrap() == Event::Arrived {
            el_done = Some(now);
        }
        now += 50; // a 50 µs main loop
    }
    assert_eq!((az.position(), el.position()), (400, -150));
    assert!(az_done.is_some() && el_done.is_some());
    assert!(!az.is_energised() && !el.is_energised());
    // 400 half steps = 50 full cycles of 8 phases: back at phase 0; -150 full steps
    // from phase 1 = -300 half-phases, -300 mod 8 = 4 -> phase 5.
    assert_eq!((az.phase(), el.phase()), (0, 5));
    let (p, _) = az.destroy();
    // Every step writes every pin once, plus one write when the coils are released.
    assert_eq!(p.in1.writes, 400 + 1);
}
