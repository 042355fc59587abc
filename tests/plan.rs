//! The Jimoh & Aliyu 2019 scheduler walked through whole days.
//!
//! The sun model here is the paper's own textbook model (Jimoh & Aliyu 2019
//! eq. 2–8: Cooper declination, Spencer equation of time, hour angle),
//! written out independently of the library, so that sunrise and sunset have
//! the paper's closed form (eq. 9) to compare with.

use sun_algos::{Error, Site, SunPosition, UtcTime};
use suntracker::plan::{
    solar_day_start, Action, Daylight, Phase, ScheduleConfig, ScheduleError, Scheduler, SetPoint,
};
use suntracker::sun::PositionSource;

#[derive(Clone, Copy)]
struct Textbook {
    lat: f64,
    lon: f64,
}

impl Textbook {
    fn decl_deg(n: f64) -> f64 {
        // eq. 2
        23.45 * (360.0 / 365.25 * (284.0 + n)).to_radians().sin()
    }
    fn et_h(n: f64) -> f64 {
        // eq. 5–6
        let b = (360.0 * (n - 1.0) / 365.0).to_radians();
        229.2 / 60.0
            * (0.000075 + 0.001868 * b.cos()
                - 0.032077 * b.sin()
                - 0.014615 * (2.0 * b).cos()
                - 0.04089 * (2.0 * b).sin())
            / 60.0
    }
    /// Jimoh & Aliyu eq. 9: sunrise/sunset in UTC hours (None for polar day/night).
    fn rise_set_utc_h(&self, n: f64) -> Option<(f64, f64)> {
        let x = -(self.lat.to_radians().tan()) * Self::decl_deg(n).to_radians().tan();
        if x.abs() >= 1.0 {
            return None;
        }
        let ws = x.acos().to_degrees() / 15.0;
        // ST = UTC + lon/15 + ET (eq. 4 with LST = UTC, standard longitude 0).
        let noon_utc = 12.0 - self.lon / 15.0 - Self::et_h(n);
        Some((noon_utc - ws, noon_utc + ws))
    }
}

impl PositionSource<f64> for Textbook {
    fn site(&self) -> Site<f64> {
        Site::new(self.lat, self.lon).unwrap()
    }
    fn position(&mut self, t: &UtcTime) -> Result<SunPosition<f64>, Error> {
        let n = f64::from(t.day_of_year());
        let st = t.hours::<f64>() + self.lon / 15.0 + Self::et_h(n);
        let w = (15.0 * (st - 12.0)).to_radians(); // eq. 3
        let d = Self::decl_deg(n).to_radians();
        let phi = self.lat.to_radians();
        let sin_alt = d.sin() * phi.sin() + d.cos() * w.cos() * phi.cos(); // eq. 7
        let alt = sin_alt.clamp(-1.0, 1.0).asin();
        // eq. 8b, sign of ω; from south positive west.
        let cg =
            ((d.cos() * phi.sin() * w.cos() - d.sin() * phi.cos()) / alt.cos()).clamp(-1.0, 1.0);
        let gs = cg.acos().to_degrees().copysign(w.sin());
        Ok(SunPosition::new(90.0 - alt.to_degrees(), gs + 180.0, false))
    }
}

const KANO: Textbook = Textbook {
    lat: 11.9683,
    lon: 8.4261,
};
const TROMSO: Textbook = Textbook {
    lat: 69.65,
    lon: 18.96,
};

fn t(s: &str) -> UtcTime {
    s.parse().unwrap()
}

type Sched = Scheduler<f64, Textbook, 1441>;

/// Runs ticks every `step_s` from `from` for `secs`, collecting actions.
fn run<P: PositionSource<f64>, const N: usize>(
    s: &mut Scheduler<f64, P, N>,
    from: UtcTime,
    secs: i64,
    step_s: i64,
) -> Vec<(UtcTime, Action<f64>)> {
    let mut out = Vec::new();
    let mut k = 0;
    while k <= secs {
        let now = from.add_seconds(k).unwrap();
        let o = s.tick(now);
        if o.action != Action::Idle {
            out.push((now, o.action));
        }
        k += step_s;
    }
    out
}

