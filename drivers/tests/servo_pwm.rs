//! Servo pulse widths through the embedded-hal-mock PWM channel. Expected duty
//! values by hand: duty = round(pulse_us · max_duty / 20000).

use drivers::servo::{ContinuousServo, Error, ServoConfig};
use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as T};
use embedded_hal_mock::eh1::MockError;

#[test]
fn one_microsecond_per_count() {
    // max duty 20000 over 20 ms: duty == pulse in µs.
    let ex = [
        T::max_duty_cycle(20_000),
        T::set_duty_cycle(1_500), // neutral at start
        T::set_duty_cycle(2_000), // +1
        T::set_duty_cycle(1_000), // -1
        T::set_duty_cycle(1_750), // +0.5
        T::set_duty_cycle(1_375), // -0.25
        T::set_duty_cycle(2_000), // +3 clamps to +1
        T::set_duty_cycle(1_500), // stop
    ];
    let mut pwm = Pwm::new(&ex);
    let mut s = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ).unwrap();
    for v in [1.0, -1.0, 0.5, -0.25, 3.0] {
        s.set_speed(v).unwrap();
    }
    s.stop().unwrap();
    assert_eq!(s.pulse_us(), 1_500);
    s.destroy();
    pwm.done();
}

#[test]
fn twelve_bit_channel_rounds_to_nearest() {
    // max 4095: 1500 µs -> 307.125 -> 307; 2000 -> 409.5 -> 410 (half up); 1000 -> 204.75 -> 205.
    let ex = [
        T::max_duty_cycle(4_095),
        T::set_duty_cycle(307),
        T::set_duty_cycle(410),
        T::set_duty_cycle(205),
    ];
    let mut pwm = Pwm::new(&ex);
    let mut s = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ).unwrap();
    s.set_speed(1.0).unwrap();
    s.set_speed(-1.0).unwrap();
    s.destroy();
    pwm.done();
}

#[test]
fn neutral_calibration_shifts_the_speed_map() {
    // Neutral trimmed to 1520 µs: +0.5 -> 1520 + 0.5·480 = 1760; -0.5 -> 1520 - 0.5·520 = 1260.
    let ex = [
        T::max_duty_cycle(20_000),
        T::set_duty_cycle(1_500),
        T::set_duty_cycle(1_520),
        T::set_duty_cycle(1_760),
        T::set_duty_cycle(1_260),
    ];
    let mut pwm = Pwm::new(&ex);
    let mut s = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ).unwrap();
    s.set_neutral_us(1_520).unwrap();
    s.set_speed(0.5).unwrap();
    s.set_speed(-0.5).unwrap();
    assert_eq!(s.set_neutral_us(2_000), Err(Error::InvalidConfig));
    assert_eq!(s.config().neutral_us, 1_520);
    s.destroy();
    pwm.done();
}

#[test]
fn bad_inputs_and_pwm_error() {
    let err = MockError::Io(std::io::ErrorKind::Other);
    let ex = [
        T::max_duty_cycle(20_000),
        T::set_duty_cycle(1_500),
        T::set_duty_cycle(1_100).with_error(err.clone()),
    ];
    let mut pwm = Pwm::new(&ex);
    let mut s = ContinuousServo::new(pwm.clone(), ServoConfig::STANDARD_50HZ).unwrap();
    assert_eq!(s.set_speed(f32::NAN), Err(Error::InvalidSpeed));
    assert_eq!(s.set_pulse_us(999), Err(Error::PulseOutOfRange));
    assert_eq!(s.set_pulse_us(2_001), Err(Error::PulseOutOfRange));
    assert_eq!(s.set_speed(-0.8), Err(Error::Comm(err)));
    assert_eq!(
        s.pulse_us(),
        1_500,
        "failed write leaves the recorded pulse"
    );
    s.destroy();
    pwm.done();

    let mut pwm = Pwm::new(&[]);
    let bad = ServoConfig {
        neutral_us: 900,
        ..ServoConfig::STANDARD_50HZ
    };
    assert!(matches!(
        ContinuousServo::new(pwm.clone(), bad),
        Err(Error::InvalidConfig)
    ));
    pwm.done();
}
