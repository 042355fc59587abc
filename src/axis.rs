//! One axis of the tracker: targets in degrees over a motor that counts in
//! steps (stepper) or encoder counts (servo).
//!
//! [`AxisDrive`] is the hardware side (a stepper or servo driver, or a
//! simulated plant); [`AxisController`] adds what every axis needs: the
//! counts-per-degree scale from the configuration (steps × microsteps ×
//! gear ratio / 360°), homing against the limit switch, soft limits,
//! backlash compensation, and three [`FeedbackMode`]s:
//!
//! - open loop: counted steps only;
//! - pseudo-closed loop (seed jimoh-2019 §2.1): set-points applied open loop,
//!   the feedback only observed and its deviation reported;
//! - closed loop: correct toward the set-point from feedback until inside the
//!   deadband.

use crate::config::AxisConfig;

/// The motor side of an axis.
pub trait AxisDrive {
    /// Bus or driver error.
    type Error;
    /// Starts a relative move of `counts` motor counts (signed). Moves are
    /// queued; [`AxisDrive::pending`] tells how many are not done yet.
    fn move_counts(&mut self, counts: i32) -> Result<(), Self::Error>;
    /// Counts still to run of the moves started.
    fn pending(&self) -> i32;
    /// Stops at once, dropping pending counts.
    fn stop(&mut self) -> Result<(), Self::Error>;
    /// True while the homing limit switch is closed.
    fn at_limit(&mut self) -> Result<bool, Self::Error>;
    /// The axis angle from an output-side encoder, degrees, when fitted.
    fn encoder_deg(&mut self) -> Result<Option<f32>, Self::Error>;
}

/// How the axis uses feedback.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeedbackMode {
    /// Counted steps only.
    OpenLoop,
    /// Counted steps; feedback observed and reported, never acted upon.
    PseudoClosed,
    /// Correct from feedback until inside the deadband.
    ClosedLoop,
}

/// Errors of an axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxisError<E> {
    /// The drive failed.
    Drive(E),
    /// The axis has not been homed.
    NotHomed,
    /// A target or feedback value was NaN or infinite.
    NotFinite,
    /// Homing ran its whole travel without closing the switch.
    HomeNotFound,
}

/// State of a homing run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HomeState {
    /// Not homed.
    Idle,
    /// The switch was closed at the start: moving off it first.
    BackingOff,
    /// Driving toward the switch.
    Seeking,
    /// Homed: the counted position is the switch angle.
    Done,
}

/// What one [`AxisController::update`] did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisReport {
    /// The target after soft limits.
    pub target_deg: f32,
    /// True when the target was clamped to a soft limit.
    pub clamped: bool,
    /// Counts commanded in this update (including backlash take-up).
    pub commanded_counts: i32,
    /// Feedback minus target, when feedback was available.
    pub deviation_deg: Option<f32>,
}

/// An axis under control.
#[derive(Debug)]
pub struct AxisController<D> {
    drive: D,
    config: AxisConfig,
    counts_per_deg: f32,
    /// Position in counts relative to the home switch, as commanded.
    position_counts: i64,
    /// Direction of the last move: +1, −1 or 0 (unknown).
    last_dir: i8,
    home: HomeState,
    seek_counts: i64,
    /// Second, slow approach of homing.
    fine: bool,
    /// Total counts commanded (motor travel).
    pub travel_counts: u64,
}

impl<D: AxisDrive> AxisController<D> {
    /// An axis over `drive`; not homed yet.
    pub fn new(drive: D, config: AxisConfig) -> Self {
        let cpd = config.counts_per_deg();
        AxisController {
            drive,
            config,
            counts_per_deg: if cpd.is_finite() && cpd > 0.0 {
                cpd
            } else {
                1.0
            },
            position_counts: 0,
            last_dir: 0,
            home: HomeState::Idle,
            seek_counts: 0,
            fine: false,
            travel_counts: 0,
        }
    }

    /// The drive.
    pub fn drive_mut(&mut self) -> &mut D {
        &mut self.drive
    }

    /// The drive, read-only.
    pub fn drive(&self) -> &D {
        &self.drive
    }

    /// The configuration.
    pub fn config(&self) -> &AxisConfig {
        &self.config
    }

    /// Homing state.
    pub fn home_state(&self) -> HomeState {
        self.home
    }

    /// Forgets the reference (after a fault): homing is needed again.
    pub fn unhome(&mut self) {
        self.home = HomeState::Idle;
    }

    /// The angle the step count says, degrees.
    pub fn counted_deg(&self) -> f32 {
        self.config.home_deg + self.position_counts as f32 / self.counts_per_deg
    }

    fn command(&mut self, counts: i64) -> Result<i32, AxisError<D::Error>> {
        let c = i32::try_from(counts.clamp(i64::from(i32::MIN), i64::from(i32::MAX))).unwrap_or(0);
        if c != 0 {
            self.drive.move_counts(c).map_err(AxisError::Drive)?;
            self.travel_counts = self
                .travel_counts
                .saturating_add(u64::from(c.unsigned_abs()));
        }
        Ok(c)
    }