#[test]
fn whole_day_in_kano_follows_the_flowchart() {
    let mut s = Sched::new(ScheduleConfig::default(), KANO).unwrap();
    assert_eq!(s.phase(), Phase::PowerOn);
    // 19 Oct 2018, the paper's example day; start before sunrise.
    let start = t("2018-10-19T03:00:00Z");
    // Step 1: set-points zero.
    let o = s.tick(start);
    assert_eq!(o.action, Action::SetPoints(SetPoint::default()));
    // Steps 2–6: before sunrise → sleep until sunrise.
    let o = s.tick(start.add_seconds(1).unwrap());
    let Action::Sleep { until } = o.action else {
        panic!("{o:?}")
    };
    let day = s.day().unwrap();
    let Daylight::Normal { rise, set } = day.daylight else {
        panic!()
    };
    assert_eq!(until, rise);
    // Sunrise and sunset agree with the paper's eq. 9 within a minute.
    let (r_h, s_h) = KANO.rise_set_utc_h(292.0).unwrap();
    let hours = |u: UtcTime| u.hours::<f64>();
    assert!((hours(rise) - r_h).abs() * 60.0 < 1.0, "{rise} vs {r_h}");
    assert!((hours(set) - s_h).abs() * 60.0 < 1.0, "{set} vs {s_h}");

    // Walk the day with 10-second ticks.
    let acts = run(&mut s, start.add_seconds(2).unwrap(), 20 * 3600, 10);
    let sets: Vec<_> = acts
        .iter()
        .filter_map(|(now, a)| match a {
            Action::SetPoints(p) => Some((*now, *p)),
            _ => None,
        })
        .collect();
    // One set-point per 4-minute table entry, applied on its minute.
    let n_entries = s.table().len();
    assert!(n_entries > 170 && n_entries < 185, "{n_entries}");
    assert_eq!(sets.len(), n_entries);
    for w in sets.windows(2) {
        assert_eq!(w[1].0.unix_seconds() - w[0].0.unix_seconds(), 240);
    }
    for (now, p) in &sets {
        // Matched within the 30-second re-check window after its time.
        assert!(now.unix_seconds() % 240 < 30);
        assert!(*now >= rise && *now < set);
        // Set-point is the sun's direction at the entry's time (entries are
        // kept in 0.01°).
        let entry = UtcTime::from_unix_seconds(now.unix_seconds() / 240 * 240).unwrap();
        let sun = KANO.clone().position(&entry).unwrap();
        assert!((p.slope_deg - sun.zenith_deg).abs() <= 0.0051);
    }
    // At solar noon eq. 7 gives zenith = φ − δ (hand formula); the
    // smallest slope of the table is within the 4-minute sampling of it.
    let decl = 23.45 * (360.0f64 / 365.25 * (284.0 + 292.0)).to_radians().sin();
    let noon_zenith = KANO.lat - decl;
    let min_slope = sets
        .iter()
        .map(|(_, p)| p.slope_deg)
        .fold(f64::INFINITY, f64::min);
    assert!(
        (min_slope - noon_zenith).abs() < 0.05,
        "{min_slope} vs {noon_zenith}"
    );
    // Morning set-points face east of south, afternoon ones west.
    assert!(sets.first().unwrap().1.azimuth_deg < 180.0);
    assert!(sets.last().unwrap().1.azimuth_deg > 180.0);

    // Step 10: after sunset, go home to the day's first position, then sleep.
    let homes: Vec<_> = acts
        .iter()
        .filter(|(_, a)| matches!(a, Action::GoHome(_)))
        .collect();
    assert_eq!(homes.len(), 1);
    let (when, Action::GoHome(home)) = homes[0] else {
        unreachable!()
    };
    assert!(*when >= set && when.unix_seconds() - set.unix_seconds() <= 10);
    assert_eq!(*home, sets[0].1);
    assert!(matches!(
        s.phase(),
        Phase::WaitNextDay { .. } | Phase::WaitSunrise { .. }
    ));
}

#[test]
fn jimoh_aliyu_intervals_hold_and_recheck() {
    // With 1-second ticks the table is searched every 30 s and, after a
    // match, not before 2 minutes: count ticks that did work.
    let mut s = Sched::new(ScheduleConfig::default(), KANO).unwrap();
    let start = t("2018-10-19T10:00:00Z");
    s.tick(start);
    let acts = run(&mut s, start.add_seconds(1).unwrap(), 3598, 1);
    let sets = acts
        .iter()
        .filter(|(_, a)| matches!(a, Action::SetPoints(_)))
        .count();
    assert_eq!(sets, 15); // 3600 s / 240 s
                          // Configurable: a 1-minute table sets 60 points in an hour.
    let cfg = ScheduleConfig {
        table_step_s: 60,
        hold_s: 30,
        ..ScheduleConfig::default()
    };
    let mut s = Sched::new(cfg, KANO).unwrap();
    s.tick(start);
    let acts = run(&mut s, start.add_seconds(1).unwrap(), 3599, 1);
    let sets = acts
        .iter()
        .filter(|(_, a)| matches!(a, Action::SetPoints(_)))
        .count();
    // 10:00 … 11:00 inclusive: the check after a hold lands on the next
    // entry's time, so the 11:00 entry is taken at the run's last tick.
    assert_eq!(sets, 61);
}

#[test]
fn polar_day_in_tromso_tracks_around_the_clock() {
    // 21 June: eq. 9 has −tanφ tanδ ≤ −1 at 69.65° N, no sunset.
    assert!(TROMSO.rise_set_utc_h(172.0).is_none());
    let mut s = Sched::new(ScheduleConfig::default(), TROMSO).unwrap();
    let start = t("2026-06-21T00:00:00Z");
    s.tick(start);
    let acts = run(&mut s, start.add_seconds(1).unwrap(), 86_400 - 1, 10);
    assert_eq!(s.day().map(|d| d.daylight), Some(Daylight::PolarDay));
    let sets = acts
        .iter()
        .filter(|(_, a)| matches!(a, Action::SetPoints(_)))
        .count();
    // Every 4-minute entry of 24 hours, give or take the day boundary.
    assert!((359..=361).contains(&sets), "{sets}");
    assert!(!acts.iter().any(|(_, a)| matches!(a, Action::Sleep { .. })));
    // The solar day ends at 22:44 UTC with the sun up: td_ed is zero, no
    // going home, the next day's table follows at once.
    assert!(!acts.iter().any(|(_, a)| matches!(a, Action::GoHome(_))));
    // Midnight sun: set-points with the sun due north, low.
    let midnight = acts
        .iter()
        .find_map(|(n, a)| match a {
            Action::SetPoints(p) if n.hms_milli().0 == 22 && n.hms_milli().1 == 44 => Some(*p),
            _ => None,
        })
        .unwrap();
    assert!(midnight.slope_deg > 80.0 && midnight.slope_deg < 90.0);
    assert!(midnight.azimuth_deg > 350.0 || midnight.azimuth_deg < 10.0);
}

