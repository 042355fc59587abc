//! The pose look-ahead: which of the mount's two solutions (and which turn
//! of the C axis) a day starts on, so that no axis runs into its limit
//! while the sun is up and the day's path travels least (Choi et al.
//! (portable tracker) eq. 13–21 for the solutions).
//!
//! A path that runs into a limit has to swing to another branch: half a
//! turn of the C axis with the A axis changing sign, or a whole turn of C.
//! The panel faces away from the sun for that move, so the starts are
//! ranked first by their swings, each weighted by the sun's height then
//! (its elevation over 90°, plus a little so that a swing at the horizon
//! still counts), and only among equals by travel. Where the sun never
//! sets and the C axis turns less than the sun does in a day, some swing
//! is unavoidable: the path that swings at the sun's lowest wins. The
//! scheduler's days begin at local mean solar midnight, within minutes
//! of the sun's lowest, so a polar day's one unwind falls there; a
//! branch that runs into its limit during the day all the same (after a
//! stow, or at the end of a day) is replaced by a search over the next
//! 24 hours from that moment ([`Controller::begin_swing_search`]).
//!
//! Each search follows a path of up to 48 set-points from six candidate
//! starts (one inverse kinematics each per set-point, plus a sun position
//! per set-point where no table holds them): about a second on an
//! ATmega2560. On a board that plans a few positions a tick the searches
//! advance by half that budget of set-points a tick (at least one), so no
//! loop pass holds the CPU for long; the axes hold still until the answer
//! is there (a few tens of seconds).

use sun_algos::{Float, UtcTime};

use super::Controller;
use crate::attitude::{sun_vector_xyz, Choice, MountAttitude, Pose, PoseLimits};
use crate::motion::AxisDrive;
use crate::plan::{Scheduler, SetPoint};
use crate::ports::AttitudeSensor;
use crate::safety::{Mode, Weather};
use crate::sun::PositionSource;

/// Set-points of the day's remainder the look-ahead follows, at most.
const LOOK_AHEAD_POINTS: usize = 48;

/// Half-hour samples over the 24 hours a day is judged on without a table.
const DAY_SAMPLES: u16 = 48;

/// A move between two poses whose normal sweeps more than this beyond
/// twice the angle between where they point ([`Pose::swings_from`]) is a
/// swing to another branch, not following the sun: following sweeps about
/// the sun's own arc between set-points, and the flip of the A axis under
/// a sun near the tracker's axis little more; a change of branch with the
/// panel tilted 20° sweeps 60° or more and points the same way at both
/// ends.
pub(super) const SWING_DEG: f32 = 30.0;

/// Swing weights within this of each other are equal, and travel decides.
const SWING_TIE: f32 = 0.01;

/// A swing's weight besides the sun's elevation over 90°.
const SWING_FLOOR: f32 = 0.05;

