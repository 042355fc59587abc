//! The random fault schedule of `simulate --faults`: the daily random
//! conditions (wind, bus errors, stalls, ...), per year, field incidents
//! of the time and site chain written as scenario events, and the weather
//! days (snow, hail warnings, the plant's stow contact, a sagging supply,
//! overcast days).

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
    /// The snow input on.
    Snow,
    /// A hail warning.
    Hail,
    /// The plant's stow contact at its active level.
    StowContact,
    /// The supply sags to this many millivolts (below [`SUPPLY_STOW_MV`])
    /// for the first half of the window, reads [`SUPPLY_HELD_MV`] (between
    /// the thresholds) for the second half, and [`SUPPLY_RECHARGED_MV`]
    /// (above [`SUPPLY_RESUME_MV`]) for [`SUPPLY_RECHARGED_MIN`] minutes
    /// after it: [`supply_mv`].
    LowSupply(u16),
    /// The pyranometer reads this fraction of the clear sky's irradiance.
    Overcast(f64),
}

impl Window {
    /// True at minute `m` of the run.
    pub fn covers(&self, m: u32) -> bool {
        self.from <= m && m < self.until
    }
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

/// `supply.stow_mv` of a `--faults` run (the configuration's default 0
/// turns the watch off): a 12 V lead-acid battery nearly flat (20 % charge
/// near 11.9 V at rest; `config::SupplyConfig`).
pub const SUPPLY_STOW_MV: u16 = 11_500;
/// `supply.resume_mv` of a `--faults` run: 60 % charge at rest.
pub const SUPPLY_RESUME_MV: u16 = 12_200;
/// The supply in the second half of a low-supply window: above the stow
/// level, below the resume level (the stow holds by hysteresis).
pub const SUPPLY_HELD_MV: u16 = 11_900;
/// The supply once charged again, after a low-supply window.
pub const SUPPLY_RECHARGED_MV: u16 = 12_600;
/// How long the supply reads [`SUPPLY_RECHARGED_MV`] after a low-supply
/// window, minutes; then the run's supply model again.
pub const SUPPLY_RECHARGED_MIN: u32 = 60;

/// One kind of weather spell: how many a year, how long (minutes), when,
/// and its kind (with what it draws: a sag, a sky).
struct Spell {
    per_year: f64,
    min_minutes: f64,
    max_minutes: f64,
    /// Starts between these local solar hours (a hail storm's afternoon;
    /// 0 to 24: at any time).
    local_hours: (f64, f64),
    kind: fn(&mut SplitMix64) -> Kind,
}

/// Weather spells of `--faults`, a handful of each kind a year (a stress
/// test of every stow mode, not a climate), each ending at least a day
/// before the run does:
/// - snow: the input on for 2–10 h (then `stow.snow_release_s`), 5 a year;
/// - hail warnings: 10–50 min, starting between 11:00 and 18:00 local
///   solar time, 6 a year;
/// - the plant's stow contact: 1–2 h, 5 a year;
/// - a low supply: 1–4 h below the stow level, then between the levels,
///   then charged ([`Kind::LowSupply`]), 5 a year;
/// - overcast days: from local solar midnight for 24 h the pyranometer
///   reads 10–25 % of the clear sky's irradiance, 6 a year.
///
/// A run of N days gets N/365 of each rate, the fraction drawn at random.
/// A spell starts at a random time (hail: of the afternoon), or, one time
/// in three, up to an hour before a random window of `faults` (the daily
/// conditions; an overcast day: that window's day), so that weather and
/// faults meet. `lon_deg` gives local solar time.
pub fn weather(days: u32, lon_deg: f64, faults: &[Window], rng: &mut SplitMix64) -> Vec<Window> {
    const ANY_TIME: (f64, f64) = (0.0, 24.0);
    let spells = [
        Spell {
            per_year: 5.0,
            min_minutes: 120.0,
            max_minutes: 600.0,
            local_hours: ANY_TIME,
            kind: |_| Kind::Snow,
        },
        Spell {
            per_year: 6.0,
            min_minutes: 10.0,
            max_minutes: 50.0,
            local_hours: (11.0, 18.0),
            kind: |_| Kind::Hail,
        },
        Spell {
            per_year: 5.0,
            min_minutes: 60.0,
            max_minutes: 120.0,
            local_hours: ANY_TIME,
            kind: |_| Kind::StowContact,
        },
        Spell {
            per_year: 5.0,
            min_minutes: 60.0,
            max_minutes: 240.0,
            local_hours: ANY_TIME,
            kind: |r| Kind::LowSupply(r.uniform(10_800.0, 11_400.0) as u16),
        },
        Spell {
            per_year: 6.0,
            min_minutes: 1440.0,
            max_minutes: 1440.0,
            local_hours: (0.0, 0.0),
            kind: |r| Kind::Overcast(r.uniform(0.10, 0.25)),
        },
    ];
    let mut out = Vec::new();
    let end_limit = days.saturating_sub(1) * 1440;
    // Local solar midnight, minutes after UTC midnight.
    let midnight_utc_min = (-lon_deg * 4.0).round() as i64;
    for spell in spells.iter() {
        let expected = spell.per_year * f64::from(days) / 365.0;
        let mut n = expected.floor() as u32;
        if rng.next_f64() < expected.fract() {
            n += 1;
        }
        for _ in 0..n {
            let kind = (spell.kind)(rng);
            let dur = (rng.uniform(spell.min_minutes, spell.max_minutes) as u32).max(1);
            let near_fault = rng.next_f64() < 1.0 / 3.0;
            let pick = rng.next_u64();
            let lead_min = rng.uniform(0.0, 60.0) as i64;
            let day = rng.uniform(0.0, f64::from(days.saturating_sub(1))) as i64;
            let (lo, hi) = spell.local_hours;
            let local_min = (rng.uniform(lo, hi) * 60.0) as i64;
            if end_limit <= dur + 1 {
                continue;
            }
            let start = match faults
                .get((pick % faults.len().max(1) as u64) as usize)
                .filter(|_| near_fault)
            {
                // An overcast day: the local day of the window.
                Some(w) if matches!(kind, Kind::Overcast(_)) => {
                    let d = (i64::from(w.from) - midnight_utc_min).div_euclid(1440);
                    d * 1440 + midnight_utc_min
                }
                Some(w) => i64::from(w.from) - lead_min,
                None => day * 1440 + midnight_utc_min + local_min,
            };
            let from = start.clamp(0, i64::from(end_limit - dur)) as u32;
            out.push(Window {
                kind,
                from,
                until: from + dur,
            });
        }
    }
    out.sort_by_key(|w| w.from);
    out
}

/// What the supply input reads at minute `m` in the low-supply windows of
/// `weather` (the lowest where they overlap); `None` outside them.
pub fn supply_mv(weather: &[Window], m: u32) -> Option<u16> {
    weather
        .iter()
        .filter_map(|w| match w.kind {
            Kind::LowSupply(sag_mv) => {
                let mid = w.from + (w.until - w.from) / 2;
                if (w.from..mid).contains(&m) {
                    Some(sag_mv)
                } else if w.covers(m) {
                    Some(SUPPLY_HELD_MV)
                } else if (w.until..w.until + SUPPLY_RECHARGED_MIN).contains(&m) {
                    Some(SUPPLY_RECHARGED_MV)
                } else {
                    None
                }
            }
            _ => None,
        })
        .min()
}

/// The fraction of the clear sky's irradiance the pyranometer reads at
/// minute `m` in the overcast windows of `weather`; `None` outside them.
pub fn sky_fraction(weather: &[Window], m: u32) -> Option<f64> {
    weather
        .iter()
        .filter(|w| w.covers(m))
        .filter_map(|w| match w.kind {
            Kind::Overcast(f) => Some(f),
            _ => None,
        })
        .reduce(f64::min)
}
