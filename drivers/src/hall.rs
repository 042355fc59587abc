//! Hall pulse counting for a DC motor shaft (or an actuator's built-in
//! Hall sensor), with a stall and unexpected-motion watch. Pure logic: the
//! board feeds it edges (from a pin-change interrupt or by polling) and the
//! commanded duty, with a monotonic `now_ms: u32` (differences wrap with
//! the counter, every 49.7 days).
//!
//! * [`SingleHall`]: one channel. A pulse carries no direction, so it is
//!   counted by the commanded one: +1 while the duty is positive, −1 while
//!   negative, and in the last driven direction while the motor runs down
//!   (a coasting rotor keeps its direction). Actuators with a single Hall
//!   output (e.g. LINAK LA35 "relative positioning", 8 pulses per spindle
//!   turn, LA35 user manual "I/O specifications") are counted this way.
//! * [`QuadratureHall`]: two channels 90° apart (dual Hall, e.g. the LINAK
//!   LA36 "Dual Hall" option, LA36 user manual "Actuator with relative
//!   positioning – Dual Hall"), decoded ×4 by [`crate::encoder`]'s
//!   [`QuadratureDecoder`]: direction comes from the sensor itself.
//!
//! Positions are `i32` pulses and saturate at the ends of the range instead
//! of wrapping.
//!
//! The watch ([`StallWatch`]) reports [`Watch::Stall`] when the motor is
//! driven (|duty| above `drive_threshold_permille`) and no pulse has come
//! for `stall_ms` (counted from the last pulse or from the start of the
//! drive, whichever is later), and [`Watch::UnexpectedMotion`] when more than
//! `max_idle_pulses` pulses arrive while it is not driven (a back-driven
//! axis, a wind load on a non-self-locking gear, a stuck bridge).

use crate::encoder::{QuadratureDecoder, Transition};

/// Invalid watch configuration.
///
/// ```
/// use drivers::hall::{HallConfig, HallError, SingleHall};
///
/// let bad = HallConfig { stall_ms: 0, drive_threshold_permille: 100, max_idle_pulses: 3 };
/// assert_eq!(SingleHall::new(bad).err(), Some(HallError::InvalidConfig));
/// assert_eq!(HallError::InvalidConfig.to_string(), "unusable Hall watch configuration");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HallError {
    /// `stall_ms` is 0 or `drive_threshold_permille` is 1000 or more (the
    /// motor could never count as driven).
    InvalidConfig,
}

impl core::fmt::Display for HallError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            HallError::InvalidConfig => f.write_str("unusable Hall watch configuration"),
        }
    }
}

impl core::error::Error for HallError {}

/// Stall and unexpected-motion limits.
///
/// ```
/// use drivers::hall::HallConfig;
///
/// // An actuator giving a pulse every 0.38 mm at about 5 mm/s pulses every
/// // 76 ms; 500 ms without a pulse while driven above 15 % is a stall, more
/// // than 4 pulses (1.5 mm) while idle is unexpected motion.
/// let config = HallConfig { stall_ms: 500, drive_threshold_permille: 150, max_idle_pulses: 4 };
/// assert!(config.is_valid());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HallConfig {
    /// Longest time without a pulse while driven, ms (> 0).
    pub stall_ms: u32,
    /// The motor counts as driven when |duty| is above this, ‰ (< 1000):
    /// below it a geared motor may not turn at all.
    pub drive_threshold_permille: u16,
    /// Pulses tolerated while not driven (run-down after a stop).
    pub max_idle_pulses: u32,
}

impl HallConfig {
    /// True when `stall_ms` > 0 and `drive_threshold_permille` < 1000.
    ///
    /// ```
    /// use drivers::hall::HallConfig;
    ///
    /// let c = HallConfig { stall_ms: 300, drive_threshold_permille: 999, max_idle_pulses: 0 };
    /// assert!(c.is_valid());
    /// assert!(!HallConfig { drive_threshold_permille: 1_000, ..c }.is_valid());
    /// ```
    pub fn is_valid(&self) -> bool {
        self.stall_ms > 0 && self.drive_threshold_permille < 1_000
    }
}

/// What the watch sees.
///
/// ```
/// use drivers::hall::Watch;
///
/// let alarm = |w: Watch| w != Watch::Normal;
/// assert!(alarm(Watch::Stall) && !alarm(Watch::Normal));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Watch {
    /// Nothing wrong.
    Normal,
    /// Driven, but no pulse for `stall_ms`.
    Stall,
    /// More than `max_idle_pulses` pulses while not driven.
    UnexpectedMotion,
}