impl<T, P, D, S, const N: usize, W> Controller<T, P, D, S, N, W>
where
    T: Float,
    P: PositionSource<T>,
    D: AxisDrive,
    S: AttitudeSensor<T>,
    W: Weather,
{
    /// Set-points a search may follow in one tick: half the scheduler's
    /// plan budget (each costs six inverse kinematics, and a sun position
    /// where no table holds it), at least one; all of them when the budget
    /// is 0 (planning in one tick).
    fn search_points_per_tick(&self) -> u16 {
        match self.scheduler.plan_budget() {
            0 => u16::MAX,
            b => (b / 2).max(1),
        }
    }

    /// Entering tracking, or a new day table: begins the search for the
    /// branch of the two solutions that serves the rest of the day with
    /// least travel (the move from where the axes are now included), so
    /// that a C axis that would run into its limit at noon (and swing half
    /// a turn there) is avoided at sunrise. The day table's rest is followed
    /// (at most [`LOOK_AHEAD_POINTS`] entries apart); without a table (or
    /// on a day too long for it) the sun sampled every 30 minutes.
    ///
    /// False while the day's table begins after `now` (a polar day's new
    /// table, planned minutes before its first entry is due, while the
    /// last entry of the day before is followed): the search waits for
    /// that entry, as the branch is the new day's.
    pub(super) fn begin_look_ahead(&mut self, now: UtcTime) -> bool {
        self.branch_anchor = None;
        self.end_search();
        // A C axis that turns without end has both branches serve the day
        // alike. Tracking on (a polar day's new table), the branch
        // followed is kept: a change would be a swing for nothing. After
        // a break (the night, a re-homing, a stow) the one nearer the home
        // switches is taken, as the night's search does: the axes move
        // there anyway, and the night's re-homing then moves least.
        let here = match self.continuous_home() {
            Some(_) if self.pose_commanded && self.last_mode == Some(Mode::Tracking) => self.pose,
            Some(home) => home,
            None => self.counted_pose(),
        };
        let sampled = self.scheduler.real_time();
        let (path, first) = if sampled {
            let Some(first) = self.scheduler.applied() else {
                return true;
            };
            (
                Path::Sampled {
                    from: first.time,
                    next: 1,
                },
                first.set_point,
            )
        } else {
            let table = self.scheduler.table();
            // The entry kept as found, not decoded again by its index (68 B
            // less on the ATmega2560).
            let Some((i, entry)) = (0..table.len()).find_map(|i| {
                table
                    .get(i)
                    .filter(|e| {
                        now.seconds_since(&e.time)
                            .is_some_and(|late| (0..=60).contains(&late))
                    })
                    .map(|e| (i, e))
            }) else {
                // No entry due now: wait for the first if it is still to
                // come.
                return table.get(0).is_none_or(|e| e.time <= now);
            };
            let Ok(first) = u16::try_from(i) else {
                return true;
            };
            // The rest of the day at most LOOK_AHEAD_POINTS set-points
            // apart (every entry of a short remainder): which branch
            // travels least shows at that resolution.
            let stride = (table.len() - i).div_ceil(LOOK_AHEAD_POINTS).max(1);
            (
                Path::Table {
                    next: first,
                    first,
                    stride: u16::try_from(stride).unwrap_or(u16::MAX),
                },
                entry.set_point,
            )
        };
        self.start_branch_search(path, &first, &here);
        true
    }

    /// The home switches' pose when the C axis turns without end (the
    /// searches then charge the move from there); `None` otherwise.
    fn continuous_home(&self) -> Option<Pose<T>> {
        match &self.axes {
            [c, a] if c.is_continuous() => Some(Pose {
                gamma_deg: T::from_f32(c.home_deg()),
                alpha_deg: T::from_f32(a.home_deg()),
            }),
            _ => None,
        }
    }

    /// Ends the search in progress, the day's or the night's (one left
    /// unfinished at sunrise gives no answer: it starts again should that
    /// sunrise be waited for again).
    fn end_search(&mut self) {
        self.search = None;
        if matches!(self.night_pose, Some(NightPose::Searching(_))) {
            self.night_pose = None;
        }
    }

    /// The branch search along `path` from its first set-point `first`,
    /// the move from `here` charged; none when no pose faces `first`. Out of
    /// line on the AVR: the starts' stack copy pushed `begin_look_ahead`'s
    /// other locals beyond the 63 bytes `ldd`/`std` reach from the frame
    /// pointer (92 B less on the ATmega2560).
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn start_branch_search(&mut self, path: Path, first: &SetPoint<T>, here: &Pose<T>) {
        let sampled = matches!(path, Path::Sampled { .. });
        let limits = self.limits();
        self.end_search();
        // Built where it is stored (a copy on the stack would be some 170
        // bytes of an 8-bit board's 8 KB).
        let search = self.search.insert(PathSearch {
            path,
            starts: Starts([None; 6]),
        });
        let frame = Frame {
            attitude: &self.attitude,
            limits: &limits,
            gamma_deg: self.pose.gamma_deg,
        };
        if !search.starts.fill(&frame, first, Some(here)) {
            self.search = None;
        } else if sampled {
            search.starts.visit(first, &self.attitude, &limits);
        }
    }

    /// Advances the branch search; true while it runs (the anchor is set
    /// when it ends).
    pub(super) fn look_ahead_pending(&mut self) -> bool {
        let points = self.search_points_per_tick();
        let limits = self.limits();
        // Advanced where it is stored.
        // The one search is the night's while that runs.
        let night = matches!(self.night_pose, Some(NightPose::Searching(_)));
        let Some(search) = self.search.as_mut().filter(|_| !night) else {
            return false;
        };
        if !advance(&mut self.scheduler, &self.attitude, &limits, search, points) {
            return true;
        }
        self.branch_anchor = search.starts.best();
        self.search = None;
        false
    }

    /// Before the first day: where to wait for sunrise. The sun is sampled
    /// every 30 minutes over the 24 hours from `sunrise`, and the pose facing
    /// sunrise on the branch that serves that day with least travel is
    /// taken. `None` while the search runs (it begins in one tick and goes
    /// on in the next ones, see the module documentation), then `Some` of
    /// its answer, kept for that sunrise: a failed search (no pose facing
    /// sunrise within the limits) too.
    pub(super) fn pre_position(&mut self, sunrise: UtcTime) -> Option<Option<Pose<T>>> {
        // The limits once, for a search begun and one advanced.
        let limits = self.limits();
        match self.night_pose {
            Some(NightPose::Found(t, p)) if t == sunrise => return Some(p),
            Some(NightPose::Searching(t)) if t == sunrise => {}
            _ => {
                self.begin_night_search(sunrise, &limits);
                // On a board that spreads its work, the first position and
                // kinematics are this tick's share.
                if self.scheduler.plan_budget() != 0 {
                    return match self.night_pose {
                        Some(NightPose::Found(_, p)) => Some(p),
                        _ => None,
                    };
                }
            }
        }
        let points = self.search_points_per_tick();
        // Advanced where it is stored, as the branch search.
        let (Some(NightPose::Searching(_)), Some(search)) = (self.night_pose, self.search.as_mut())
        else {
            return match self.night_pose {
                Some(NightPose::Found(_, p)) => Some(p),
                _ => Some(None),
            };
        };
        if !advance(&mut self.scheduler, &self.attitude, &limits, search, points) {
            return None;
        }
        let pose = search.starts.best();
        self.search = None;
        self.night_pose = Some(NightPose::Found(sunrise, pose));
        Some(pose)
    }

    /// The branch of the present set-point `first` that serves the next 24
    /// hours (the sun every 30 minutes from `now`) with the fewest and
    /// lowest swings: the followed branch runs into a limit that the day's
    /// search did not foresee (the end of a polar day, a day resumed after
    /// a stow), so the axes swing now, once, to the branch that needs no
    /// other swing before the sun's lowest.
    pub(super) fn begin_swing_search(&mut self, now: UtcTime, first: &SetPoint<T>) {
        self.branch_anchor = None;
        let here = self.counted_pose();
        self.start_branch_search(Path::Sampled { from: now, next: 1 }, first, &here);
    }

    /// The night search's start: the set-point facing sunrise (one sun
    /// position) and the starts facing it, built where it is stored; found
    /// with no pose when none faces it.
    fn begin_night_search(&mut self, sunrise: UtcTime, limits: &PoseLimits<T>) {
        let first = self
            .scheduler
            .source_mut()
            .position(&sunrise)
            .ok()
            .map(|p| SetPoint::facing(&p));
        // A C axis that turns without end leaves both branches free, with
        // the same swings and travel through the day: the one nearer the
        // home switches is taken (the night's re-homing then moves least),
        // not the first of equals.
        let home = self.continuous_home();
        let frame = Frame {
            attitude: &self.attitude,
            limits,
            gamma_deg: self.pose.gamma_deg,
        };
        // The one search, which a day's branch search leaves at night.
        let search = self.search.insert(PathSearch {
            path: Path::Sampled {
                from: sunrise,
                next: 1,
            },
            starts: Starts([None; 6]),
        });
        let started = first.is_some_and(|first| {
            let ok = search.starts.fill(&frame, &first, home.as_ref());
            if ok {
                search.starts.visit(&first, &self.attitude, limits);
            }
            ok
        });
        self.night_pose = Some(if started {
            NightPose::Searching(sunrise)
        } else {
            self.search = None;
            NightPose::Found(sunrise, None)
        });
    }
}

