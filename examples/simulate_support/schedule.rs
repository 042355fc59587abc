//! The random fault schedule of `simulate --faults`: the daily random
//! conditions (wind, bus errors, stalls, ...) and, per year, field incidents
//! of the time and site chain written as scenario events.

use sim::rng::SplitMix64;
use sim::scenario::{Event, RtcState, SwitchState};
use suntracker::safety::AxisId;

/// One injected condition, active for minutes `from..until` of the run.
#[derive(Debug, Clone, Copy)]
pub struct Window {
    pub kind: Kind,
    pub from: u32,
    pub until: u32,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    Wind,
    CompassBus,
    EncoderTimeout(usize),
    Stall(usize),
    Slip(usize, f64),
    SwitchStuck(usize),
    GpsLost,
    RtcPowerLoss,
    CommandStow,
}

/// What happens at a minute: a scenario event, or the end of an incident
/// that scenario files cannot express (they keep a GPS override to the end).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    Event(Event),
    /// The receiver reports the true date again.
    GpsDateTrue,
    /// The receiver reports the true position again.
    GpsPositionTrue,
}

/// An action at a minute of the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timed {
    pub minute: u32,
    pub action: Action,
}

/// Each day, each kind with its own probability; every window ends at
/// least a day before the run does.
pub fn daily(days: u32, rng: &mut SplitMix64) -> Vec<Window> {
    let mut ev = Vec::new();
    let last = days.saturating_sub(1);
    for d in 0..last {
        let day0 = d * 1440;
        let mut at = |rng: &mut SplitMix64, p: f64, lo: f64, hi: f64, kind: Kind| {
            if rng.next_f64() < p {
                let from = day0 + (rng.uniform(0.0, 1440.0)) as u32;
                let dur = rng.uniform(lo, hi) as u32;
                ev.push(Window {
                    kind,
                    from,
                    until: from + dur.max(1),
                });
            }
        };
        let axis = (rng.next_u64() & 1) as usize;
        at(rng, 0.08, 20.0, 180.0, Kind::Wind);
        at(rng, 0.03, 5.0, 60.0, Kind::CompassBus);
        at(rng, 0.03, 2.0, 30.0, Kind::EncoderTimeout(axis));
        at(rng, 0.03, 2.0, 20.0, Kind::Stall(axis));
        let slip = rng.uniform(-5.0, 5.0);
        at(rng, 0.03, 1.0, 2.0, Kind::Slip(axis, slip));
        at(rng, 0.02, 1.0, 5.0, Kind::SwitchStuck(axis));
        at(rng, 0.05, 60.0, 720.0, Kind::GpsLost);
        at(rng, 0.01, 1.0, 2.0, Kind::RtcPowerLoss);
        at(rng, 0.01, 30.0, 120.0, Kind::CommandStow);
    }
    ev
}

/// Field incidents of the time, site and switch chain, about once a year
/// each (a run of N days gets N/365 of each, the fraction drawn at random),
/// each placed at a random minute and ending at least a day before the run
/// does:
/// - the clock (RTC and GPS time) steps back a day, and is put right 2–8 h
///   later;
/// - the clock steps forward an hour, put right 1–6 h later;
/// - the receiver reports a week-rollover date (2006) for 2–12 h;
/// - the receiver reports an impossible position (91°, 200°) for 2–12 h;
/// - a limit switch sticks closed for 2–8 h;
/// - the RTC loses power while GPS is off for 1–6 h.
pub fn incidents(days: u32, rng: &mut SplitMix64) -> Vec<Timed> {
    let mut out = Vec::new();
    // Latest minute an incident may end: a day before the end of the run.
    let end_limit = days.saturating_sub(1) * 1440;
    let ev = |minute, e| Timed {
        minute,
        action: Action::Event(e),
    };
    for kind in 0..6u32 {
        let expected = f64::from(days) / 365.0;
        let mut n = expected.floor() as u32;
        if rng.next_f64() < expected.fract() {
            n += 1;
        }
        for _ in 0..n {
            let (lo_h, hi_h) = match kind {
                0 => (2.0, 8.0),
                1 => (1.0, 6.0),
                2 | 3 => (2.0, 12.0),
                4 => (2.0, 8.0),
                _ => (1.0, 6.0),
            };
            let dur = (rng.uniform(lo_h, hi_h) * 60.0) as u32;
            let axis_pick = rng.next_u64() & 1;
            if end_limit <= dur + 1 {
                continue;
            }
            let from = rng.uniform(0.0, f64::from(end_limit - dur - 1)) as u32;
            let until = from + dur.max(1);
            match kind {
                0 => {
                    out.push(ev(from, Event::ClockStep { seconds: -86_400 }));
                    out.push(ev(until, Event::ClockStep { seconds: 86_400 }));
                }
                1 => {
                    out.push(ev(from, Event::ClockStep { seconds: 3_600 }));
                    out.push(ev(until, Event::ClockStep { seconds: -3_600 }));
                }
                2 => {
                    out.push(ev(
                        from,
                        Event::GpsDate {
                            year: 2006,
                            month: 4,
                            day: 16,
                        },
                    ));
                    out.push(Timed {
                        minute: until,
                        action: Action::GpsDateTrue,
                    });
                }
                3 => {
                    out.push(ev(
                        from,
                        Event::GpsPosition {
                            lat_deg: 91.0,
                            lon_deg: 200.0,
                        },
                    ));
                    out.push(Timed {
                        minute: until,
                        action: Action::GpsPositionTrue,
                    });
                }
                4 => {
                    let axis = if axis_pick == 0 { AxisId::C } else { AxisId::A };
                    out.push(ev(from, Event::LimitSwitch(axis, SwitchState::StuckClosed)));
                    out.push(ev(until, Event::LimitSwitch(axis, SwitchState::Ok)));
                }
                _ => {
                    out.push(ev(from, Event::Gps(false)));
                    out.push(ev(from + 1, Event::Rtc(RtcState::LostPower)));
                    out.push(ev(until.max(from + 2), Event::Gps(true)));
                }
            }
        }
    }
    out.sort_by_key(|t| t.minute);
    out
}