    /// One step of homing: drive toward the switch (negative direction) in
    /// chunks of `chunk_deg`; when the switch closes, stop and take the
    /// switch angle as the position. Call until it returns `Done`.
    pub fn home_step(&mut self, chunk_deg: f32) -> Result<HomeState, AxisError<D::Error>> {
        if !chunk_deg.is_finite() || chunk_deg <= 0.0 {
            return Err(AxisError::NotFinite);
        }
        if self.home == HomeState::Done {
            return Ok(HomeState::Done);
        }
        let closed = self.drive.at_limit().map_err(AxisError::Drive)?;
        // Fast approach in `chunk_deg` steps, then back off and approach
        // again 50 times slower: the switch angle is known to chunk/50.
        let step_deg = if self.fine {
            chunk_deg / 50.0
        } else {
            chunk_deg
        };
        if self.home == HomeState::Idle {
            self.seek_counts = 0;
            self.fine = false;
            // Approach the switch from the open side: a switch already
            // closed (or stuck) is first backed away from.
            self.home = if closed {
                HomeState::BackingOff
            } else {
                HomeState::Seeking
            };
        }
        if self.home == HomeState::BackingOff {
            if !closed {
                self.drive.stop().map_err(AxisError::Drive)?;
                self.home = HomeState::Seeking;
                self.seek_counts = 0;
                return Ok(HomeState::Seeking);
            }
            if self.drive.pending() != 0 {
                return Ok(HomeState::BackingOff);
            }
            if self.seek_counts as f32 > 15.0 * self.counts_per_deg {
                self.home = HomeState::Idle;
                return Err(AxisError::HomeNotFound);
            }
            let chunk = ((step_deg * self.counts_per_deg) as i64).max(1);
            self.command(chunk)?;
            self.seek_counts += chunk;
            return Ok(HomeState::BackingOff);
        }
        if closed && !self.fine {
            self.drive.stop().map_err(AxisError::Drive)?;
            self.fine = true;
            self.seek_counts = 0;
            self.home = HomeState::BackingOff;
            return Ok(HomeState::BackingOff);
        }
        if closed {
            self.drive.stop().map_err(AxisError::Drive)?;
            self.position_counts = 0;
            // Arrived moving negative: the gear's slack is taken up that way.
            self.last_dir = -1;
            self.home = HomeState::Done;
            return Ok(HomeState::Done);
        }
        if self.drive.pending() != 0 {
            return Ok(HomeState::Seeking);
        }
        let range = (self.config.max_deg - self.config.min_deg) + 10.0;
        if (self.seek_counts as f32) > (range + self.config.backlash_deg) * self.counts_per_deg {
            self.home = HomeState::Idle;
            return Err(AxisError::HomeNotFound);
        }
        let chunk = -((step_deg * self.counts_per_deg) as i64).max(1);
        self.command(chunk)?;
        self.seek_counts += -chunk;
        Ok(HomeState::Seeking)
    }

    /// Moves toward `target_deg` (clamped to the soft limits) and, per
    /// `mode`, uses `feedback_deg` (the axis angle from an encoder or from
    /// attitude sensors).
    pub fn update(
        &mut self,
        target_deg: f32,
        mode: FeedbackMode,
        feedback_deg: Option<f32>,
    ) -> Result<AxisReport, AxisError<D::Error>> {
        if self.home != HomeState::Done {
            return Err(AxisError::NotHomed);
        }
        if !target_deg.is_finite() || feedback_deg.is_some_and(|f| !f.is_finite()) {
            return Err(AxisError::NotFinite);
        }
        let lo = self.config.min_deg;
        let hi = self.config.max_deg;
        // max/min, not clamp: no panic path for a misordered config.
        let t = target_deg.max(lo).min(hi);
        let clamped = t != target_deg;
        let deviation = feedback_deg.map(|f| f - t);
        let goal_counts = match (mode, feedback_deg) {
            (FeedbackMode::ClosedLoop, Some(fb)) => {
                let err = t - fb;
                if err.abs() <= self.config.deadband_deg {
                    // Inside the deadband: trust the counted position.
                    self.position_counts
                } else {
                    // Re-anchor the count on the measurement and correct; a
                    // move still under way is dropped first, or its counts
                    // would be commanded twice.
                    if self.drive.pending() != 0 {
                        self.drive.stop().map_err(AxisError::Drive)?;
                    }
                    let here = ((fb - self.config.home_deg) * self.counts_per_deg) as i64;
                    self.position_counts = here;
                    ((t - self.config.home_deg) * self.counts_per_deg) as i64
                }
            }
            _ => ((t - self.config.home_deg) * self.counts_per_deg) as i64,
        };
        let delta = goal_counts - self.position_counts;
        let mut commanded = 0;
        if delta != 0 {
            let dir: i8 = if delta > 0 { 1 } else { -1 };
            // Backlash compensation: on reversal, take up the slack first.
            let take_up = if self.last_dir != 0 && dir != self.last_dir {
                (self.config.backlash_deg * self.counts_per_deg) as i64 * i64::from(dir)
            } else {
                0
            };
            commanded = self.command(delta + take_up)?;
            self.position_counts = goal_counts;
            self.last_dir = dir;
        }
        Ok(AxisReport {
            target_deg: t,
            clamped,
            commanded_counts: commanded,
            deviation_deg: deviation,
        })
    }
}
