//! L298N: exact ENA/IN1/IN2 writes, from the L298 data sheet's Figure 6
//! truth table (forward IN1 = H, IN2 = L; backward the mirror; fast motor
//! stop ENA = H with IN1 = IN2; free running stop ENA = L), ENA duty =
//! round(‰ · max / 1000), ENA to 0 whenever IN1/IN2 change, lows first.

use drivers::dc_motor::l298n::{L298n, L298nPins};
use drivers::dc_motor::{Config, Direction, Error, Output, RestMode};
use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
use embedded_hal_mock::eh1::MockError;

use State::{High as H, Low as L};

fn rig(max: u16, ena: &[u16], in1: &[State], in2: &[State]) -> (Pwm, Pin, Pin) {
    let mut t = vec![P::max_duty_cycle(max)];
    t.extend(ena.iter().map(|&x| P::set_duty_cycle(x)));
    let pin = |s: &[State]| Pin::new(&s.iter().map(|&x| T::set(x)).collect::<Vec<_>>());
    (Pwm::new(&t), pin(in1), pin(in2))
}

fn motor(r: &(Pwm, Pin, Pin), ramp_permille_per_ms: u16, rest: RestMode) -> L298n<Pwm, Pin> {
    let pins = L298nPins {
        ena: r.0.clone(),
        in1: r.1.clone(),
        in2: r.2.clone(),
    };
    L298n::new(
        pins,
        Config {
            ramp_permille_per_ms,
            rest,
        },
    )
    .unwrap()
}

fn done(m: L298n<Pwm, Pin>, mut r: (Pwm, Pin, Pin)) {
    m.destroy();
    r.0.done();
    r.1.done();
    r.2.done();
}

#[test]
fn forward_brake_backward_without_ramp() {
    // 8-bit ENA. Forward 20 %: round(51) = 51 (IN1 high; ENA already 0).
    // Brake: ENA 0, IN1 low, ENA full 255. Backward 60 %: round(153) = 153;
    // IN1 = IN2 = L → L/H: ENA 0, IN2 high, ENA 153.
    let r = rig(255, &[0, 51, 0, 255, 0, 153], &[L, H, L], &[L, H]);
    let mut m = motor(&r, 0, RestMode::Coast);
    m.set_duty(0.2).unwrap();
    assert_eq!(m.poll(0).unwrap(), Output::Forward(200));
    m.brake().unwrap();
    assert_eq!(m.output(), Output::Brake);
    m.set_permille(Direction::Backward, 600).unwrap();
    assert_eq!(m.poll(1).unwrap(), Output::Backward(600));
    done(m, r);
}

#[test]
fn soft_stop_ends_in_brake_when_configured() {
    // 1000 counts, 1 ‰/ms, rest = brake. 0 → 300 ‰ in 300 ms (two polls),
    // then down to 0: brake = IN1 low with ENA 0 first, then ENA full.
    let r = rig(1_000, &[0, 100, 300, 100, 0, 1_000], &[L, H, L], &[L]);
    let mut m = motor(&r, 1, RestMode::Brake);
    m.set_duty(0.3).unwrap();
    m.poll(0).unwrap();
    assert_eq!(m.poll(100).unwrap(), Output::Forward(100));
    assert_eq!(m.poll(300).unwrap(), Output::Forward(300));
    m.set_duty(0.0).unwrap();
    m.poll(1_000).unwrap();
    assert_eq!(m.poll(1_200).unwrap(), Output::Forward(100));
    assert_eq!(m.poll(1_300).unwrap(), Output::Brake);
    done(m, r);
}

#[test]
fn coast_only_drops_the_enable() {
    // Backward full (1000), coast: ENA 0, IN2 stays high.
    let r = rig(1_000, &[0, 1_000, 0], &[L], &[L, H]);
    let mut m = motor(&r, 0, RestMode::Brake);
    m.set_duty(-1.0).unwrap();
    assert_eq!(m.poll(0).unwrap(), Output::Backward(1_000));
    m.coast().unwrap();
    assert_eq!((m.output(), m.target_permille()), (Output::Coast, 0));
    done(m, r);
}

#[test]
fn ramp_steps_saturate_after_a_long_pause_and_across_the_counter_wrap() {
    // 65 535 ‰/ms · 65 536 ms overflows 32 bits: saturated, capped at the
    // target. Polls straddle the u32 wrap: 5 ms → 5 · 1 ‰.
    let r = rig(1_000, &[0, 5], &[L, H], &[L]);
    let mut m = motor(&r, 1, RestMode::Coast);
    m.set_duty(1.0).unwrap();
    m.poll(u32::MAX - 1).unwrap();
    assert_eq!(m.poll(3).unwrap(), Output::Forward(5));
    done(m, r);
    let r = rig(1_000, &[0, 1_000], &[L, H], &[L]);
    let mut m = motor(&r, u16::MAX, RestMode::Coast);
    m.set_duty(1.0).unwrap();
    m.poll(0).unwrap();
    assert_eq!(m.poll(65_536).unwrap(), Output::Forward(1_000));
    done(m, r);
}

#[test]
fn pin_error_is_reported_and_retried() {
    let err = MockError::Io(std::io::ErrorKind::Other);
    let mut ena = Pwm::new(&[
        P::max_duty_cycle(100),
        P::set_duty_cycle(0),
        P::set_duty_cycle(50),
    ]);
    let mut in1 = Pin::new(&[T::set(L), T::set(H).with_error(err.clone()), T::set(H)]);
    let mut in2 = Pin::new(&[T::set(L)]);
    let pins = L298nPins {
        ena: ena.clone(),
        in1: in1.clone(),
        in2: in2.clone(),
    };
    let mut m = L298n::new(
        pins,
        Config {
            ramp_permille_per_ms: 0,
            rest: RestMode::Coast,
        },
    )
    .unwrap();
    m.set_duty(0.5).unwrap();
    assert_eq!(m.poll(0), Err(Error::Pin(err)));
    assert_eq!(m.output(), Output::Coast);
    assert_eq!(m.poll(1).unwrap(), Output::Forward(500));
    m.destroy();
    ena.done();
    in1.done();
    in2.done();
}
