//! Fusing GGA and RMC into one [`GpsFix`] per receiver epoch, and ageing it.
//!
//! A receiver sends a burst of sentences per epoch (usually once a second),
//! all stamped with the same UTC time of day. Sentences are gathered while
//! the time of day stays the same; the epoch's fix is given out as soon as
//! both its GGA and RMC have arrived, or else when the next epoch begins (or
//! at [`FixFusion::flush`]).
//!
//! Rules:
//! - a position only when RMC status is `A`/`D` or GGA quality > 0
//!   (the GGA position is preferred, since it comes with the altitude);
//! - the date-time from RMC (date + time), even when it has no position;
//!   GGA carries no date and does not set it;
//! - the altitude only with a GGA quality > 0;
//! - `quality` is the GGA quality; with only an RMC, `Gps` if its status is
//!   valid and `Invalid` if not;
//! - a sentence with impossible values (see `parse_sentence`) is ignored, also
//!   when it is built by hand and given to [`FixFusion::update`];
//! - after `stale_after_ms` of the caller's monotonic clock without any
//!   GGA/RMC, [`FixFusion::current`] reports no fix and no time.

use super::parse::{sentence_is_plausible, FixQuality, Gga, Rmc, Sentence, TimeOfDayMs};
use crate::time::DateTime;

/// The fused result of one epoch.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GpsFix {
    /// UTC date-time from RMC.
    pub utc: Option<DateTime>,
    /// Latitude, degrees north positive (only with a valid fix).
    pub latitude_deg: Option<f64>,
    /// Longitude, degrees east positive (only with a valid fix).
    pub longitude_deg: Option<f64>,
    /// Altitude above mean sea level, metres (only with GGA quality > 0).
    pub altitude_m: Option<f32>,
    /// Fix quality.
    pub quality: FixQuality,
    /// Satellites used (GGA).
    pub satellites: Option<u8>,
}

impl GpsFix {
    /// No time, no position.
    pub const NONE: GpsFix = GpsFix {
        utc: None,
        latitude_deg: None,
        longitude_deg: None,
        altitude_m: None,
        quality: FixQuality::Invalid,
        satellites: None,
    };

    /// Whether latitude and longitude are known.
    pub fn has_position(&self) -> bool {
        self.latitude_deg.is_some() && self.longitude_deg.is_some()
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct Epoch {
    key: Option<TimeOfDayMs>,
    gga: Option<Gga>,
    rmc: Option<Rmc>,
    emitted: bool,
    last_ms: u64,
}

impl Epoch {
    fn fix(&self) -> GpsFix {
        let mut fix = GpsFix {
            utc: self.rmc.and_then(|r| r.utc),
            ..GpsFix::NONE
        };
        let rmc_valid = self.rmc.is_some_and(|r| r.valid);
        match self.gga {
            Some(g) => {
                fix.quality = g.quality;
                fix.satellites = g.satellites;
            }
            None if rmc_valid => fix.quality = FixQuality::Gps,
            None => {}
        }
        let gga_position = self
            .gga
            .filter(|g| g.quality != FixQuality::Invalid)
            .and_then(|g| Some((g.latitude_deg?, g.longitude_deg?, g.altitude_m)));
        let rmc_position = self
            .rmc
            .filter(|r| r.valid)
            .and_then(|r| Some((r.latitude_deg?, r.longitude_deg?, None)));
        if let Some((lat, lon, alt)) = gga_position.or(rmc_position) {
            fix.latitude_deg = Some(lat);
            fix.longitude_deg = Some(lon);
            fix.altitude_m = alt;
        }
        fix
    }

    fn has_data(&self) -> bool {
        self.gga.is_some() || self.rmc.is_some()
    }
}

/// Gathers GGA and RMC sentences into fixes; see the module docs.
#[derive(Debug, Clone)]
pub struct FixFusion {
    stale_after_ms: u64,
    epoch: Epoch,
    last: Option<(GpsFix, u64)>,
}

impl FixFusion {
    /// A fusion whose fix goes stale `stale_after_ms` after the last GGA/RMC.
    pub const fn new(stale_after_ms: u64) -> Self {
        Self {
            stale_after_ms,
            epoch: Epoch {
                key: None,
                gga: None,
                rmc: None,
                emitted: false,
                last_ms: 0,
            },
            last: None,
        }
    }

    /// Takes one parsed sentence seen at `now_ms`; returns a fix when an
    /// epoch is complete. A sentence with impossible values is ignored.
    pub fn update(&mut self, sentence: &Sentence, now_ms: u64) -> Option<GpsFix> {
        if !sentence_is_plausible(sentence) {
            return None;
        }
        let key = match sentence {
            Sentence::Gga(g) => g.time_of_day_ms,
            Sentence::Rmc(r) => r.time_of_day_ms,
            Sentence::Other => return None,
        };
        let mut done = None;
        if key != self.epoch.key {
            done = self.finish_epoch();
            self.epoch = Epoch {
                key,
                ..Epoch::default()
            };
        }
        match sentence {
            Sentence::Gga(g) => self.epoch.gga = Some(*g),
            Sentence::Rmc(r) => self.epoch.rmc = Some(*r),
            Sentence::Other => {}
        }
        self.epoch.last_ms = now_ms;
        if done.is_none() && self.epoch.gga.is_some() && self.epoch.rmc.is_some() {
            done = self.finish_epoch();
        }
        done
    }

    /// Gives out the epoch being gathered, if it has not been given out yet
    /// (call at the end of a log).
    pub fn flush(&mut self) -> Option<GpsFix> {
        self.finish_epoch()
    }

    fn finish_epoch(&mut self) -> Option<GpsFix> {
        if self.epoch.emitted || !self.epoch.has_data() {
            return None;
        }
        self.epoch.emitted = true;
        let fix = self.epoch.fix();
        self.last = Some((fix, self.epoch.last_ms));
        Some(fix)
    }

    /// Whether nothing (no completed epoch) was heard within `stale_after_ms`
    /// before `now_ms`.
    pub fn is_stale(&self, now_ms: u64) -> bool {
        match self.last {
            Some((_, at_ms)) => now_ms.saturating_sub(at_ms) > self.stale_after_ms,
            None => true,
        }
    }

    /// The latest fix, or [`GpsFix::NONE`] once it is stale.
    pub fn current(&self, now_ms: u64) -> GpsFix {
        match self.last {
            Some((fix, _)) if !self.is_stale(now_ms) => fix,
            _ => GpsFix::NONE,
        }
    }
}