/// The timing half of the counters: commanded duty in, pulses in, [`Watch`]
/// out. Usable on its own with any position sensor that gives pulses.
///
/// ```
/// use drivers::hall::{HallConfig, StallWatch, Watch};
///
/// let config = HallConfig { stall_ms: 200, drive_threshold_permille: 100, max_idle_pulses: 2 };
/// let mut w = StallWatch::new(config)?;
/// w.set_drive(500, 1_000); // driven from t = 1000 ms
/// assert_eq!(w.check(1_199), Watch::Normal);
/// assert_eq!(w.check(1_200), Watch::Stall); // 200 ms without a pulse
/// w.pulse(1_250);
/// assert_eq!(w.check(1_300), Watch::Normal);
/// # Ok::<(), drivers::hall::HallError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StallWatch {
    config: HallConfig,
    drive_permille: i16,
    since_ms: u32,
    idle_pulses: u32,
}

impl StallWatch {
    /// Not driven, no pulses seen.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, StallWatch, Watch};
    ///
    /// let config = HallConfig { stall_ms: 200, drive_threshold_permille: 100, max_idle_pulses: 2 };
    /// let w = StallWatch::new(config)?;
    /// assert_eq!(w.check(u32::MAX), Watch::Normal); // not driven: never a stall
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn new(config: HallConfig) -> Result<Self, HallError> {
        if !config.is_valid() {
            return Err(HallError::InvalidConfig);
        }
        Ok(Self {
            config,
            drive_permille: 0,
            since_ms: 0,
            idle_pulses: 0,
        })
    }

    /// Back to the state of [`StallWatch::new`] (not driven, no pulses
    /// seen), the configuration kept.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, StallWatch, Watch};
    ///
    /// let config = HallConfig { stall_ms: 100, drive_threshold_permille: 200, max_idle_pulses: 0 };
    /// let new = StallWatch::new(config)?;
    /// let mut w = new;
    /// w.set_drive(500, 0);
    /// assert_eq!(w.check(100), Watch::Stall);
    /// w.reset();
    /// assert_eq!(w, new);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn reset(&mut self) {
        self.drive_permille = 0;
        self.since_ms = 0;
        self.idle_pulses = 0;
    }

    /// The duty now commanded, ‰ (positive = forward). The stall timer
    /// restarts when the motor becomes driven or reverses; the idle pulse
    /// count restarts when it stops being driven.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, StallWatch, Watch};
    ///
    /// let config = HallConfig { stall_ms: 100, drive_threshold_permille: 200, max_idle_pulses: 0 };
    /// let mut w = StallWatch::new(config)?;
    /// w.set_drive(200, 0); // not above the threshold: not driven
    /// assert_eq!(w.check(500), Watch::Normal);
    /// w.set_drive(-201, 500);
    /// assert_eq!(w.check(600), Watch::Stall);
    /// w.set_drive(300, 600); // reversed: the timer restarts
    /// assert_eq!(w.check(650), Watch::Normal);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn set_drive(&mut self, duty_permille: i16, now_ms: u32) {
        let was = self.driven_sign();
        self.drive_permille = duty_permille;
        let is = self.driven_sign();
        if is != was {
            if is == 0 {
                self.idle_pulses = 0;
            } else {
                self.since_ms = now_ms;
            }
        }
    }

    /// One pulse at `now_ms`.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, StallWatch, Watch};
    ///
    /// let config = HallConfig { stall_ms: 100, drive_threshold_permille: 50, max_idle_pulses: 2 };
    /// let mut w = StallWatch::new(config)?;
    /// for t in [10, 20] {
    ///     w.pulse(t); // run-down pulses while idle: tolerated
    /// }
    /// assert_eq!(w.check(30), Watch::Normal);
    /// w.pulse(40); // a third one
    /// assert_eq!(w.check(50), Watch::UnexpectedMotion);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn pulse(&mut self, now_ms: u32) {
        if self.driven_sign() == 0 {
            self.idle_pulses = self.idle_pulses.saturating_add(1);
        } else {
            self.since_ms = now_ms;
        }
    }

    /// The state at `now_ms`.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, StallWatch, Watch};
    ///
    /// // The millisecond counter wraps between the start and the check:
    /// // u32::MAX − 49 → 50 is 100 ms.
    /// let config = HallConfig { stall_ms: 100, drive_threshold_permille: 0, max_idle_pulses: 0 };
    /// let mut w = StallWatch::new(config)?;
    /// w.set_drive(1, u32::MAX - 49);
    /// assert_eq!(w.check(49), Watch::Normal);
    /// assert_eq!(w.check(50), Watch::Stall);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn check(&self, now_ms: u32) -> Watch {
        if self.driven_sign() != 0 {
            if now_ms.wrapping_sub(self.since_ms) >= self.config.stall_ms {
                return Watch::Stall;
            }
        } else if self.idle_pulses > self.config.max_idle_pulses {
            return Watch::UnexpectedMotion;
        }
        Watch::Normal
    }

    /// The duty last given to [`StallWatch::set_drive`], ‰.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, StallWatch};
    ///
    /// let config = HallConfig { stall_ms: 100, drive_threshold_permille: 50, max_idle_pulses: 2 };
    /// let mut w = StallWatch::new(config)?;
    /// w.set_drive(-700, 0);
    /// assert_eq!(w.drive_permille(), -700);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn drive_permille(&self) -> i16 {
        self.drive_permille
    }

    /// +1 / −1 when driven forward / backward above the threshold, else 0.
    fn driven_sign(&self) -> i8 {
        if self.drive_permille.unsigned_abs() > self.config.drive_threshold_permille {
            if self.drive_permille > 0 {
                1
            } else {
                -1
            }
        } else {
            0
        }
    }
}