/// Follows up to `points` more set-points of the search's path from each
/// start; true when the path has ended. Not inlined: one copy serves the
/// night's and the day's searches.
#[inline(never)]
fn advance<T: Float, P: PositionSource<T>, const N: usize>(
    scheduler: &mut Scheduler<T, P, N>,
    attitude: &MountAttitude<T>,
    limits: &PoseLimits<T>,
    search: &mut PathSearch<T>,
    points: u16,
) -> bool {
    let mut taken = 0u16;
    loop {
        let sp = match &mut search.path {
            Path::Table {
                next,
                first,
                stride,
            } => {
                let table = scheduler.table();
                let len = table.len();
                // The next entry on the stride, or the day's last.
                let on_stride = |i: usize| {
                    (i - usize::from(*first)).is_multiple_of(usize::from(*stride)) || i + 1 == len
                };
                let Some(i) = (usize::from(*next)..len).find(|&i| on_stride(i)) else {
                    return true;
                };
                *next = u16::try_from(i + 1).unwrap_or(u16::MAX);
                table.get(i).map(|e| e.set_point)
            }
            Path::Sampled { from, next } => {
                if *next >= DAY_SAMPLES {
                    return true;
                }
                let t = from.add_seconds_i32(i32::from(*next) * 1800);
                *next += 1;
                t.ok()
                    .and_then(|t| scheduler.source_mut().position(&t).ok())
                    .filter(|p| p.is_above_horizon())
                    .map(|p| SetPoint::facing(&p))
            }
        };
        if let Some(sp) = sp {
            search.starts.visit(&sp, attitude, limits);
        }
        taken = taken.saturating_add(1);
        if taken >= points {
            return false;
        }
    }
}

