//! STEP/DIR/ENABLE driver: exact pin and delay transactions for an A4988
//! (STEP high ≥ 1 µs, DIR setup 200 ns, ¬ENABLE active low) and a DRV8825
//! (1.9 µs, 650 ns, 1.7 ms wake-up scheduled without blocking).

use drivers::stepper::ramp::{Ramp, RampError};
use drivers::stepper::step_dir::{Config, PulseTiming, StepDirPins, StepDirStepper};
use drivers::stepper::{Error, Event, Limit, LimitSwitches};
use embedded_hal_mock::eh1::delay::{CheckedDelay, Transaction as D};
use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};

use State::{High as H, Low as L};

const RAMP: Ramp = Ramp {
    start_speed_sps: 100,
    max_speed_sps: 1000,
    accel_sps2: 10_000,
};

fn set(states: &[State]) -> Pin {
    Pin::new(&states.iter().map(|&x| T::set(x)).collect::<Vec<_>>())
}

fn config(timing: PulseTiming) -> Config {
    Config {
        ramp: RAMP,
        timing,
        invert_dir: false,
        enable_active_low: true,
        settle_us: 0,
    }
}

fn finish(m: StepDirStepper<Pin, Pin, CheckedDelay>) {
    let (mut p, l, mut d) = m.destroy();
    p.step.done();
    p.dir.done();
    if let Some(e) = p.enable.as_mut() {
        e.done();
    }
    for mut pin in [l.min, l.max].into_iter().flatten() {
        pin.done();
    }
    d.done();
}

#[test]
fn a4988_two_steps_forward() {
    let pins = StepDirPins {
        step: set(&[H, L, H, L]),
        dir: set(&[H]),
        enable: Some(set(&[L, H])), // enable (active low) at start, disable on arrival
    };
    let delay = CheckedDelay::new(&[D::delay_ns(200), D::delay_ns(1_000), D::delay_ns(1_000)]);
    let mut m = StepDirStepper::new(
        pins,
        LimitSwitches::none(),
        delay,
        config(PulseTiming::A4988),
    )
    .unwrap();
    m.move_to(2);
    assert_eq!(m.poll(0).unwrap(), Event::Stepped);
    assert!(m.is_enabled());
    // 2-step move: level 1 -> isqrt(30000) = 173 steps/s -> 5780 µs.
    assert_eq!(m.poll(5_779).unwrap(), Event::Waiting);
    assert_eq!(m.poll(5_780).unwrap(), Event::Arrived);
    assert!(!m.is_enabled());
    assert_eq!(m.position(), 2);
    finish(m);
}

#[test]
fn drv8825_wake_is_scheduled_and_direction_change_sets_dir() {
    let pins = StepDirPins {
        step: set(&[H, L, H, L]),
        // Forward with DIR inverted: low. Then backward: high.
        dir: set(&[L, H]),
        enable: Some(set(&[L, H, L, H])),
    };
    let delay = CheckedDelay::new(&[
        D::delay_ns(650),
        D::delay_ns(1_900),
        D::delay_ns(650),
        D::delay_ns(1_900),
    ]);
    let mut cfg = config(PulseTiming::DRV8825);
    cfg.invert_dir = true;
    let mut m = StepDirStepper::new(pins, LimitSwitches::none(), delay, cfg).unwrap();
    m.move_to(1);
    // Enable at t=0, first step not before 1700 µs (no blocking wait).
    assert_eq!(m.poll(0).unwrap(), Event::Waiting);
    assert_eq!(m.poll(1_699).unwrap(), Event::Waiting);
    assert_eq!(m.poll(1_700).unwrap(), Event::Arrived);
    m.move_to(0);
    assert_eq!(m.poll(10_000).unwrap(), Event::Waiting);
    assert_eq!(m.poll(11_700).unwrap(), Event::Arrived);
    assert_eq!(m.position(), 0);
    finish(m);
}

#[test]
fn min_limit_stops_before_stepping() {
    let pins = StepDirPins {
        step: set(&[]),
        dir: set(&[]),
        enable: Some(set(&[H])), // released (disabled) at the limit
    };
    let limits = LimitSwitches {
        min: Some(Pin::new(&[T::get(H)])), // active high here: pressed
        max: None,
        active_low: false,
    };
    let delay = CheckedDelay::new(&[]);
    let mut m = StepDirStepper::new(pins, limits, delay, config(PulseTiming::A4988)).unwrap();
    m.move_to(-5);
    assert_eq!(m.poll(0).unwrap(), Event::LimitReached(Limit::Min));
    assert_eq!((m.position(), m.is_moving()), (0, false));
    finish(m);
}

#[test]
fn pulse_longer_than_interval_is_refused() {
    // 62 500 steps/s -> a 16 µs interval, but this pulse needs 10 + 10 µs
    let mut cfg = config(PulseTiming {
        step_high_ns: 10_000,
        step_low_ns: 10_000,
        ..PulseTiming::DRV8825
    });
    cfg.ramp.max_speed_sps = 62_500;
    let pins = StepDirPins {
        step: set(&[]),
        dir: set(&[]),
        enable: None,
    };
    let (mut s, mut d) = (pins.step.clone(), pins.dir.clone());
    s.done();
    d.done();
    let mut delay = CheckedDelay::new(&[]);
    delay.done();
    let r = StepDirStepper::<Pin, Pin, CheckedDelay>::new(pins, LimitSwitches::none(), delay, cfg);
    assert!(matches!(
        r,
        Err(Error::InvalidConfig(RampError::PulseTooLong))
    ));
}