#[test]
fn polar_night_in_tromso_never_moves() {
    assert!(TROMSO.rise_set_utc_h(355.0).is_none());
    let mut s = Sched::new(ScheduleConfig::default(), TROMSO).unwrap();
    let start = t("2026-12-21T00:00:00Z");
    assert_eq!(s.tick(start).action, Action::SetPoints(SetPoint::default()));
    let acts = run(&mut s, start.add_seconds(1).unwrap(), 2 * 86_400, 60);
    assert_eq!(s.day().map(|d| d.daylight), Some(Daylight::PolarNight));
    assert!(acts.iter().all(|(_, a)| matches!(a, Action::Sleep { .. })));
    // One plan per solar day, each sleeping until the next solar midnight
    // (00:00 UTC − 18.96°/15 h ≈ 22:44 UTC).
    assert!((2..=3).contains(&acts.len()), "{acts:?}");
    for (_, a) in &acts {
        let Action::Sleep { until } = a else {
            unreachable!()
        };
        assert_eq!(until.hms_milli().0, 22);
        assert_eq!(until.hms_milli().1, 44);
    }
}

#[test]
fn clock_jump_forward_and_backward_replans() {
    let cfg = ScheduleConfig::default();
    let mut s = Sched::new(cfg, KANO).unwrap();
    let start = t("2018-10-19T09:00:00Z");
    s.tick(start);
    run(&mut s, start.add_seconds(1).unwrap(), 600, 10);
    // Forward: 09:10 → 13:00 the same day; the 13:00 entry is set at once.
    let o = s.tick(t("2018-10-19T13:00:00Z"));
    assert!(o.clock_jump);
    let Action::SetPoints(p) = o.action else {
        panic!("{o:?}")
    };
    let sun = KANO.clone().position(&t("2018-10-19T13:00:00Z")).unwrap();
    assert!((p.azimuth_deg - sun.azimuth_deg).abs() <= 0.0051);
    // Backward: 13:00 → 08:00; no waiting for a 13:02 hold, 08:00 is set.
    let o = s.tick(t("2018-10-19T08:00:00Z"));
    assert!(o.clock_jump);
    let Action::SetPoints(p) = o.action else {
        panic!("{o:?}")
    };
    let sun = KANO.clone().position(&t("2018-10-19T08:00:00Z")).unwrap();
    assert!((p.azimuth_deg - sun.azimuth_deg).abs() <= 0.0051);
    // Backward across midnight into the previous night: sleeps until that
    // day's sunrise.
    let o = s.tick(t("2018-10-18T02:00:00Z"));
    assert!(o.clock_jump);
    let Action::Sleep { until } = o.action else {
        panic!("{o:?}")
    };
    assert_eq!(until.ymd(), (2018, 10, 18));
    // Forward two days, into the afternoon: tracking that day's table.
    let o = s.tick(t("2018-10-20T15:00:00Z"));
    assert!(o.clock_jump);
    assert!(matches!(o.action, Action::SetPoints(_)));
    assert_eq!(s.table().get(0).unwrap().time.ymd(), (2018, 10, 20));
    // Small forward steps are not jumps.
    let o = s.tick(t("2018-10-20T15:01:00Z"));
    assert!(!o.clock_jump);
}

#[test]
fn invalid_intervals_are_rejected() {
    let bad = [
        ScheduleConfig {
            table_step_s: 0,
            ..ScheduleConfig::default()
        },
        ScheduleConfig {
            table_step_s: 7,
            ..ScheduleConfig::default()
        },
        ScheduleConfig {
            recheck_s: 0,
            ..ScheduleConfig::default()
        },
    ];
    for c in bad {
        assert!(Sched::new(c, KANO).is_err());
    }
    // Not whole minutes.
    let c = ScheduleConfig {
        table_step_s: 90,
        ..ScheduleConfig::default()
    };
    assert!(Sched::new(c, KANO).is_err());
}

#[test]
fn a_day_longer_than_the_table_is_tracked_slot_by_slot_not_truncated() {
    // 24 hours at 4 minutes need 360 or 361 entries; 300 do not hold them:
    // no table (never a truncated one), the sun computed for each slot.
    let mut s = Scheduler::<f64, Textbook, 300>::new(ScheduleConfig::default(), TROMSO).unwrap();
    let start = t("2026-06-21T10:00:00Z");
    s.tick(start);
    let o = s.tick(start.add_seconds(1).unwrap());
    let Action::SetPoints(sp) = o.action else {
        panic!("{o:?}");
    };
    assert!(s.real_time());
    assert_eq!(s.table().len(), 0);
    let mut tromso = TROMSO;
    let sun = tromso.position(&start).unwrap();
    assert!((sp.slope_deg - sun.zenith_deg).abs() < 1e-9);
    assert!((sp.azimuth_deg - sun.azimuth_deg).abs() < 1e-9);
    // Kano's longest day fits the same table.
    let mut s = Scheduler::<f64, Textbook, 300>::new(ScheduleConfig::default(), KANO).unwrap();
    let start = t("2026-06-21T10:00:00Z");
    s.tick(start);
    assert!(matches!(
        s.tick(start.add_seconds(1).unwrap()).action,
        Action::SetPoints(_)
    ));
}