/// One candidate start and the path followed from it so far.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Start<T> {
    start: Pose<T>,
    /// The pose reached at the last set-point visited.
    prev: Pose<T>,
    /// Degrees travelled to reach it.
    travel: T,
    /// Its swings so far, each weighted by the sun's height then
    /// (see the module documentation).
    swings: T,
}

/// What the starts are chosen in: the mount, the axes' limits, and the C
/// angle kept when the sun on the tracker's axis leaves it free.
struct Frame<'a, T> {
    attitude: &'a MountAttitude<T>,
    limits: &'a PoseLimits<T>,
    gamma_deg: T,
}

/// The candidate starts of a search: two solutions, three turns each.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Starts<T>([Option<Start<T>>; 6]);

impl<T: Float> Starts<T> {
    /// The candidate starts for a day beginning at `first`: both poses
    /// facing it and their ±360° turns, inside the limits, each charged
    /// the move from `from` when given; false when the sun's direction
    /// gives no pose.
    /// (Few arguments: on the ATmega2560 those that do not fit the
    /// registers go on the stack, which LLVM reads one byte off there.)
    fn fill(&mut self, frame: &Frame<'_, T>, first: &SetPoint<T>, from: Option<&Pose<T>>) -> bool {
        let sun0 = sun_vector_xyz(first.elevation_deg(), first.azimuth_deg);
        let Ok(sols) = frame.attitude.solutions(&sun0, frame.gamma_deg) else {
            return false;
        };
        self.0 = [None; 6];
        let mut slots = self.0.iter_mut();
        // By reference: the array moved into its iterator was a copy on
        // the stack (64 B more on the ATmega2560).
        for sol in sols.iter() {
            // Whole turns as integers: an array of f64 read in the loop
            // would be converted by software f64 on an 8-bit board; 16 bits
            // hold them (24 B less on the ATmega2560 than `i32`).
            for turn in [-360i16, 0, 360] {
                let start = Pose {
                    gamma_deg: sol.gamma_deg + T::from_i32(i32::from(turn)),
                    alpha_deg: sol.alpha_deg,
                };
                if !frame.limits.contains(&start) {
                    continue;
                }
                if let Some(slot) = slots.next() {
                    *slot = Some(Start {
                        start,
                        prev: start,
                        travel: from.map_or(T::ZERO, |f| start.travel_deg(f)),
                        swings: T::ZERO,
                    });
                }
            }
        }
        true
    }

