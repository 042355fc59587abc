//! The command logic every chip shares (`DcMotor`): refused commands, the
//! ramp's target, brake/coast resetting it, and the retry of an output whose
//! writes failed, over a recording bridge so no chip's pin order is
//! involved. Each chip's own writes are in dc_motor_bts7960.rs and
//! dc_motor_l298n.rs.

use drivers::dc_motor::{Bridge, Config, DcMotor, Direction, Error, Output, RestMode};

/// Records every output it is told to write; fails the writes listed in
/// `fail` (by their index in `applied`), once each.
#[derive(Debug, Default)]
struct Recorder {
    applied: Vec<Output>,
    fail: Vec<usize>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct WriteFailed;

impl Bridge for Recorder {
    type PwmError = WriteFailed;
    type PinError = WriteFailed;
    type State = ();

    fn init(&mut self) -> Result<(), Error<WriteFailed, WriteFailed>> {
        Ok(())
    }

    fn apply(&mut self, _: &mut (), output: Output) -> Result<(), Error<WriteFailed, WriteFailed>> {
        let n = self.applied.len();
        self.applied.push(output);
        if self.fail.contains(&n) {
            return Err(Error::Pwm(WriteFailed));
        }
        Ok(())
    }
}

fn motor(ramp_permille_per_ms: u16, rest: RestMode, fail: &[usize]) -> DcMotor<Recorder> {
    let bridge = Recorder {
        applied: Vec::new(),
        fail: fail.to_vec(),
    };
    DcMotor::new(
        bridge,
        Config {
            ramp_permille_per_ms,
            rest,
        },
    )
    .unwrap()
}

#[test]
fn invalid_commands_are_errors_and_keep_the_target() {
    let mut m = motor(1, RestMode::Brake, &[]);
    assert_eq!(m.target_permille(), 0);
    m.set_duty(0.25).unwrap();
    for bad in [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1.0001,
        -1.5,
        -2.0,
    ] {
        assert_eq!(m.set_duty(bad), Err(Error::InvalidDuty));
    }
    for (direction, permille) in [(Direction::Backward, 1_001), (Direction::Forward, 2_000)] {
        assert_eq!(m.set_permille(direction, permille), Err(Error::InvalidDuty));
    }
    assert_eq!(m.target_permille(), 250);
    // Nothing is written by a command, only by `poll`.
    assert_eq!(m.poll(10).unwrap(), Output::Coast);
    assert!(m.destroy().applied.is_empty());
}

#[test]
fn brake_and_coast_act_at_once_and_reset_the_ramp() {
    let mut m = motor(1, RestMode::Coast, &[]);
    m.set_duty(0.5).unwrap();
    m.poll(0).unwrap();
    assert_eq!(m.poll(100).unwrap(), Output::Forward(100));
    m.brake().unwrap();
    assert_eq!(
        (m.output(), m.duty_permille(), m.target_permille()),
        (Output::Brake, 0, 0)
    );
    assert_eq!(m.poll(200).unwrap(), Output::Brake); // the ramp does not undo it
    m.coast().unwrap();
    assert_eq!(m.output(), Output::Coast);
    assert_eq!(
        m.destroy().applied,
        [Output::Forward(100), Output::Brake, Output::Coast]
    );
}

#[test]
fn failed_output_stays_pending_until_written() {
    // No ramp. Forward 30 % fails twice: `output` keeps the last output
    // written (coast) and every poll tries again until it succeeds, then
    // nothing more is written.
    let mut m = motor(0, RestMode::Brake, &[0, 1]);
    m.set_duty(0.3).unwrap();
    assert_eq!(m.poll(0), Err(Error::Pwm(WriteFailed)));
    assert_eq!(m.output(), Output::Coast);
    assert_eq!(m.poll(1), Err(Error::Pwm(WriteFailed)));
    assert_eq!(m.poll(2).unwrap(), Output::Forward(300));
    assert_eq!(m.poll(3).unwrap(), Output::Forward(300));
    assert_eq!(m.destroy().applied, [Output::Forward(300); 3]);
}

#[test]
fn a_new_ramp_step_replaces_a_pending_output() {
    // 1 ‰/ms: the write of 10 ‰ fails; 10 ms later the ramp is at 20 ‰,
    // which is written instead of the stale 10 ‰.
    let mut m = motor(1, RestMode::Coast, &[0]);
    m.set_duty(1.0).unwrap();
    m.poll(0).unwrap();
    assert!(m.poll(10).is_err());
    assert_eq!(m.poll(20).unwrap(), Output::Forward(20));
    assert_eq!(
        m.destroy().applied,
        [Output::Forward(10), Output::Forward(20)]
    );
}

#[test]
fn failed_brake_is_retried_by_poll() {
    let mut m = motor(0, RestMode::Coast, &[0]);
    assert!(m.brake().is_err());
    assert_eq!(m.output(), Output::Coast);
    assert_eq!(m.poll(0).unwrap(), Output::Brake);
    assert_eq!(m.destroy().applied, [Output::Brake, Output::Brake]);
}
