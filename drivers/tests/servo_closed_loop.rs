//! Closed-loop position control on a simulated FS5106R + YMT22 plant
//! (Chowdhury et al. 2019: 95 rpm at 6 V, encoder up to 300 pulses/rev).
//!
//! Plant (written here, independent of the driver): the servo reads the pulse
//! width back from the PWM duty; a neutral deadband of ±20 µs around its own
//! (mis-trimmed) neutral gives no motion; outside it the commanded speed is
//! linear in the pulse, up to 95 rpm at ±500 µs; the shaft follows with a
//! first-order lag (τ = 40 ms: inertia + the servo's own loop). The encoder
//! produces the Gray code of the shaft angle; every edge "interrupts" into
//! the shared decoder. Controller and servo frame run at 50 Hz.

use std::cell::Cell;
use std::rc::Rc;

use drivers::encoder::SharedEncoder;
use drivers::servo::{ContinuousServo, PositionController, ServoConfig};
use embedded_hal::pwm::{ErrorType, SetDutyCycle};

const MAX_DUTY: u16 = 20_000; // 1 µs per count at 20 ms

struct SimPwm(Rc<Cell<u16>>);

impl ErrorType for SimPwm {
    type Error = core::convert::Infallible;
}
impl SetDutyCycle for SimPwm {
    fn max_duty_cycle(&self) -> u16 {
        MAX_DUTY
    }
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {
        self.0.set(duty);
        Ok(())
    }
}

struct Plant {
    /// Shaft angle, revolutions.
    angle_rev: f64,
    /// Shaft speed, rev/s.
    speed_rps: f64,
    /// Pulse at which this servo really stands still, µs.
    true_neutral_us: f64,
    /// Encoder quadrature counts per revolution (4 × pulses per revolution).
    counts_per_rev: f64,
    /// Last Gray state emitted.
    last_count: i64,
}

const GRAY: [(bool, bool); 4] = [(false, false), (true, false), (true, true), (false, true)];

impl Plant {
    fn step(&mut self, pulse_us: f64, dt_s: f64, enc: &SharedEncoder) {
        const DEADBAND_US: f64 = 20.0;
        const MAX_RPS: f64 = 95.0 / 60.0;
        const TAU_S: f64 = 0.040;
        let d = pulse_us - self.true_neutral_us;
        let cmd_rps = if d.abs() <= DEADBAND_US {
            0.0
        } else {
            (d - DEADBAND_US.copysign(d)) / (500.0 - DEADBAND_US) * MAX_RPS
        };
        self.speed_rps += (cmd_rps - self.speed_rps) * (dt_s / TAU_S);
        self.angle_rev += self.speed_rps * dt_s;
        let count = (self.angle_rev * self.counts_per_rev).floor() as i64;
        // One edge per state change; dt is small enough that at most one happens.
        while self.last_count != count {
            self.last_count += if count > self.last_count { 1 } else { -1 };
            let (a, b) = GRAY[self.last_count.rem_euclid(4) as usize];
            enc.update(a, b);
        }
    }
    fn true_count(&self) -> i64 {
        (self.angle_rev * self.counts_per_rev).floor() as i64
    }
}

