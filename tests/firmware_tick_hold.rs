//! The firmware loop puts a controller tick off while a drive is due within
//! `TICK_HOLD_MS` (a timed axis's run end: the tick's tens of milliseconds
//! on an 8-bit part would end that run late, and the axis would run on by
//! its speed times the lateness), never by more than `TICK_HOLD_MS`, and
//! not at all after a drive stopped itself on a fault.
//!
//! The drive here only reports its instant (`Motion::due_in_ms`) and its
//! latched fault; the loop's answer is whether a pass ran the tick
//! (`Firmware::poll`'s result).

mod common;

use std::cell::Cell;
use std::convert::Infallible;
use std::rc::Rc;

use common::host_io::Log;
use sim::rtc::SimRtc;
use sim::sensors::MountSensors;
use sun_algos::UtcTime;
use suntracker::controller::ControllerOptions;
use suntracker::firmware::{AppConfig, Firmware, Motion, Platform, TICK_HOLD_MS};
use suntracker::hw::NoGps;
use suntracker::motion::AxisDrive;

/// A drive that moves at once; the test sets when it is next due (an
/// instant on the board's clock) and whether it latched a fault.
#[derive(Clone, Default)]
struct Drive {
    due_at_ms: Rc<Cell<Option<u64>>>,
    latched: Rc<Cell<bool>>,
}

impl AxisDrive for Drive {
    type Error = Infallible;
    fn move_counts(&mut self, _counts: i32) -> Result<(), Infallible> {
        Ok(())
    }
    fn pending(&self) -> i32 {
        0
    }
    fn stop(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
    fn at_limit(&mut self) -> Result<bool, Infallible> {
        Ok(false)
    }
    fn encoder_deg(&mut self) -> Result<Option<f32>, Infallible> {
        Ok(None)
    }
    fn fault_latched(&self) -> bool {
        self.latched.get()
    }
}

impl Motion for Drive {
    fn service(&mut self, now_ms: u64) -> bool {
        // Served at or after its instant: nothing due any more.
        if self.due_at_ms.get().is_some_and(|t| now_ms >= t) {
            self.due_at_ms.set(None);
        }
        true
    }
    fn due_in_ms(&self, now_ms: u64) -> Option<u32> {
        self.due_at_ms
            .get()
            .map(|t| u32::try_from(t.saturating_sub(now_ms)).unwrap_or(u32::MAX))
    }
}

struct Board {
    now_ms: u64,
}

impl Platform for Board {
    fn now_ms(&mut self) -> u64 {
        self.now_ms
    }
    fn take_wind_pulses(&mut self) -> u32 {
        0
    }
    fn feed_watchdog(&mut self) {}
    fn wait_for_interrupt(&mut self) {}
}

type Fw = Firmware<f32, SimRtc, NoGps, Drive, MountSensors, Log, 0>;

/// The firmware at board time 0 after its first tick (ticks every
/// 1,000 ms), and its C axis's drive.
fn started() -> (Fw, Board, Drive) {
    let start = UtcTime::from_ymd_hms(2026, 3, 20, 12, 0, 0).unwrap();
    let c = Drive::default();
    let mut fw = Fw::new(
        AppConfig::new("host"),
        suntracker::config::Config::default(),
        ControllerOptions::default(),
        SimRtc::new(start),
        NoGps,
        [c.clone(), Drive::default()],
        None,
        Log::default(),
    )
    .expect("the default configuration is valid");
    let mut board = Board { now_ms: 0 };
    assert!(fw.poll(&mut board), "the first pass ticks");
    (fw, board, c)
}

/// Passes a millisecond apart from `from_ms` to `to_ms` (inclusive): the
/// board times of those that ran a tick.
fn ticks_between(fw: &mut Fw, board: &mut Board, from_ms: u64, to_ms: u64) -> Vec<u64> {
    let mut ticked = Vec::new();
    for ms in from_ms..=to_ms {
        board.now_ms = ms;
        if fw.poll(board) {
            ticked.push(ms);
        }
    }
    ticked
}

#[test]
fn a_tick_waits_for_a_drive_due_within_the_hold() {
    let (mut fw, mut board, c) = started();
    // The next tick is due at 1,000 ms; the drive at 1,040 ms.
    assert_eq!(
        ticks_between(&mut fw, &mut board, 1, 990),
        Vec::<u64>::new()
    );
    c.due_at_ms.set(Some(1_040));
    // Served on time at the start of the pass at 1,040, which then ticks.
    assert_eq!(ticks_between(&mut fw, &mut board, 991, 1_100), vec![1_040]);
}

#[test]
fn a_drive_due_beyond_the_hold_does_not_hold_the_tick() {
    let (mut fw, mut board, c) = started();
    c.due_at_ms.set(Some(1_000 + u64::from(TICK_HOLD_MS)));
    assert_eq!(ticks_between(&mut fw, &mut board, 1, 1_100), vec![1_000]);
}

/// A drive that stays due (always a millisecond away) holds the tick
/// `TICK_HOLD_MS` at most.
#[test]
fn a_tick_is_held_no_longer_than_the_hold() {
    let (mut fw, mut board, c) = started();
    let mut ticked = None;
    for ms in 1..=2_000u64 {
        board.now_ms = ms;
        c.due_at_ms.set(Some(ms + 1));
        if fw.poll(&mut board) {
            ticked = Some(ms);
            break;
        }
    }
    assert_eq!(ticked, Some(1_000 + u64::from(TICK_HOLD_MS)));
}

/// A drive that stopped itself on a fault brings a held tick forward: the
/// fault is raised now, not when the other drive's instant has passed.
#[test]
fn a_tripped_drive_ends_the_hold() {
    let (mut fw, mut board, c) = started();
    c.due_at_ms.set(Some(1_100));
    // Held from 1,000 ms on.
    assert_eq!(
        ticks_between(&mut fw, &mut board, 1, 1_009),
        Vec::<u64>::new()
    );
    board.now_ms = 1_010;
    c.latched.set(true);
    assert!(fw.poll(&mut board), "the trip's tick at once");
}
