//! The DC-motor pieces together, as a board's axis loop would use them: an
//! L298N with a soft start, a single-channel Hall sensor counted by the
//! duty actually output, and the stall watch ending the move with a brake.
//! Pin writes from the L298 truth table, timings worked by hand.

use drivers::dc_motor::l298n::{L298n, L298nPins};
use drivers::dc_motor::{Config, Output, RestMode};
use drivers::hall::{HallConfig, SingleHall, Watch};
use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};

#[test]
fn soft_start_count_then_stall_and_brake() {
    // 1000-count ENA, 5 ‰/ms, polled every 10 ms: the first poll (t = 0)
    // starts the ramp clock, then +50 ‰ a poll, 50 … 800 ‰ at t = 10 … 160
    // (IN1 goes high before the first of them). The axis then runs into an
    // obstacle: pulses every 50 ms from 100 to 400, none after; with
    // stall_ms = 300 the watch trips at 700 and the loop brakes: ENA 0,
    // IN1 low, ENA full.
    let mut ena_writes = vec![P::max_duty_cycle(1_000), P::set_duty_cycle(0)];
    ena_writes.extend((1..=16).map(|k| P::set_duty_cycle(50 * k)));
    ena_writes.extend([P::set_duty_cycle(0), P::set_duty_cycle(1_000)]);
    let mut ena = Pwm::new(&ena_writes);
    let mut in1 = Pin::new(&[T::set(State::Low), T::set(State::High), T::set(State::Low)]);
    let mut in2 = Pin::new(&[T::set(State::Low)]);
    let pins = L298nPins {
        ena: ena.clone(),
        in1: in1.clone(),
        in2: in2.clone(),
    };
    let mut motor = L298n::new(
        pins,
        Config {
            ramp_permille_per_ms: 5,
            rest: RestMode::Coast,
        },
    )
    .unwrap();
    let mut hall = SingleHall::new(HallConfig {
        stall_ms: 300,
        drive_threshold_permille: 200,
        max_idle_pulses: 2,
    })
    .unwrap();

    motor.set_duty(0.8).unwrap();
    let mut braked_at = None;
    for now in (0..=1_000).step_by(10) {
        motor.poll(now).unwrap();
        hall.set_drive(motor.duty_permille(), now);
        if (100..=400).contains(&now) && now % 50 == 0 {
            hall.pulse(now);
        }
        if braked_at.is_none() && hall.check(now) == Watch::Stall {
            motor.brake().unwrap();
            hall.set_drive(0, now);
            braked_at = Some(now);
        }
    }
    // Driven above 200 ‰ from t = 50 (250 ‰): the pulses at 100, 150, …,
    // 400 are 7, all forward; the last at 400, so the stall comes at
    // 400 + 300.
    assert_eq!(hall.position(), 7);
    assert_eq!(braked_at, Some(700));
    assert_eq!(motor.output(), Output::Brake);
    assert_eq!(hall.check(1_000), Watch::Normal);
    motor.destroy();
    ena.done();
    in1.done();
    in2.done();
}