/// One Hall channel, counted by the commanded direction.
///
/// ```
/// use drivers::hall::{HallConfig, SingleHall, Watch};
///
/// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 3 };
/// let mut hall = SingleHall::new(config)?;
/// hall.set_drive(-600, 0); // retracting
/// for t in [40, 80, 120] {
///     hall.pulse(t);
/// }
/// assert_eq!(hall.position(), -3);
/// hall.set_drive(0, 130); // stopped; it runs down one more pulse, still backward
/// hall.pulse(150);
/// assert_eq!((hall.position(), hall.check(200)), (-4, Watch::Normal));
/// # Ok::<(), drivers::hall::HallError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SingleHall {
    watch: StallWatch,
    position: i32,
    forward: bool,
}

impl SingleHall {
    /// Position 0, not driven; pulses before any drive count forward.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, SingleHall};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 3 };
    /// let mut hall = SingleHall::new(config)?;
    /// hall.pulse(5);
    /// assert_eq!(hall.position(), 1);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn new(config: HallConfig) -> Result<Self, HallError> {
        Ok(Self {
            watch: StallWatch::new(config)?,
            position: 0,
            forward: true,
        })
    }

    /// The commanded duty, ‰ (see [`StallWatch::set_drive`]); a non-zero
    /// duty also sets the counting direction.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, SingleHall};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 3 };
    /// let mut hall = SingleHall::new(config)?;
    /// hall.set_drive(-50, 0); // below the threshold, but still backward
    /// hall.pulse(10);
    /// assert_eq!(hall.position(), -1);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn set_drive(&mut self, duty_permille: i16, now_ms: u32) {
        if duty_permille != 0 {
            self.forward = duty_permille > 0;
        }
        self.watch.set_drive(duty_permille, now_ms);
    }

    /// One pulse (call on one edge of the channel); returns the position.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, SingleHall};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 3 };
    /// let mut hall = SingleHall::new(config)?;
    /// hall.set_position(i32::MAX);
    /// hall.set_drive(1_000, 0);
    /// assert_eq!(hall.pulse(1), i32::MAX); // saturates
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn pulse(&mut self, now_ms: u32) -> i32 {
        self.position = if self.forward {
            self.position.saturating_add(1)
        } else {
            self.position.saturating_sub(1)
        };
        self.watch.pulse(now_ms);
        self.position
    }

    /// Position, pulses.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, SingleHall};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 3 };
    /// assert_eq!(SingleHall::new(config)?.position(), 0);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn position(&self) -> i32 {
        self.position
    }

    /// Redefines the position (after homing against an end stop).
    ///
    /// ```
    /// use drivers::hall::{HallConfig, SingleHall};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 3 };
    /// let mut hall = SingleHall::new(config)?;
    /// hall.set_position(-42);
    /// assert_eq!(hall.position(), -42);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn set_position(&mut self, position: i32) {
        self.position = position;
    }

    /// The watch state at `now_ms` (see [`StallWatch::check`]).
    ///
    /// ```
    /// use drivers::hall::{HallConfig, SingleHall, Watch};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 3 };
    /// let mut hall = SingleHall::new(config)?;
    /// hall.set_drive(400, 1_000);
    /// assert_eq!(hall.check(1_300), Watch::Stall);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn check(&self, now_ms: u32) -> Watch {
        self.watch.check(now_ms)
    }
}

/// Two Hall channels in quadrature, decoded ×4.
///
/// ```
/// use drivers::hall::{HallConfig, QuadratureHall};
/// use drivers::encoder::Transition;
///
/// // A leads B: 00 → 10 → 11 → 01 → 00 is four counts forward.
/// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 8 };
/// let mut hall = QuadratureHall::new(false, false, config)?;
/// hall.set_drive(500, 0);
/// for (t, (a, b)) in [(true, false), (true, true), (false, true), (false, false)].into_iter().enumerate() {
///     assert_eq!(hall.update(a, b, t as u32), Transition::Forward);
/// }
/// assert_eq!(hall.position(), 4);
/// # Ok::<(), drivers::hall::HallError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct QuadratureHall {
    watch: StallWatch,
    decoder: QuadratureDecoder,
    position: i32,
}

