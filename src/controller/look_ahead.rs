//! The pose look-ahead: which of the mount's two solutions (and which turn
//! of the C axis) a day starts on, so that the day's path travels least
//! and no axis runs into its limit at noon (Choi et al. (portable tracker) eq. 13–21
//! for the solutions).

use sun_algos::{Float, UtcTime};

use super::Controller;
use crate::attitude::{sun_vector_xyz, Pose};
use crate::motion::AxisDrive;
use crate::plan::SetPoint;
use crate::ports::AttitudeSensor;
use crate::sun::PositionSource;

/// Set-points of the day's remainder the look-ahead follows, at most.
const LOOK_AHEAD_POINTS: usize = 48;

/// A path of set-points as `best_start` walks it: handed a visitor, it
/// calls it once per set-point, in order.
type SetPointPath<'a, T> = &'a dyn Fn(&mut dyn FnMut(SetPoint<T>));

impl<T, P, D, S, const N: usize> Controller<T, P, D, S, N>
where
    T: Float,
    P: PositionSource<T>,
    D: AxisDrive,
    S: AttitudeSensor<T>,
{
    /// [`Self::look_ahead`] without a table (or on a day too long for
    /// it): the rest of the day sampled every 30 minutes from the set-point
    /// in force. Its own frame: the samples are on the stack only here, not
    /// under the table's look-ahead.
    #[inline(never)]
    fn look_ahead_sampled(&mut self) -> Option<Pose<T>> {
        let first = self.scheduler.applied()?;
        let here = Pose {
            gamma_deg: T::from_f32(self.axes[0].counted_deg()),
            alpha_deg: T::from_f32(self.axes[1].counted_deg()),
        };
        let (samples, n) = self.sample_day(first.time, first.set_point);
        self.best_start(&first.set_point, Some(&here), &|visit| {
            samples.iter().take(n).for_each(|&sp| visit(sp))
        })
    }

    /// Follows the rest of the day table from each candidate starting pose
    /// (both solutions of the first entry, and their ±360° turns), each
    /// step taking the least-motion solution, and returns the start whose
    /// day needs the least travel (the move from where the axes are now
    /// included): a C axis that would run into its limit at noon (and swing
    /// half a turn there) is avoided at sunrise.
    pub(super) fn look_ahead(&mut self, now: UtcTime) -> Option<Pose<T>> {
        if self.scheduler.real_time() {
            return self.look_ahead_sampled();
        }
        let table = self.scheduler.table();
        let first = (0..table.len())
            .filter_map(|i| table.get(i))
            .find(|e| now.seconds_since(&e.time).is_some_and(|late| late <= 60))?;
        let here = Pose {
            gamma_deg: T::from_f32(self.axes[0].counted_deg()),
            alpha_deg: T::from_f32(self.axes[1].counted_deg()),
        };
        // The rest of the day at most LOOK_AHEAD_POINTS set-points apart
        // (every entry of a short remainder): which branch travels least
        // shows at that resolution, and on an 8-bit board the whole table
        // (six starts by ~180 entries of inverse kinematics) would hold
        // the loop past the watchdog's 2 s.
        let rest = (0..table.len())
            .filter(|&i| table.get(i).is_some_and(|e| e.time >= first.time))
            .count();
        let stride = rest.div_ceil(LOOK_AHEAD_POINTS).max(1);
        let skip = table.len() - rest;
        self.best_start(&first.set_point, Some(&here), &|visit| {
            (skip..table.len())
                .filter(|i| (i - skip).is_multiple_of(stride) || *i + 1 == table.len())
                .filter_map(|i| table.get(i))
                .for_each(|e| visit(e.set_point))
        })
    }

    /// Of the poses facing `first`, the one whose path through the
    /// set-points `path` hands its visitor (least motion at each step)
    /// travels least, plus the move from `from` when given. The path is a
    /// visitor, not a generic iterator: one copy of this search serves
    /// both callers (each generic copy took about 3 KB of an 8-bit
    /// board's flash).
    /// (Arguments by reference: on the ATmega2560 by value they would not
    /// all fit the registers, and LLVM reads stack arguments one byte off
    /// there.)
    fn best_start(
        &self,
        first: &SetPoint<T>,
        from: Option<&Pose<T>>,
        path: SetPointPath<'_, T>,
    ) -> Option<Pose<T>> {
        let limits = self.limits();
        let sun0 = sun_vector_xyz(first.elevation_deg(), first.azimuth_deg);
        let sols = self.attitude.solutions(&sun0, self.pose.gamma_deg).ok()?;
        let dist = |a: &Pose<T>, b: &Pose<T>| {
            (a.gamma_deg - b.gamma_deg).abs() + (a.alpha_deg - b.alpha_deg).abs()
        };
        let mut best: Option<(T, Pose<T>)> = None;
        for sol in sols {
            // Whole turns as integers: an array of f64 read in the loop
            // would be converted by software f64 on an 8-bit board.
            for turn in [-360, 0, 360] {
                let start = Pose {
                    gamma_deg: sol.gamma_deg + T::from_i32(turn),
                    alpha_deg: sol.alpha_deg,
                };
                if !limits.contains(&start) {
                    continue;
                }
                let mut prev = start;
                let mut travel = from.map_or(T::ZERO, |f| dist(f, &start));
                path(&mut |sp| {
                    let s = sun_vector_xyz(sp.elevation_deg(), sp.azimuth_deg);
                    if let Ok(c) = self.attitude.choose(&s, &prev, &limits) {
                        let p = c.pose();
                        travel += dist(&p, &prev);
                        prev = p;
                    }
                });
                if best.is_none_or(|(t, _)| travel < t) {
                    best = Some((travel, start));
                }
            }
        }
        best.map(|(_, p)| p)
    }

    /// Before the first day: where to wait for sunrise. The sun is sampled
    /// every 30 minutes over the 24 hours from `sunrise`, and the pose facing
    /// sunrise on the branch that serves that day with least travel is taken.
    /// The answer is kept for that sunrise, a failed search too (no pose
    /// facing it within the limits): the search costs 48 sun positions,
    /// some 135 ms on an ATmega2560, and the night has a tick a second.
    pub(super) fn pre_position(&mut self, sunrise: UtcTime) -> Option<Pose<T>> {
        if let Some((t, p)) = self.night_pose {
            if t == sunrise {
                return p;
            }
        }
        let pose = self.search_pre_position(sunrise);
        self.night_pose = Some((sunrise, pose));
        pose
    }

    fn search_pre_position(&mut self, sunrise: UtcTime) -> Option<Pose<T>> {
        let first = self
            .scheduler
            .source_mut()
            .position(&sunrise)
            .ok()
            .map(|p| SetPoint::facing(&p))?;
        let (samples, n) = self.sample_day(sunrise, first);
        self.best_start(&first, None, &|visit| {
            samples.iter().take(n).for_each(|&sp| visit(sp))
        })
    }

    /// Half-hourly samples of the sun over the 24 hours from `from`, the
    /// daylight ones, after `first` (the set-point at `from`): the path a
    /// day's branch is judged on when no table holds it.
    fn sample_day(&mut self, from: UtcTime, first: SetPoint<T>) -> ([SetPoint<T>; 48], usize) {
        let mut samples = [first; 48];
        let mut n = 1;
        for k in 1..48i32 {
            let Ok(t) = from.add_seconds_i32(k * 1800) else {
                break;
            };
            let Ok(p) = self.scheduler.source_mut().position(&t) else {
                continue;
            };
            if p.is_above_horizon() {
                if let Some(slot) = samples.get_mut(n) {
                    *slot = SetPoint::facing(&p);
                    n += 1;
                }
            }
        }
        (samples, n)
    }
}