/// Planning spread over ticks (a slow board's budget) computes the same day
/// as planning in one tick, never more positions per tick than the budget,
/// and tracks from the first tick after the plan completes.
#[test]
fn planning_in_small_steps_gives_the_same_day() {
    struct Counting {
        sun: Textbook,
        calls: u32,
    }
    impl PositionSource<f64> for Counting {
        fn site(&self) -> Site<f64> {
            self.sun.site()
        }
        fn position(&mut self, t: &UtcTime) -> Result<SunPosition<f64>, Error> {
            self.calls += 1;
            self.sun.position(t)
        }
    }
    // Noon at Kano on the paper's example day: the whole table is needed.
    let noon = t("2018-10-19T11:30:00Z");
    let mut whole = Sched::new(ScheduleConfig::default(), KANO).unwrap();
    whole.tick(noon);
    let first_set_point = |s: &mut Sched| {
        (1..600).find_map(|k| match s.tick(noon.add_seconds(k).unwrap()).action {
            Action::SetPoints(sp) => Some((k, sp)),
            _ => None,
        })
    };
    // The one-tick planner plans at +1 s and re-checks every 30 s (flowchart
    // step 12), but never past the next entry's time: the 11:32 entry is
    // found at 11:32:00.
    let (k_whole, expected) = first_set_point(&mut whole).unwrap();
    assert_eq!(k_whole, 120);
    let budget = 4;
    let mut s = Scheduler::<f64, Counting, 1441>::new(
        ScheduleConfig::default(),
        Counting {
            sun: KANO,
            calls: 0,
        },
    )
    .unwrap();
    s.set_plan_budget(budget);
    s.tick(noon);
    let mut ticks = 0;
    let mut planned_at = None;
    let got = loop {
        ticks += 1;
        let before = s.source_mut().calls;
        let o = s.tick(noon.add_seconds(ticks).unwrap());
        assert!(s.source_mut().calls - before <= u32::from(budget));
        match (o.action, s.phase()) {
            (Action::Idle, Phase::Planning) => {
                assert!(s.table().is_empty(), "a table shown before it is complete");
            }
            (Action::Idle, Phase::Tracking { .. }) => {
                planned_at.get_or_insert(ticks);
            }
            (Action::SetPoints(sp), _) => break sp,
            other => panic!("{other:?} while planning"),
        }
    };
    let planned_at = planned_at.unwrap();
    // ~190 positions for the events and one per 4-minute entry.
    let total = s.source_mut().calls;
    assert!((300..=450).contains(&total), "{total} positions");
    assert!(planned_at as u32 >= total / u32::from(budget));
    assert!(planned_at < 115, "planned at +{planned_at} s");
    // Planned within the two minutes before the 11:32 entry: the same
    // first set-point at the same tick.
    assert_eq!((ticks, got), (k_whole, expected));
    assert_eq!(s.table().len(), whole.table().len());
    for i in 0..whole.table().len() {
        assert_eq!(s.table().get(i), whole.table().get(i));
    }
    assert_eq!(s.day(), whole.day());
}

/// Checks every recheck_s against a window of recheck_s drift: each check
/// comes when the first tick at or after its time does, the next one is
/// counted from there, and the lateness adds up until a check falls past
/// the window and an entry is skipped (seen in emulation, where a slow loop
/// pass delays a tick). The check after a hold lands on the next entry's
/// time instead: with a tick every 7 s every entry is taken, each within
/// 7 s of its time.
#[test]
fn late_ticks_skip_no_entry() {
    let mut s = Sched::new(ScheduleConfig::default(), KANO).unwrap();
    let start = t("2018-10-19T10:00:00Z");
    s.tick(start);
    let mut taken = Vec::new();
    for k in 1..=(2 * 3600 / 7) {
        let now = start.add_seconds(7 * k).unwrap();
        if let Action::SetPoints(_) = s.tick(now).action {
            taken.push(now);
        }
    }
    // 10:00 … 11:56: thirty entries, none skipped.
    assert_eq!(taken.len(), 30, "{taken:?}");
    for t in &taken {
        assert!(t.unix_seconds().rem_euclid(240) <= 7, "taken at {t}");
    }
}

// ---------------------------------------------------------------------
// Real-time mode (`N = 0`): no table, one position per slot when it falls
// due (Chowdhury et al.'s (2019) way, on 4-minute slots).

type RealTime<P> = Scheduler<f64, P, 0>;

// A table capacity of 0 is the real-time mode.
const _: () = assert!(RealTime::<Textbook>::REAL_TIME);

/// A source that counts the positions it computes.
struct Counting<P> {
    inner: P,
    calls: u32,
}

impl<P: PositionSource<f64>> PositionSource<f64> for Counting<P> {
    fn site(&self) -> Site<f64> {
        self.inner.site()
    }
    fn position(&mut self, t: &UtcTime) -> Result<SunPosition<f64>, Error> {
        self.calls += 1;
        self.inner.position(t)
    }
}