impl QuadratureHall {
    /// Starts from the current levels of A and B, position 0.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, QuadratureHall};
    /// use drivers::encoder::Transition;
    ///
    /// // From 11, 11 → 10 is backward.
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 8 };
    /// let mut hall = QuadratureHall::new(true, true, config)?;
    /// assert_eq!(hall.update(true, false, 0), Transition::Backward);
    /// assert_eq!(hall.position(), -1);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn new(a: bool, b: bool, config: HallConfig) -> Result<Self, HallError> {
        Ok(Self {
            watch: StallWatch::new(config)?,
            decoder: QuadratureDecoder::new(a, b),
            position: 0,
        })
    }

    /// The commanded duty, ‰ (for the watch only: the direction comes from
    /// the channels).
    ///
    /// ```
    /// use drivers::hall::{HallConfig, QuadratureHall, Watch};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 8 };
    /// let mut hall = QuadratureHall::new(false, false, config)?;
    /// hall.set_drive(-800, 0);
    /// assert_eq!(hall.check(300), Watch::Stall);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn set_drive(&mut self, duty_permille: i16, now_ms: u32) {
        self.watch.set_drive(duty_permille, now_ms);
    }

    /// Feeds one sample of both channels at `now_ms`; every counted edge is
    /// a pulse for the watch. Illegal transitions (both channels changed:
    /// an edge was missed) do not move the position and are counted in
    /// [`QuadratureHall::errors`].
    ///
    /// ```
    /// use drivers::hall::{HallConfig, QuadratureHall};
    /// use drivers::encoder::Transition;
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 8 };
    /// let mut hall = QuadratureHall::new(false, false, config)?;
    /// assert_eq!(hall.update(true, true, 0), Transition::Illegal);
    /// assert_eq!((hall.position(), hall.errors()), (0, 1));
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn update(&mut self, a: bool, b: bool, now_ms: u32) -> Transition {
        let t = self.decoder.update(a, b);
        match t {
            Transition::Forward => {
                self.position = self.position.saturating_add(1);
                self.watch.pulse(now_ms);
            }
            Transition::Backward => {
                self.position = self.position.saturating_sub(1);
                self.watch.pulse(now_ms);
            }
            Transition::None | Transition::Illegal => {}
        }
        t
    }

    /// Position, counts (four per Hall cycle).
    ///
    /// ```
    /// use drivers::hall::{HallConfig, QuadratureHall};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 8 };
    /// assert_eq!(QuadratureHall::new(false, true, config)?.position(), 0);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn position(&self) -> i32 {
        self.position
    }

    /// Redefines the position (after homing).
    ///
    /// ```
    /// use drivers::hall::{HallConfig, QuadratureHall};
    /// use drivers::encoder::Transition;
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 8 };
    /// let mut hall = QuadratureHall::new(false, false, config)?;
    /// hall.set_position(i32::MIN);
    /// hall.update(false, true, 0); // 00 → 01: backward, saturated
    /// assert_eq!(hall.position(), i32::MIN);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn set_position(&mut self, position: i32) {
        self.position = position;
    }

    /// Illegal transitions so far.
    ///
    /// ```
    /// use drivers::hall::{HallConfig, QuadratureHall};
    ///
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 8 };
    /// assert_eq!(QuadratureHall::new(false, false, config)?.errors(), 0);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn errors(&self) -> u32 {
        self.decoder.errors()
    }

    /// The watch state at `now_ms` (see [`StallWatch::check`]).
    ///
    /// ```
    /// use drivers::hall::{HallConfig, QuadratureHall, Watch};
    ///
    /// // Not driven: the 9th edge is one more than tolerated.
    /// let config = HallConfig { stall_ms: 300, drive_threshold_permille: 100, max_idle_pulses: 8 };
    /// let mut hall = QuadratureHall::new(false, false, config)?;
    /// let cycle = [(true, false), (true, true), (false, true), (false, false)];
    /// for (a, b) in cycle.into_iter().chain(cycle) {
    ///     hall.update(a, b, 0);
    /// }
    /// assert_eq!(hall.check(1), Watch::Normal);
    /// hall.update(true, false, 2);
    /// assert_eq!(hall.check(3), Watch::UnexpectedMotion);
    /// # Ok::<(), drivers::hall::HallError>(())
    /// ```
    pub fn check(&self, now_ms: u32) -> Watch {
        self.watch.check(now_ms)
    }
}
