//! Safety: typed faults with their recovery, wind stow, and the choice of
//! what the tracker does (track, stow, manual, stop).
//!
//! Fault handling follows what commercial tracker controllers do: retry a
//! transient failure a few times, then degrade (track open loop on counted
//! steps, or keep tracking on one axis), and stop safely only when neither
//! keeps the structure safe. Nothing here panics.

use crate::config::{SafetyConfig, WindConfig};
use sun_algos::UtcTime;

/// The two axes: C (vertical at home, azimuth-like) and A (tilt).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum AxisId {
    /// C axis, rotation γ.
    C,
    /// A axis, rotation α.
    A,
}

impl AxisId {
    /// Index 0 for C, 1 for A.
    pub fn index(self) -> usize {
        match self {
            AxisId::C => 0,
            AxisId::A => 1,
        }
    }
}

/// A sensor of the tracker.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sensor {
    /// Two-axis inclinometer.
    Inclinometer,
    /// Magnetometer (compass).
    Compass,
    /// Encoder of an axis.
    Encoder(AxisId),
    /// Real-time clock.
    Rtc,
    /// GPS receiver.
    Gps,
}

/// A fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Fault {
    /// No reading from the sensor within the timeout.
    SensorTimeout(Sensor),
    /// The sensor's bus (I2C) returned an error.
    I2cError(Sensor),
    /// The GPS lost its fix.
    GpsLost,
    /// The RTC lost power or holds an impossible time.
    RtcInvalid,
    /// The axis was driven but its encoder showed no motion.
    MotorStalled(AxisId),
    /// Feedback and set-point differ by more than the maximum.
    SetPointDeviation(AxisId),
    /// A limit switch closed where none was expected.
    LimitSwitchHit(AxisId),
}

/// What to do about a fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Recovery {
    /// Try the operation again next cycle.
    Retry,
    /// Stop using feedback: track open loop on counted steps.
    DegradeOpenLoop,
    /// Stop this axis where it is and track with the other.
    DegradeOneAxis(AxisId),
    /// Lost position reference: home the axis against its limit switch.
    Rehome(AxisId),
    /// Carry on with the RTC and the stored site until GPS returns.
    UseRtcAndStoredSite,
    /// Do not track (the time is unknown) until GPS sets the clock.
    WaitForGps,
    /// Stop both axes; only a person clears it.
    StopSafely,
}

impl Fault {
    /// The recovery for the `attempt`-th occurrence (1 = first) while the
    /// fault is active, with at most `max_retries` retries.
    pub fn recovery(self, attempt: u32, max_retries: u8) -> Recovery {
        let retries = u32::from(max_retries);
        match self {
            Fault::SensorTimeout(Sensor::Gps) | Fault::I2cError(Sensor::Gps) | Fault::GpsLost => {
                Recovery::UseRtcAndStoredSite
            }
            Fault::SensorTimeout(Sensor::Rtc)
            | Fault::I2cError(Sensor::Rtc)
            | Fault::RtcInvalid => Recovery::WaitForGps,
            Fault::SensorTimeout(_) | Fault::I2cError(_) => {
                if attempt <= retries {
                    Recovery::Retry
                } else {
                    Recovery::DegradeOpenLoop
                }
            }
            Fault::MotorStalled(ax) => {
                if attempt <= retries {
                    Recovery::Retry
                } else {
                    Recovery::DegradeOneAxis(ax)
                }
            }
            Fault::SetPointDeviation(ax) => {
                if attempt <= retries {
                    Recovery::Rehome(ax)
                } else {
                    Recovery::DegradeOneAxis(ax)
                }
            }
            Fault::LimitSwitchHit(ax) => {
                if attempt <= retries {
                    Recovery::Rehome(ax)
                } else {
                    Recovery::StopSafely
                }
            }
        }
    }
}

/// Capacity of the active-fault list.
pub const MAX_ACTIVE: usize = 8;

/// An active fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ActiveFault {
    /// The fault.
    pub fault: Fault,
    /// When first raised.
    pub since: UtcTime,
    /// Occurrences while active.
    pub attempts: u32,
    /// The recovery chosen last.
    pub recovery: Recovery,
}

/// Keeps the active faults and counts raised and recovered ones.
#[derive(Debug, Clone)]
pub struct FaultManager {
    active: [Option<ActiveFault>; MAX_ACTIVE],
    config: SafetyConfig,
    /// Faults raised (first occurrences).
    pub raised: u32,
    /// Faults that cleared.
    pub recovered: u32,
    /// Faults that could not be recorded (list full); still acted upon.
    pub dropped: u32,
}

impl FaultManager {
    /// No active faults.
    pub fn new(config: SafetyConfig) -> Self {
        FaultManager {
            active: [None; MAX_ACTIVE],
            config,
            raised: 0,
            recovered: 0,
            dropped: 0,
        }
    }

    /// Reports a fault (again); returns the recovery to apply.
    pub fn raise(&mut self, fault: Fault, now: UtcTime) -> Recovery {
        if let Some(a) = self.active.iter_mut().flatten().find(|a| a.fault == fault) {
            a.attempts = a.attempts.saturating_add(1);
            a.recovery = fault.recovery(a.attempts, self.config.max_retries);
            return a.recovery;
        }
        self.raised = self.raised.saturating_add(1);
        let recovery = fault.recovery(1, self.config.max_retries);
        match self.active.iter_mut().find(|s| s.is_none()) {
            Some(slot) => {
                *slot = Some(ActiveFault {
                    fault,
                    since: now,
                    attempts: 1,
                    recovery,
                });
            }
            None => self.dropped = self.dropped.saturating_add(1),
        }
        recovery
    }