/// A real-time scheduler at `site` whose source counts its positions.
fn counting(site: Textbook) -> RealTime<Counting<Textbook>> {
    RealTime::new(
        ScheduleConfig::default(),
        Counting {
            inner: site,
            calls: 0,
        },
    )
    .unwrap()
}

#[test]
fn real_time_day_in_kano_follows_the_flowchart() {
    let mut s = RealTime::new(ScheduleConfig::default(), KANO).unwrap();
    let start = t("2018-10-19T03:00:00Z");
    // Step 1, then outside daylight: sleep until the next slot.
    assert_eq!(s.tick(start).action, Action::SetPoints(SetPoint::default()));
    let o = s.tick(start.add_seconds(1).unwrap());
    assert_eq!(
        o.action,
        Action::Sleep {
            until: t("2018-10-19T03:04:00Z")
        }
    );
    assert!(s.table().is_empty());
    let acts = run(&mut s, start.add_seconds(2).unwrap(), 20 * 3600, 10);
    let sets: Vec<_> = acts
        .iter()
        .filter_map(|(now, a)| match a {
            Action::SetPoints(p) => Some((*now, *p)),
            _ => None,
        })
        .collect();
    // The slots with the textbook sun's centre above the horizon (eq. 9),
    // counted here from the model: every one set, on time, facing the sun
    // at the slot's time.
    let day0 = t("2018-10-19T00:00:00Z").unix_seconds();
    let expected: Vec<UtcTime> = (0..360)
        .map(|k| UtcTime::from_unix_seconds(day0 + k * 240).unwrap())
        .filter(|u| KANO.clone().position(u).unwrap().zenith_deg < 90.0)
        .collect();
    assert_eq!(sets.len(), expected.len());
    for ((now, p), slot) in sets.iter().zip(&expected) {
        assert_eq!(
            now.unix_seconds() - now.unix_seconds() % 240,
            slot.unix_seconds()
        );
        assert!(
            now.unix_seconds() - slot.unix_seconds() < 30,
            "late at {now}"
        );
        let sun = KANO.clone().position(slot).unwrap();
        assert_eq!(*p, SetPoint::facing(&sun));
    }
    // The first and last set-points bracket eq. 9's sunrise and sunset
    // within a slot.
    let (r_h, s_h) = KANO.rise_set_utc_h(292.0).unwrap();
    let h = |u: &UtcTime| u.hours::<f64>();
    let first = expected.first().unwrap();
    let last = expected.last().unwrap();
    assert!(h(first) >= r_h - 1.0 / 60.0 && h(first) - r_h < 4.0 / 60.0);
    assert!(h(last) <= s_h + 1.0 / 60.0 && s_h - h(last) < 4.0 / 60.0);
    // Step 10: home once, at the first slot after daylight, to the day's
    // first set-point; then nothing but waiting.
    let homes: Vec<_> = acts
        .iter()
        .filter_map(|(now, a)| match a {
            Action::GoHome(p) => Some((*now, *p)),
            _ => None,
        })
        .collect();
    assert_eq!(homes.len(), 1);
    assert_eq!(homes[0].1, sets[0].1);
    let home_slot = homes[0].0.unix_seconds() / 240 * 240;
    assert_eq!(home_slot, last.unix_seconds() + 240);
    assert_eq!(s.day_key(), Some(*first));
    assert!(!acts.iter().any(|(_, a)| matches!(a, Action::Error(_))));
}

#[test]
fn real_time_mode_computes_one_position_per_slot() {
    let mut s = counting(KANO);
    let start = t("2018-10-19T10:00:00Z");
    s.tick(start);
    // An hour of 1-second ticks: 15 set-points of Jimoh & Aliyu's 4-minute
    // table, their 2-minute hold, and one sun position per 4-minute slot.
    let acts = run(&mut s, start.add_seconds(1).unwrap(), 3598, 1);
    let sets = acts
        .iter()
        .filter(|(_, a)| matches!(a, Action::SetPoints(_)))
        .count();
    assert_eq!(sets, 15);
    assert_eq!(s.source_mut().calls, 15);
    // The entry in force for any instant of its slot, none for the next.
    let e = s.applied().unwrap();
    assert_eq!(e.time, t("2018-10-19T10:56:00Z"));
    assert_eq!(s.current(&t("2018-10-19T10:59:59Z")), Some(e));
    assert_eq!(s.current(&t("2018-10-19T11:00:00Z")), None);
}

#[test]
fn real_time_polar_day_and_night_in_tromso() {
    // 21 June: every slot of 24 hours is daylight; no home; a new day
    // (and home) from the first slot after the solar midnight (00:00 UTC −
    // 18.96°/15 h = 22:44:10 UTC): 22:48.
    let mut s = RealTime::new(ScheduleConfig::default(), TROMSO).unwrap();
    let start = t("2026-06-21T00:00:00Z");
    s.tick(start);
    let acts = run(&mut s, start.add_seconds(1).unwrap(), 86_400 - 1, 10);
    let sets = acts
        .iter()
        .filter(|(_, a)| matches!(a, Action::SetPoints(_)))
        .count();
    assert_eq!(sets, 360);
    assert!(!acts
        .iter()
        .any(|(_, a)| matches!(a, Action::GoHome(_) | Action::Sleep { .. })));
    assert_eq!(s.day_key(), Some(t("2026-06-21T22:48:00Z")));
    // 21 December: never daylight; one Sleep after power-on, then nothing.
    let mut s = RealTime::new(ScheduleConfig::default(), TROMSO).unwrap();
    let start = t("2026-12-21T00:00:00Z");
    assert_eq!(s.tick(start).action, Action::SetPoints(SetPoint::default()));
    let acts = run(&mut s, start.add_seconds(1).unwrap(), 2 * 86_400, 60);
    assert_eq!(acts.len(), 1, "{acts:?}");
    assert!(matches!(acts[0].1, Action::Sleep { .. }));
    assert_eq!(s.day_key(), None);
}

