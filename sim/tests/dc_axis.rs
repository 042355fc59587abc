//! The DC-motor and linear-actuator models read through the drivers'
//! sense and Hall code, the way a board's firmware sees them: a jam shows
//! as the stall current on the BTS7960's IS pin and as a Hall stall.

use drivers::dc_motor::bts7960::SenseConfig;
use drivers::dc_motor::{DutyRamp, Output};
use drivers::hall::{HallConfig, QuadratureHall, Watch};
use sim::dc_motor::{Bts7960Sense, DcMotor, MotorSpec, DEFAULT_STEP_S};
use sim::linear_actuator::{ActuatorSpec, LinearActuator};

/// 10-bit converter on 5 V, as the Uno's.
const FULL_SCALE: u16 = 1_023;
/// One count of it in load current: 5 V / 1023 · 8,500 / 1 kΩ = 41.5 mA.
const COUNT_MA: u32 = 42;

fn read_ma(output: Output, current_a: f64) -> u32 {
    let raw = Bts7960Sense::TYPICAL_1K_5V.adc_counts(output, current_a, 5.0, FULL_SCALE);
    SenseConfig::DATASHEET_1K_5V
        .milliamps(raw, FULL_SCALE)
        .unwrap_or(u32::MAX)
}

#[test]
fn a_jammed_gear_motor_reads_its_stall_current_and_stops_pulsing() {
    let mut motor = DcMotor::new(MotorSpec::pololu_37d_131_12v());
    let config = HallConfig {
        stall_ms: 100,
        drive_threshold_permille: 150,
        max_idle_pulses: 8,
    };
    let (a, b) = motor.hall_levels();
    let Ok(mut hall) = QuadratureHall::new(a, b, config) else {
        panic!("valid Hall config");
    };
    // The firmware ramps 0 → 1000 ‰ at 5 ‰/ms (200 ms), the axis jams at
    // 20° of output travel.
    let mut ramp = DutyRamp::new(5);
    ramp.set_target(1_000);
    motor.set_hard_stops_deg(Some((-360.0, 20.0)));
    let mut now_ms = 0u32;
    let mut jammed_at_ms = None;
    while now_ms < 3_000 {
        let duty = ramp.poll(now_ms);
        let output = match u16::try_from(duty) {
            Ok(0) | Err(_) => Output::Brake,
            Ok(p) => Output::Forward(p),
        };
        motor.set_output(output);
        hall.set_drive(duty, now_ms);
        for _ in 0..100 {
            motor.step(DEFAULT_STEP_S);
            let (a, b) = motor.hall_levels();
            hall.update(a, b, now_ms);
        }
        if jammed_at_ms.is_none() && motor.output_angle_deg() >= 20.0 {
            jammed_at_ms = Some(now_ms);
        }
        now_ms += 1;
    }
    // 20° at 76 rpm (456 °/s) takes well under the 3 s run.
    assert!(jammed_at_ms.is_some_and(|t| t < 1_000));
    // Pololu: 5.5 A stall at 12 V; read back within one ADC count.
    let ma = read_ma(Output::Forward(1_000), motor.current_a());
    assert!(ma.abs_diff(5_500) <= COUNT_MA, "read {ma} mA");
    assert_eq!(hall.check(now_ms), Watch::Stall);
    // 20° of output = 20 / 360 · 8,400 counts = 466.7: the driver saw 466.
    assert_eq!(hall.position(), 466);
}

#[test]
fn an_obstructed_actuator_reads_its_stall_current() {
    let mut actuator = LinearActuator::new(ActuatorSpec::LA12_L1_12V, 20.0);
    actuator.set_obstruction_mm(Some(30.0));
    actuator.set_output(Output::Forward(1_000));
    for _ in 0..1_000 {
        actuator.step(1.0e-3);
    }
    // Stall at full duty: 1 + 4 · 26 / 12 = 9.667 A (module documentation).
    let ma = read_ma(Output::Forward(1_000), actuator.current_a());
    assert!(ma.abs_diff(9_667) <= COUNT_MA, "read {ma} mA");
    // Braked, the IS pin is silent whatever the current was.
    assert_eq!(read_ma(Output::Brake, actuator.current_a()), 0);
}