    /// The fault's condition is gone; returns true when it was active.
    pub fn clear(&mut self, fault: Fault) -> bool {
        for slot in self.active.iter_mut() {
            if slot.is_some_and(|a| a.fault == fault) {
                *slot = None;
                self.recovered = self.recovered.saturating_add(1);
                return true;
            }
        }
        false
    }

    /// True when `fault` is active.
    pub fn is_active(&self, fault: Fault) -> bool {
        self.active.iter().flatten().any(|a| a.fault == fault)
    }

    /// The active faults.
    pub fn active(&self) -> impl Iterator<Item = &ActiveFault> {
        self.active.iter().flatten()
    }

    /// Number of active faults.
    pub fn active_count(&self) -> usize {
        self.active().count()
    }

    /// True when any active fault asks to stop.
    pub fn must_stop(&self) -> bool {
        self.active().any(|a| a.recovery == Recovery::StopSafely)
    }

    /// True when tracking must run open loop.
    pub fn open_loop(&self) -> bool {
        self.active()
            .any(|a| a.recovery == Recovery::DegradeOpenLoop)
    }

    /// True when `axis` is stopped by a degradation.
    pub fn axis_disabled(&self, axis: AxisId) -> bool {
        self.active()
            .any(|a| a.recovery == Recovery::DegradeOneAxis(axis))
    }

    /// True when the time is not trusted.
    pub fn time_unknown(&self) -> bool {
        self.active().any(|a| a.recovery == Recovery::WaitForGps)
    }

    /// Clears every fault (an operator's reset after a safe stop).
    pub fn reset(&mut self) {
        for slot in self.active.iter_mut() {
            if slot.take().is_some() {
                self.recovered = self.recovered.saturating_add(1);
            }
        }
    }
}

/// Wind stow from an anemometer's pulse rate: stow after the rate stayed
/// above the threshold for `hold_s`; leave stow after it stayed below for
/// `release_s`.
#[derive(Debug, Clone, Copy)]
pub struct WindMonitor {
    config: WindConfig,
    above_since: Option<UtcTime>,
    calm_since: Option<UtcTime>,
    stowed: bool,
    /// Number of stows so far.
    pub stow_count: u32,
}

impl WindMonitor {
    /// Calm, not stowed.
    pub fn new(config: WindConfig) -> Self {
        WindMonitor {
            config,
            above_since: None,
            calm_since: None,
            stowed: false,
            stow_count: 0,
        }
    }

    /// Feeds `pulses` counted over `interval_s` seconds ending at `now`;
    /// returns true while stowed. A zero interval keeps the state.
    pub fn update_pulses(&mut self, now: UtcTime, pulses: u32, interval_s: f32) -> bool {
        if !(interval_s.is_finite() && interval_s > 0.0) {
            return self.stowed;
        }
        self.update_rate(now, pulses as f32 / interval_s)
    }

    /// Feeds a pulse rate in Hz; returns true while stowed. A rate that is
    /// not a number counts as windy (fail safe).
    pub fn update_rate(&mut self, now: UtcTime, rate_hz: f32) -> bool {
        let windy = rate_hz.is_nan() || rate_hz > self.config.threshold_hz;
        let elapsed = |since: UtcTime| now.unix_seconds().saturating_sub(since.unix_seconds());
        if windy {
            self.calm_since = None;
            let since = *self.above_since.get_or_insert(now);
            if !self.stowed && elapsed(since) >= i64::from(self.config.hold_s) {
                self.stowed = true;
                self.stow_count = self.stow_count.saturating_add(1);
            }
        } else {
            self.above_since = None;
            let since = *self.calm_since.get_or_insert(now);
            if self.stowed && elapsed(since) >= i64::from(self.config.release_s) {
                self.stowed = false;
            }
        }
        self.stowed
    }

    /// True while stowed.
    pub fn is_stowed(&self) -> bool {
        self.stowed
    }
}

/// What the tracker is doing, highest priority first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// A fault asked to stop: nothing moves.
    SafeStop,
    /// Stowed for wind.
    WindStow,
    /// Stowed on an operator's command.
    CommandStow,
    /// An operator drives the axes.
    Manual,
    /// The time is unknown (RTC invalid, no GPS): stowed, waiting.
    WaitForTime,
    /// Outside daylight: stowed or parked at home.
    Night,
    /// Following the sun.
    Tracking,
}

/// Inputs of [`select_mode`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ModeInputs {
    /// A fault requires a safe stop.
    pub must_stop: bool,
    /// The wind monitor is stowed.
    pub wind_stow: bool,
    /// An operator commanded stow.
    pub command_stow: bool,
    /// An operator took manual control.
    pub manual: bool,
    /// The time is not trusted.
    pub time_unknown: bool,
    /// The scheduler is outside daylight.
    pub night: bool,
}

/// The mode for the inputs. Protection of the structure first (fault stop,
/// wind), then the operator, then the clock, then the sun.
pub fn select_mode(i: &ModeInputs) -> Mode {
    if i.must_stop {
        Mode::SafeStop
    } else if i.wind_stow {
        Mode::WindStow
    } else if i.command_stow {
        Mode::CommandStow
    } else if i.manual {
        Mode::Manual
    } else if i.time_unknown {
        Mode::WaitForTime
    } else if i.night {
        Mode::Night
    } else {
        Mode::Tracking
    }
}