#[test]
fn real_time_clock_jumps_set_the_new_slot_at_once() {
    let mut s = RealTime::new(ScheduleConfig::default(), KANO).unwrap();
    let start = t("2018-10-19T09:00:00Z");
    s.tick(start);
    run(&mut s, start.add_seconds(1).unwrap(), 600, 10);
    for (to, slot) in [
        ("2018-10-19T13:00:10Z", "2018-10-19T13:00:00Z"),
        ("2018-10-19T08:00:05Z", "2018-10-19T08:00:00Z"),
    ] {
        let o = s.tick(t(to));
        assert!(o.clock_jump);
        let sun = KANO.clone().position(&t(slot)).unwrap();
        assert_eq!(o.action, Action::SetPoints(SetPoint::facing(&sun)));
    }
    // Into the night: waits (Sleep) for the next slot.
    let o = s.tick(t("2018-10-18T02:00:00Z"));
    assert!(o.clock_jump);
    assert_eq!(
        o.action,
        Action::Sleep {
            until: t("2018-10-18T02:04:00Z")
        }
    );
}

#[test]
fn real_time_mode_finds_the_coming_sunrise_a_budget_of_slots_a_tick() {
    // Powered on at Kano at night, 4 positions a tick (the ATmega2560's
    // budget): the coming sunrise is the first slot with the textbook sun's
    // centre above the horizon (eq. 9), within a slot of eq. 9's closed
    // form, and tracking begins at that slot.
    let mut s = counting(KANO);
    s.set_plan_budget(4);
    let start = t("2018-10-19T01:00:00Z");
    s.tick(start);
    assert_eq!(s.next_sunrise(), None);
    let day0 = t("2018-10-19T00:00:00Z").unix_seconds();
    let rise = (0..360)
        .map(|k| UtcTime::from_unix_seconds(day0 + k * 240).unwrap())
        .find(|u| KANO.clone().position(u).unwrap().zenith_deg < 90.0)
        .unwrap();
    let (r_h, _) = KANO.rise_set_utc_h(292.0).unwrap();
    assert!(rise.hours::<f64>() >= r_h && rise.hours::<f64>() - r_h < 4.0 / 60.0);
    // From 01:04 (the first slot of the wait) to sunrise: one position per
    // slot, at most 4 a tick, and none after it is found.
    let slots = (rise.unix_seconds() - t("2018-10-19T01:04:00Z").unix_seconds()) / 240 + 1;
    let mut found_at = None;
    for k in 1..=600 {
        let now = start.add_seconds(k).unwrap();
        let before = s.source_mut().calls;
        s.tick(now);
        assert!(s.source_mut().calls - before <= 4 + 1, "at {now}");
        if found_at.is_none() && s.next_sunrise().is_some() {
            found_at = Some(k);
        }
    }
    assert_eq!(s.next_sunrise(), Some(rise));
    // The slot checks of the wait (one per 4 minutes) and the search.
    let checks = 600 / 240 + 1;
    assert_eq!(u64::from(s.source_mut().calls), slots as u64 + checks);
    // Its first tick began the wait, the search began with the next.
    assert_eq!(found_at, Some(1 + (slots + 3) / 4));
    // Tracking from that slot on; the next night finds the next sunrise.
    let acts = run(&mut s, start.add_seconds(601).unwrap(), 86_400, 10);
    let first_set = acts
        .iter()
        .find(|(now, a)| matches!(a, Action::SetPoints(_)) && *now >= rise)
        .unwrap();
    assert_eq!(first_set.0.unix_seconds() / 240 * 240, rise.unix_seconds());
    let next_rise = (0..360)
        .map(|k| UtcTime::from_unix_seconds(day0 + 86_400 + k * 240).unwrap())
        .find(|u| KANO.clone().position(u).unwrap().zenith_deg < 90.0)
        .unwrap();
    assert_eq!(s.next_sunrise(), Some(next_rise));
}

#[test]
fn real_time_mode_finds_no_sunrise_in_a_polar_night_and_searches_a_day_ahead() {
    // Tromsø, 21 December: no slot within a day has the sun up; the search
    // keeps a day ahead of the clock (about one position per slot once it
    // has caught up) and reports nothing.
    let mut s = counting(TROMSO);
    s.set_plan_budget(4);
    let start = t("2026-12-21T00:00:00Z");
    s.tick(start);
    run(&mut s, start.add_seconds(1).unwrap(), 2 * 86_400, 60);
    assert_eq!(s.next_sunrise(), None);
    assert!(matches!(s.phase(), Phase::WaitSunrise { .. }));
    // A day of slots ahead, two days of slots passed, two days of checks.
    let calls = s.source_mut().calls;
    assert!(
        (3 * 360..=3 * 360 + 2 * 360 + 4).contains(&calls),
        "{calls}"
    );
}