/// Runs to `targets` in turn; returns (final errors in counts, largest |command|).
fn run(pulses_per_rev: u32, targets: &[i32], enc: &SharedEncoder) -> (Vec<i64>, f32) {
    let duty = Rc::new(Cell::new(0));
    let mut servo = ContinuousServo::new(SimPwm(duty.clone()), ServoConfig::STANDARD_50HZ).unwrap();
    let ctl = PositionController {
        kp_per_count: 0.004,
        deadband_counts: 1,
        max_speed: 0.6,
        // Just above the servo's 20 µs deadband (0.04 of the 500 µs span).
        min_speed: 0.06,
    };
    let mut plant = Plant {
        angle_rev: 0.0,
        speed_rps: 0.0,
        true_neutral_us: 1_508.0, // servo not perfectly trimmed
        counts_per_rev: f64::from(4 * pulses_per_rev),
        last_count: 0,
    };
    enc.set_levels(false, false);
    enc.set_count(0);
    let dt = 50e-6;

    // Neutral calibration: step the pulse 1460..1560 µs by 2 µs, hold each 0.4 s,
    // note the highest pulse that still turns backward and the lowest that turns
    // forward; neutral = their midpoint. Then return to zero.
    let (mut last_backward, mut first_forward) = (None, None);
    for pulse_us in (1_460..=1_560).step_by(2) {
        servo.set_pulse_us(pulse_us).unwrap();
        let before = enc.count();
        for _ in 0..8_000 {
            plant.step(f64::from(duty.get()), dt, enc);
        }
        let moved = enc.count() - before;
        if moved <= -2 {
            last_backward = Some(pulse_us);
        }
        if moved >= 2 && first_forward.is_none() {
            first_forward = Some(pulse_us);
        }
    }
    let neutral = (last_backward.unwrap() + first_forward.unwrap()) / 2;
    servo.set_neutral_us(neutral).unwrap();
    println!("neutral calibrated to {neutral} µs (true 1508 µs)");
    let home = enc.count();
    let mut errors = Vec::new();
    let mut max_cmd = 0.0f32;
    for &target in targets {
        // 8 s per move, controller every 20 ms (400 plant steps).
        for _tick in 0..(8 * 50) {
            let cmd = ctl.update(target + home, enc.count());
            max_cmd = max_cmd.max(cmd.abs());
            servo.set_speed(cmd).unwrap();
            // Duty back to pulse width: 1 count = 1 µs with MAX_DUTY over 20 ms.
            let pulse = f64::from(duty.get()) * 20_000.0 / f64::from(MAX_DUTY);
            for _ in 0..400 {
                plant.step(pulse, dt, enc);
            }
        }
        assert_eq!(
            enc.count() as i64,
            plant.true_count(),
            "decoder tracks the shaft"
        );
        assert_eq!(enc.errors(), 0);
        assert!(plant.speed_rps.abs() < 1e-4, "at rest, not passing through");
        errors.push(plant.true_count() - i64::from(target + home));
    }
    (errors, max_cmd)
}

#[test]
fn stops_within_one_count_300_ppr() {
    let enc = SharedEncoder::new();
    // 300 pulses/rev = 1200 counts/rev: a quarter turn, back past zero, small steps.
    let targets = [300, -450, -440, -441, 1_200, 1_203];
    let (errors, max_cmd) = run(300, &targets, &enc);
    println!("300 ppr final errors (counts): {errors:?}, max |command| {max_cmd}");
    assert!(errors.iter().all(|e| e.abs() <= 1), "{errors:?}");
    assert!(max_cmd <= 0.6 + 1e-6, "speed limit respected");
}

#[test]
fn stops_within_one_count_75_ppr() {
    // 300 counts per revolution (75 pulses/rev ×4).
    let enc = SharedEncoder::new();
    let targets = [75, -150, 2, 0];
    let (errors, _) = run(75, &targets, &enc);
    println!("75 ppr (300 counts/rev) final errors (counts): {errors:?}");
    assert!(errors.iter().all(|e| e.abs() <= 1), "{errors:?}");
}

#[test]
fn controller_by_hand() {
    let c = PositionController {
        kp_per_count: 0.01,
        deadband_counts: 1,
        max_speed: 0.5,
        min_speed: 0.05,
    };
    assert_eq!(c.update(100, 99), 0.0); // inside deadband
    assert_eq!(c.update(100, 101), 0.0);
    assert_eq!(c.update(100, 98), 0.05); // 0.02 raised to min_speed
    assert!((c.update(100, 80) - 0.2).abs() < 1e-6); // 0.01 · 20
    assert_eq!(c.update(100, -900), 0.5); // limited
    assert_eq!(c.update(-900, 100), -0.5);
    assert_eq!(c.update(i32::MIN, i32::MAX), -0.5); // no overflow
    let bad = PositionController {
        kp_per_count: f32::NAN,
        ..c
    };
    assert_eq!(bad.update(100, 0), 0.0);
}
