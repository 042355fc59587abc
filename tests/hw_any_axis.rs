//! An axis of whichever kind the configuration names (`hw::AnyAxis`):
//! every method reaches the axis inside and only it, each kind's errors
//! come out as that kind's, and the loop's millisecond count reaches a
//! DC, timed or linear axis as it is; the board-independent choices that go with
//! the kinds (`mechanics::worm_slew_config`, `mechanics::options_for_drives`).

use core::convert::Infallible;

use suntracker::config::{DriveKind, DriveSet};
use suntracker::controller::ControllerOptions;
use suntracker::firmware::Motion;
use suntracker::hw::{AnyAxis, AnyAxisError};
use suntracker::mechanics;
use suntracker::motion::{AxisDrive, DriveFault, FeedbackMode};

/// A drive that records what reached it; `fail` makes every call that can
/// fail fail.
#[derive(Debug, Default)]
struct Recorder {
    calls: Vec<String>,
    fail: bool,
    watched: bool,
}

impl Recorder {
    fn result<T>(&mut self, call: String, ok: T) -> Result<T, ()> {
        self.calls.push(call);
        if self.fail {
            Err(())
        } else {
            Ok(ok)
        }
    }
}

impl Motion for Recorder {
    fn service(&mut self, now_ms: u64) -> bool {
        self.calls.push(format!("service {now_ms}"));
        !self.fail
    }
}