/// The solar midnight as it was computed before the firmware dropped `f64`
/// and 64-bit division: `s = lon·240` widened to `f64` and truncated, then
/// `div_euclid` on the seconds. The reference for the integer version.
fn solar_day_start_in_f64<T: sun_algos::Float>(now: &UtcTime, lon: T) -> Option<UtcTime> {
    let s = (lon * T::from_f64(240.0)).to_f64();
    let off = if s.is_finite() { s as i64 } else { 0 };
    let local = now.unix_seconds() + off;
    UtcTime::from_unix_seconds(local.div_euclid(86_400) * 86_400 - off).ok()
}

#[test]
fn solar_day_start_agrees_with_the_f64_version() {
    // Longitudes every 0.37° and at the whole degrees and seconds of time
    // (1/240°) around each, where truncation decides; instants around
    // midnights and the ends of the calendar.
    let nows = [
        t("2026-03-20T00:00:00Z"),
        t("2026-03-20T23:59:59.999Z"),
        t("2026-06-21T11:59:59Z"),
        t("1999-12-31T12:00:00Z"),
        UtcTime::from_days_ms(-2_191_000, 43_200_000).unwrap(),
    ];
    let mut lons = vec![
        f64::NAN,
        f64::INFINITY,
        -180.0,
        180.0,
        0.0,
        -0.0,
        1e-300,
        -1e-300,
    ];
    for k in -500..=500 {
        let lon = f64::from(k) * 0.37 - 0.25;
        lons.extend([lon, (lon * 240.0).round() / 240.0, lon.round()]);
    }
    for now in &nows {
        for &lon in &lons {
            let want = solar_day_start_in_f64(now, lon).ok_or(ScheduleError::TimeRange);
            assert_eq!(solar_day_start(now, lon), want, "{now} {lon}");
            let lon = lon as f32;
            let want = solar_day_start_in_f64(now, lon).ok_or(ScheduleError::TimeRange);
            assert_eq!(solar_day_start(now, lon), want, "{now} {lon}");
        }
    }
}

/// The boards' scheduler (`BoardSource<f32>`, psa-2020 in f32, a plan
/// budget of 4 positions a tick) at and next to both poles, at a
/// whole-degree longitude (solar midnight on a 4-minute step: the polar day
/// needs both midnights, 361 entries) and at 8.4° E (360). A polar day plans
/// and tracks the sun around the clock, a polar night sleeps; no error.
/// With a table too short for the day, the day is tracked slot by slot.
#[test]
fn poles_plan_and_track_in_f32_with_a_polar_day_table() {
    use sun_algos::geometry::day_table::capacity_for_interval;
    use suntracker::sun::BoardSource;
    const N: usize = capacity_for_interval(4);

    fn day<const M: usize>(
        lat: f32,
        lon: f32,
        date: &str,
    ) -> (Vec<Action<f32>>, Scheduler<f32, BoardSource<f32>, M>) {
        let src = BoardSource::<f32>::new(Site::new(lat, lon).unwrap(), 69.0);
        let mut s = Scheduler::<f32, _, M>::new(ScheduleConfig::default(), src).unwrap();
        s.set_plan_budget(4);
        let start = t(&format!("{date}T00:00:00Z"));
        let mut acts = Vec::new();
        for k in 0..(2 * 8640) {
            let a = s.tick(start.add_seconds(k * 10).unwrap()).action;
            if a != Action::Idle {
                acts.push(a);
            }
        }
        (acts, s)
    }

    for lat in [90.0f32, 89.9999, 89.99, -90.0, -89.9999] {
        for lon in [0.0f32, 8.4, -180.0] {
            for (date, summer_north) in [("2026-06-21", true), ("2026-12-21", false)] {
                let (acts, mut s) = day::<N>(lat, lon, date);
                let what = format!("lat {lat} lon {lon} {date}");
                assert!(
                    !acts.iter().any(|a| matches!(a, Action::Error(_))),
                    "{what}: {:?}",
                    acts.iter().find(|a| matches!(a, Action::Error(_)))
                );
                if (lat > 0.0) == summer_north {
                    assert_eq!(
                        s.day().map(|d| d.daylight),
                        Some(Daylight::PolarDay),
                        "{what}"
                    );
                    // One set-point a table step for two days, around the clock.
                    let sets: Vec<_> = acts
                        .iter()
                        .filter_map(|a| match a {
                            Action::SetPoints(p) => Some(*p),
                            _ => None,
                        })
                        .collect();
                    assert!(sets.len() > 700, "{what}: {} set-points", sets.len());
                    // The last one faces the sun of its slot: about 23.4° up.
                    let now = t(&format!("{date}T00:00:00Z"))
                        .add_seconds(2 * 86_400 - 10)
                        .unwrap();
                    let e = s.current(&now).unwrap();
                    let sun = s.source_mut().position(&e.time).unwrap();
                    assert!(
                        (e.set_point.slope_deg - sun.zenith_deg).abs() < 0.01,
                        "{what}"
                    );
                    assert!((e.set_point.elevation_deg() - 23.4).abs() < 0.3, "{what}");
                } else {
                    assert_eq!(
                        s.day().map(|d| d.daylight),
                        Some(Daylight::PolarNight),
                        "{what}"
                    );
                    assert!(
                        acts[1..].iter().all(|a| matches!(a, Action::Sleep { .. })),
                        "{what}"
                    );
                }
            }
        }
    }
    // A shorter table (the boards' former 360 and the ATmega2560's 240): a
    // day longer than it is tracked slot by slot (as in real-time mode)
    // until the sun sets, never refused. Tromsø (69.65° N) has its polar
    // day in June; at 55° N the day lasts 17.5 h, longer than 240 entries
    // of 4 minutes (16 h), and the sun sets each night.
    fn short_table<const M: usize>(lat: f32, lon: f32, min_sets: usize, polar: bool) {
        let what = format!("{M} entries, lat {lat} lon {lon}");
        let (acts, mut s) = day::<M>(lat, lon, "2026-06-21");
        assert!(
            !acts.iter().any(|a| matches!(a, Action::Error(_))),
            "{what}: {:?}",
            acts.iter().find(|a| matches!(a, Action::Error(_)))
        );
        let sets = acts
            .iter()
            .filter(|a| matches!(a, Action::SetPoints(_)))
            .count();
        assert!(sets >= min_sets, "{what}: {sets} set-points");
        let homes = acts
            .iter()
            .filter(|a| matches!(a, Action::GoHome(_)))
            .count();
        assert_eq!(homes, if polar { 0 } else { 2 }, "{what}: {homes} nights");
        if polar {
            let now = t("2026-06-21T00:00:00Z")
                .add_seconds(2 * 86_400 - 10)
                .unwrap();
            let e = s.current(&now).unwrap();
            let sun = s.source_mut().position(&e.time).unwrap();
            assert!(
                (e.set_point.slope_deg - sun.zenith_deg).abs() < 0.01,
                "{what}"
            );
        }
    }
    short_table::<360>(90.0, 0.0, 700, true);
    short_table::<240>(90.0, 0.0, 700, true);
    short_table::<240>(69.65, 18.96, 700, true);
    // Two days of 17.5 h at one set-point per 4 minutes.
    short_table::<240>(55.0, 8.4, 2 * 17 * 15, false);
}

