//! Hall pulse counting and the stall / unexpected-motion watch, with
//! scenarios worked by hand (times in ms, thresholds in ‰).

use drivers::encoder::Transition;
use drivers::hall::{HallConfig, HallError, QuadratureHall, SingleHall, StallWatch, Watch};

const CONFIG: HallConfig = HallConfig {
    stall_ms: 250,
    drive_threshold_permille: 100,
    max_idle_pulses: 2,
};

#[test]
fn single_channel_counts_by_commanded_direction() {
    let mut h = SingleHall::new(CONFIG).unwrap();
    // Extend: five pulses 50 ms apart → +5.
    h.set_drive(800, 0);
    for t in (50..=250).step_by(50) {
        h.pulse(t);
    }
    assert_eq!(h.position(), 5);
    // Reverse: the timer restarts at 300; three pulses → 2.
    h.set_drive(-800, 300);
    for t in [350, 400, 450] {
        h.pulse(t);
    }
    assert_eq!(h.position(), 2);
    // Stop at 460: two run-down pulses still count backward → 0; normal.
    h.set_drive(0, 460);
    h.pulse(470);
    h.pulse(490);
    assert_eq!((h.position(), h.check(500)), (0, Watch::Normal));
    // A third idle pulse → unexpected motion (more than 2).
    h.pulse(900);
    assert_eq!((h.position(), h.check(901)), (-1, Watch::UnexpectedMotion));
    // Driving again clears the idle count; restarting the idle period
    // starts from zero idle pulses.
    h.set_drive(500, 1_000);
    assert_eq!(h.check(1_001), Watch::Normal);
    h.set_drive(0, 1_002);
    assert_eq!(h.check(1_003), Watch::Normal);
}

#[test]
fn stall_needs_drive_above_the_threshold_and_stall_ms_without_pulses() {
    let mut h = SingleHall::new(CONFIG).unwrap();
    // Exactly the threshold is not driven: never a stall.
    h.set_drive(100, 0);
    assert_eq!(h.check(10_000), Watch::Normal);
    // 101 ‰ is: from 10 000, stall at 10 250 (not at 10 249).
    h.set_drive(101, 10_000);
    assert_eq!(h.check(10_249), Watch::Normal);
    assert_eq!(h.check(10_250), Watch::Stall);
    // A pulse at 10 300 restarts the timer: stall again at 10 550.
    h.pulse(10_300);
    assert_eq!(h.check(10_549), Watch::Normal);
    assert_eq!(h.check(10_550), Watch::Stall);
    // A duty change in the same direction does not restart it.
    h.set_drive(900, 10_560);
    assert_eq!(h.check(10_560), Watch::Stall);
}

#[test]
fn stall_timer_across_the_millisecond_wrap() {
    let mut w = StallWatch::new(CONFIG).unwrap();
    // Drive from 2³² − 100; 250 ms later the counter reads 150.
    w.set_drive(-500, u32::MAX - 99);
    assert_eq!(w.check(149), Watch::Normal);
    assert_eq!(w.check(150), Watch::Stall);
}

#[test]
fn quadrature_direction_comes_from_the_channels() {
    let mut h = QuadratureHall::new(false, false, CONFIG).unwrap();
    h.set_drive(-600, 0); // the command says backward…
                          // …but A leads B: 00 → 10 → 11 is two counts forward.
    assert_eq!(h.update(true, false, 10), Transition::Forward);
    assert_eq!(h.update(true, true, 20), Transition::Forward);
    assert_eq!(h.position(), 2);
    // Back: 11 → 10 → 00 → 01: three counts backward → −1.
    for (a, b) in [(true, false), (false, false), (false, true)] {
        assert_eq!(h.update(a, b, 30), Transition::Backward);
    }
    assert_eq!(h.position(), -1);
    // A missed edge: 01 → 10 is illegal, no count; no change, no count.
    assert_eq!(h.update(true, false, 40), Transition::Illegal);
    assert_eq!(h.update(true, false, 50), Transition::None);
    assert_eq!((h.position(), h.errors()), (-1, 1));
    // Neither the illegal nor the unchanged sample fed the watch: the
    // last pulse was at 30, so the stall comes at 280.
    assert_eq!(h.check(279), Watch::Normal);
    assert_eq!(h.check(280), Watch::Stall);
}

#[test]
fn positions_saturate() {
    let mut s = SingleHall::new(CONFIG).unwrap();
    s.set_position(i32::MIN + 1);
    s.set_drive(-1_000, 0);
    assert_eq!(s.pulse(1), i32::MIN);
    assert_eq!(s.pulse(2), i32::MIN);
    let mut q = QuadratureHall::new(false, false, CONFIG).unwrap();
    q.set_position(i32::MAX);
    q.update(true, false, 0);
    assert_eq!(q.position(), i32::MAX);
}

#[test]
fn invalid_configurations() {
    for bad in [
        HallConfig {
            stall_ms: 0,
            ..CONFIG
        },
        HallConfig {
            drive_threshold_permille: 1_000,
            ..CONFIG
        },
    ] {
        assert_eq!(SingleHall::new(bad), Err(HallError::InvalidConfig));
        assert_eq!(
            QuadratureHall::new(false, false, bad),
            Err(HallError::InvalidConfig)
        );
    }
}