impl AxisDrive for Recorder {
    type Error = ();
    fn move_counts(&mut self, counts: i32) -> Result<(), ()> {
        self.result(format!("move {counts}"), ())
    }
    fn pending(&self) -> i32 {
        self.calls.len() as i32
    }
    fn stop(&mut self) -> Result<(), ()> {
        self.result("stop".into(), ())
    }
    fn at_limit(&mut self) -> Result<bool, ()> {
        self.result("at_limit".into(), true)
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, ()> {
        self.result("encoder".into(), Some(12.5))
    }
    fn self_watched(&self) -> bool {
        self.watched
    }
    fn take_fault(&mut self) -> Option<DriveFault> {
        self.calls.push("take_fault".into());
        Some(DriveFault::Obstruction)
    }
    fn fault_latched(&self) -> bool {
        true
    }
    fn clear_fault(&mut self) {
        self.calls.push("clear".into());
    }
    fn rebase_counts(&mut self, counts: i32) {
        self.calls.push(format!("rebase {counts}"));
    }
    fn switch_stops(&mut self, on: bool) {
        self.calls.push(format!("switch {on}"));
    }
    fn rebase_at_rest(&mut self) {
        self.calls.push("rebase_at_rest".into());
    }
}

type Axis = AnyAxis<Recorder, Recorder, Recorder, Recorder, Recorder, Recorder>;

/// Every method once, in this order.
fn exercise(axis: &mut Axis) -> Vec<String> {
    let _ = axis.service(4_000_000_123);
    let _ = axis.move_counts(-7);
    let _ = axis.stop();
    let _ = axis.at_limit();
    let _ = axis.encoder_deg();
    let _ = axis.take_fault();
    axis.clear_fault();
    axis.rebase_counts(360);
    axis.switch_stops(false);
    axis.rebase_at_rest();
    let (AnyAxis::Stepper(r)
    | AnyAxis::Dc(r)
    | AnyAxis::Timed(r)
    | AnyAxis::LinearHall(r)
    | AnyAxis::LinearPot(r)
    | AnyAxis::ServoEncoder(r)) = axis;
    r.calls.clone()
}

const EXPECTED: [&str; 10] = [
    "service 4000000123",
    "move -7",
    "stop",
    "at_limit",
    "encoder",
    "take_fault",
    "clear",
    "rebase 360",
    "switch false",
    "rebase_at_rest",
];

#[test]
fn every_method_reaches_the_axis_inside_with_its_arguments() {
    for make in [
        AnyAxis::Stepper,
        AnyAxis::Dc,
        AnyAxis::Timed,
        AnyAxis::LinearHall,
        AnyAxis::LinearPot,
        AnyAxis::ServoEncoder,
    ] {
        let mut axis: Axis = make(Recorder::default());
        assert_eq!(exercise(&mut axis), EXPECTED);
        // The values come back as the axis gave them.
        assert_eq!(axis.at_limit(), Ok(true));
        assert_eq!(axis.encoder_deg(), Ok(Some(12.5)));
        assert!(axis.fault_latched());
        assert_eq!(axis.take_fault(), Some(DriveFault::Obstruction));
        // `pending` is the recorder's count of calls: 13 by now.
        assert_eq!(axis.pending(), 13);
    }
}

#[test]
fn each_kinds_errors_come_out_as_that_kind() {
    let failing = || Recorder {
        fail: true,
        ..Recorder::default()
    };
    let mut stepper: Axis = AnyAxis::Stepper(failing());
    let mut dc: Axis = AnyAxis::Dc(failing());
    let mut timed: Axis = AnyAxis::Timed(failing());
    let mut hall: Axis = AnyAxis::LinearHall(failing());
    let mut pot: Axis = AnyAxis::LinearPot(failing());
    let mut servo: Axis = AnyAxis::ServoEncoder(failing());
    assert_eq!(stepper.move_counts(1), Err(AnyAxisError::Stepper));
    assert_eq!(stepper.stop(), Err(AnyAxisError::Stepper));
    assert_eq!(dc.at_limit(), Err(AnyAxisError::Motor));
    assert_eq!(dc.encoder_deg(), Err(AnyAxisError::Motor));
    assert_eq!(timed.move_counts(1), Err(AnyAxisError::Motor));
    assert!(!timed.service(5));
    assert_eq!(hall.stop(), Err(AnyAxisError::Motor));
    assert_eq!(pot.encoder_deg(), Err(AnyAxisError::Motor));
    assert_eq!(servo.move_counts(1), Err(AnyAxisError::Servo));
    assert_eq!(servo.at_limit(), Err(AnyAxisError::Servo));
}

#[test]
fn which_axis_watches_its_own_motor_is_the_axis_insides_answer() {
    let watched = || Recorder {
        watched: true,
        ..Recorder::default()
    };
    assert!(!Axis::Stepper(Recorder::default()).self_watched());
    assert!(Axis::Dc(watched()).self_watched());
    assert!(Axis::Timed(watched()).self_watched());
    assert!(Axis::LinearPot(watched()).self_watched());
    // Which one is known at run time only.
    const { assert!(!Axis::SELF_WATCHED) };
}

#[test]
fn a_kind_the_image_does_not_build_is_no_variant() {
    // An image without steppers (nor, by default, linear actuators): the
    // other two kinds work as before.
    let mut axis: AnyAxis<Infallible, Recorder, Recorder> = AnyAxis::Dc(Recorder::default());
    assert_eq!(axis.move_counts(3), Ok(()));
    assert!(axis.service(9));
}

#[test]
fn the_worm_slew_configuration_is_valid_and_of_dc_axes() {
    let config = mechanics::worm_slew_config();
    assert_eq!(config.validate(), Ok(()));
    for ax in &config.axes {
        assert_eq!(ax.drive, DriveKind::DcHall as u8);
        // 64 counts × 7,875 / 360 = 1,400 counts a degree (the slew
        // drive's loop, `mechanics::WORM_SLEW_LOOP`, is built for 1,400).
        assert_eq!(ax.counts_per_deg(), 1_400.0);
    }
    let dc_only = DriveSet::NONE
        .with(DriveKind::DcHall)
        .with(DriveKind::Timed);
    assert!(config.check_drives(dc_only).is_ok());
    assert!(config.check_drives(DriveSet::STEPPER).is_err());
    // The stepper mechanics are refused by an image of DC axes only.
    assert!(mechanics::config().check_drives(dc_only).is_err());
    assert!(!DriveSet::NONE.has_code(0));
}

#[test]
fn the_options_follow_the_kinds_of_the_axes() {
    let base: ControllerOptions<f32> = mechanics::controller_options();
    assert_eq!(base.feedback, FeedbackMode::OpenLoop);
    assert!(!base.rehome_after_stow);

    let steppers = mechanics::options_for_drives(base, &mechanics::config().axes);
    assert_eq!(steppers.feedback, FeedbackMode::OpenLoop);
    assert!(!steppers.rehome_after_stow);

    let mut axes = mechanics::worm_slew_config().axes;
    let dc = mechanics::options_for_drives(base, &axes);
    assert_eq!(dc.feedback, FeedbackMode::ClosedLoop);
    assert!(!dc.rehome_after_stow);

    axes[1].drive = DriveKind::Timed as u8;
    let mixed = mechanics::options_for_drives(base, &axes);
    assert_eq!(mixed.feedback, FeedbackMode::ClosedLoop);
    assert!(mixed.rehome_after_stow);

    axes[0].drive = DriveKind::Timed as u8;
    let timed = mechanics::options_for_drives(base, &axes);
    assert_eq!(timed.feedback, FeedbackMode::OpenLoop);
    assert!(timed.rehome_after_stow);
    // Everything else is the options given.
    assert_eq!(timed.sensor_samples, base.sensor_samples);

    // A servo on its encoder measures its angle too.
    let mut servo_axes = mechanics::config().axes;
    servo_axes[1].drive = DriveKind::ServoEncoder as u8;
    let servo = mechanics::options_for_drives(base, &servo_axes);
    assert_eq!(servo.feedback, FeedbackMode::ClosedLoop);
    assert!(!servo.rehome_after_stow);
}