/// The entry of a table for the slot `now` is in, found by looking at every
/// entry (what `Scheduler::current` must return).
fn slot_entry(s: &Sched, now: &UtcTime) -> Option<suntracker::plan::TableEntry<f64>> {
    let step_s = i64::from(s.config().table_step_s);
    let table = s.table();
    (0..table.len())
        .filter_map(|i| table.get(i))
        .find(|e| (0..step_s).contains(&now.seconds_since(&e.time).map_or(-1, i64::from)))
}

#[test]
fn table_current_is_the_slot_entry_applied_or_not() {
    let mut s = Sched::new(ScheduleConfig::default(), KANO).unwrap();
    let start = t("2018-10-19T03:00:00Z");
    // Tracked with 1-second ticks until 10:00:30.
    run(&mut s, start, 7 * 3600 + 30, 1);
    let now = t("2018-10-19T10:00:30Z");
    let applied = s.applied().unwrap();
    assert_eq!(applied.time, t("2018-10-19T10:00:00Z"));
    // The slot's entry is the one applied.
    assert_eq!(s.current(&now), Some(applied));
    assert_eq!(s.current(&now), slot_entry(&s, &now));
    // Ticks missed: 17 minutes later the applied entry is of an earlier
    // slot; the table's entry of the present one (10:16) is returned.
    let later = t("2018-10-19T10:17:10Z");
    let e = s.current(&later).unwrap();
    assert_eq!(e.time, t("2018-10-19T10:16:00Z"));
    assert_eq!(Some(e), slot_entry(&s, &later));
    assert_ne!(Some(e), s.applied());
    // Before sunrise no slot of the table.
    assert_eq!(s.current(&t("2018-10-19T04:00:00Z")), None);
}

/// `match_at` against a look at every entry: the latest entry whose time
/// lies in `(now − window, now]` in whole seconds
/// (`UtcTime::seconds_since`), with `now` on and off whole seconds, in and
/// past the window.
#[test]
fn match_at_is_the_entry_within_the_window() {
    let mut s = Sched::new(ScheduleConfig::default(), KANO).unwrap();
    run(&mut s, t("2018-10-19T03:00:00Z"), 7 * 3600 + 30, 1);
    let view = s.table();
    let table = view.raw().expect("a table");
    let by_look = |now: &UtcTime, window_s: i64| {
        (0..s.table().len()).rev().find_map(|i| {
            let e = s.table().get(i)?;
            let late = now.seconds_since(&e.time).map_or(-1, i64::from);
            (0..window_s.max(1)).contains(&late).then_some((i, e))
        })
    };
    let mut checked = 0;
    for now in [
        "2018-10-19T03:00:00Z",
        "2018-10-19T10:00:00Z",
        "2018-10-19T10:00:29.700Z",
        "2018-10-19T10:00:30Z",
        "2018-10-19T10:00:30.200Z",
        "2018-10-19T10:03:59.999Z",
        "2018-10-19T12:34:05.500Z",
        "2018-10-19T23:00:00Z",
    ] {
        let now = t(now);
        for window_s in [0u32, 1, 30, 240, 600] {
            let got = suntracker::plan::match_at::<f64, 1441>(table, &now, window_s);
            assert_eq!(got, by_look(&now, i64::from(window_s)), "{now} {window_s}");
            checked += usize::from(got.is_some());
        }
    }
    // Some inside a window, some not (the loop above is no vacuous test).
    assert!((5..35).contains(&checked), "{checked}");
}