    /// Each start follows `sp` by its least-motion pose; a swing
    /// ([`Pose::swings_from`] with [`SWING_DEG`]) is counted, weighted by
    /// the sun's height.
    fn visit(&mut self, sp: &SetPoint<T>, attitude: &MountAttitude<T>, limits: &PoseLimits<T>) {
        let elevation_deg = sp.elevation_deg();
        let sun = sun_vector_xyz(elevation_deg, sp.azimuth_deg);
        // Linear in the elevation (no sine: ranking needs only the order).
        let weight =
            elevation_deg.max(T::ZERO) * T::from_f32(1.0 / 90.0) + T::from_f32(SWING_FLOOR);
        let swing = T::from_f32(SWING_DEG);
        for s in self.0.iter_mut().flatten() {
            if let Ok(c) = attitude.choose(&sun, &s.prev, limits) {
                let mut p = c.pose();
                if p.swings_from(&s.prev, swing) {
                    // The branch runs into a limit. A whole turn of the C
                    // axis, where the limits allow it, keeps the branch and
                    // leaves the most room ahead; the least-travel change
                    // of branch (half a turn) would meet the limit again
                    // half a day later.
                    let turn = T::from_f32(360.0);
                    let turned = Pose {
                        gamma_deg: if s.prev.gamma_deg < T::ZERO {
                            s.prev.gamma_deg + turn
                        } else {
                            s.prev.gamma_deg - turn
                        },
                        ..s.prev
                    };
                    if let Ok(Choice::Reachable(q)) = attitude.choose(&sun, &turned, limits) {
                        if !q.swings_from(&turned, swing) {
                            p = q;
                        }
                    }
                    s.swings += weight;
                }
                s.travel += p.travel_deg(&s.prev);
                s.prev = p;
            }
        }
    }

    /// The start with the lightest swings, and of those the least travel
    /// (the first of equals).
    fn best(&self) -> Option<Pose<T>> {
        let tie = T::from_f32(SWING_TIE);
        let mut best: Option<&Start<T>> = None;
        for s in self.0.iter().flatten() {
            let better = best.is_none_or(|b| {
                s.swings < b.swings - tie || (s.swings <= b.swings + tie && s.travel < b.travel)
            });
            if better {
                best = Some(s);
            }
        }
        best.map(|s| s.start)
    }
}

/// Where a search's set-points come from.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Path {
    /// The day table's entries from `first`, every `stride`-th and the
    /// last; `next` is the next index to look at.
    Table { next: u16, first: u16, stride: u16 },
    /// The sun every 30 minutes after `from`; `next` is the next sample.
    Sampled { from: UtcTime, next: u16 },
}

/// A search in progress: its path and its starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct PathSearch<T> {
    path: Path,
    starts: Starts<T>,
}

/// Where to wait for a sunrise: being searched (in the controller's one
/// search, which the day's branch search uses while tracking), or found
/// (`None`: no pose faces it within the limits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum NightPose<T> {
    Searching(UtcTime),
    Found(UtcTime, Option<Pose<T>>),
}
