//! Fusing GGA and RMC into one [`GpsFix`] per receiver epoch, and ageing it.
//!
//! A receiver sends a burst of sentences per epoch (usually once a second),
//! all stamped with the same UTC time of day. Sentences are gathered while
//! the time of day stays the same; the epoch's fix is given out as soon as
//! both its GGA and RMC have arrived, or else when the next epoch begins (or
//! at [`FixFusion::flush`]).
//!
//! Rules:
//! - an epoch is *valid* when its RMC status (field 2) is `A` (or `D`) and its
//!   GGA quality (field 6) is 1 or more, counting only the sentences the epoch
//!   has; an RMC `V` ("navigation receiver warning") or a GGA quality 0 makes
//!   the whole epoch invalid, even if the other sentence claims a fix;
//! - a position (and `quality` other than `Invalid`) only from a valid epoch
//!   (the GGA position is preferred, since it comes with the altitude);
//! - the date-time from RMC (fields 1 and 9), even from an RMC `V`: then the
//!   fix has quality `Invalid` and no position, which is how a caller tells a
//!   receiver's untrusted clock from a time that came with a fix; GGA carries
//!   no date and does not set it;
//! - `utc_received_ms` is the caller's clock when that RMC was completed, so
//!   the age of the time can be allowed for ([`GpsFix::utc_age_ms`]);
//! - the altitude only with a GGA quality > 0 in a valid epoch;
//! - `quality` is the GGA quality of a valid epoch; with only an RMC, `Gps`
//!   if its status is valid; `Invalid` otherwise;
//! - a sentence with impossible values (see `parse_sentence`) is ignored, also
//!   when it is built by hand and given to [`FixFusion::update`];
//! - after `stale_after_ms` of the caller's monotonic clock without any
//!   GGA/RMC, [`FixFusion::current`] reports no fix and no time.

use super::parse::{sentence_is_plausible, FixQuality, Gga, Rmc, Sentence, TimeOfDayMs};
use crate::time::DateTime;

/// The fused result of one epoch.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GpsFix {
    /// UTC date-time from RMC fields 1 (time) and 9 (date). Taken as the
    /// receiver's clock only: it came with a fix when `quality` is not
    /// `Invalid` and there is a position, and from an RMC with status `V`
    /// otherwise.
    pub utc: Option<DateTime>,
    /// The caller's monotonic clock, in milliseconds (the `now_ms` given to
    /// `push`/`poll`/`update`), when the sentence that carried `utc` was
    /// completed; `None` exactly when `utc` is `None`. The instant `utc` names
    /// is that old at `utc_received_ms`, plus the receiver's output delay.
    pub utc_received_ms: Option<u64>,
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
        utc_received_ms: None,
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

    /// How long before `now_ms` (the caller's monotonic clock, milliseconds)
    /// the sentence carrying `utc` was received: add it to `utc` to get the
    /// present time. `None` without a `utc`; 0 (saturating) if `now_ms` is
    /// earlier than [`GpsFix::utc_received_ms`].
    pub fn utc_age_ms(&self, now_ms: u64) -> Option<u64> {
        self.utc?;
        self.utc_received_ms
            .map(|received_ms| now_ms.saturating_sub(received_ms))
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct Epoch {
    key: Option<TimeOfDayMs>,
    gga: Option<Gga>,
    rmc: Option<Rmc>,
    /// The caller's clock when the RMC was completed.
    rmc_ms: u64,
    emitted: bool,
    last_ms: u64,
}

impl Epoch {
    fn fix(&self) -> GpsFix {
        let utc = self.rmc.and_then(|r| r.utc);
        let mut fix = GpsFix {
            utc,
            utc_received_ms: utc.map(|_| self.rmc_ms),
            satellites: self.gga.and_then(|g| g.satellites),
            ..GpsFix::NONE
        };
        // Every sentence the epoch has must report a fix; a contradiction
        // (RMC V with GGA 1, or RMC A with GGA 0) counts as no fix.
        let rmc_ok = self.rmc.is_none_or(|r| r.valid);
        let gga_ok = self.gga.is_none_or(|g| g.quality != FixQuality::Invalid);
        if !(rmc_ok && gga_ok && self.has_data()) {
            return fix;
        }
        fix.quality = self.gga.map_or(FixQuality::Gps, |g| g.quality);
        let gga_position = self
            .gga
            .and_then(|g| Some((g.latitude_deg?, g.longitude_deg?, g.altitude_m)));
        let rmc_position = self
            .rmc
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
                rmc_ms: 0,
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
            Sentence::Rmc(r) => {
                self.epoch.rmc = Some(*r);
                self.epoch.rmc_ms = now_ms;
            }
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
