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
//!   GGA/RMC, [`FixFusion::current`] reports no fix and no time, and forgets
//!   the fix.
//!
//! The caller's clock is its monotonic milliseconds in 32 bits, wrapping
//! every 2³² ms (49.7 days); every age and staleness is a wrapping
//! difference. A fix is forgotten once [`FixFusion::current`] finds it stale,
//! so a stamp cannot come round to look fresh again as long as the fix is
//! asked for at least once every 49 days (a main loop asks every pass).

use super::coordinate::Coordinate;
use super::parse::{sentence_is_plausible, FixQuality, Gga, Rmc, Sentence, TimeOfDayMs};
use crate::time::DateTime;

/// The fused result of one epoch.
///
/// ```
/// use drivers::gps::{parse_sentence, FixFusion, FixQuality};
/// use drivers::time::DateTime;
///
/// // u-blox NEO-6 protocol specification's GGA example, and an RMC of the
/// // same epoch (checksum computed independently in Python).
/// let mut fusion = FixFusion::new(2_000);
/// let gga = parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")?;
/// let rmc = parse_sentence("$GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54")?;
/// assert_eq!(fusion.update(&gga, 100), None); // waits for the RMC
/// let fix = fusion.update(&rmc, 180).unwrap();
/// assert_eq!(fix.quality, FixQuality::Gps);
/// assert_eq!(fix.utc, Some(DateTime::new(2002, 12, 9, 9, 27, 25)?));
/// assert_eq!(fix.utc_received_ms, Some(180));
/// assert_eq!(fix.altitude_m, Some(499.6)); // GGA field 9
/// assert_eq!(fix.satellites, Some(8));
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    pub utc_received_ms: Option<u32>,
    /// Latitude, degrees north positive (only with a valid fix), exactly as
    /// the receiver wrote it (`.deg::<f32>()` or `.deg::<f64>()`).
    pub latitude_deg: Option<Coordinate>,
    /// Longitude, degrees east positive (only with a valid fix).
    pub longitude_deg: Option<Coordinate>,
    /// Altitude above mean sea level, metres (only with GGA quality > 0).
    pub altitude_m: Option<f32>,
    /// Fix quality.
    pub quality: FixQuality,
    /// Satellites used (GGA).
    pub satellites: Option<u8>,
}

impl GpsFix {
    /// No time, no position.
    ///
    /// ```
    /// use drivers::gps::{FixQuality, GpsFix};
    ///
    /// assert_eq!(GpsFix::NONE, GpsFix::default());
    /// assert_eq!(GpsFix::NONE.quality, FixQuality::Invalid);
    /// assert!(!GpsFix::NONE.has_position());
    /// ```
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
    ///
    /// ```
    /// use drivers::gps::{parse_sentence, FixFusion};
    ///
    /// // An RMC with status V (receiver warning) and no position (checksum
    /// // computed in Python): a time, but no position.
    /// let mut fusion = FixFusion::new(2_000);
    /// let rmc = parse_sentence("$GPRMC,092725.00,V,,,,,,,091202,,,N*7E")?;
    /// fusion.update(&rmc, 0);
    /// let fix = fusion.flush().unwrap();
    /// assert!(fix.utc.is_some());
    /// assert!(!fix.has_position());
    /// # Ok::<(), drivers::gps::ParseError>(())
    /// ```
    pub fn has_position(&self) -> bool {
        self.latitude_deg.is_some() && self.longitude_deg.is_some()
    }

    /// How long before `now_ms` (the caller's monotonic clock, milliseconds,
    /// 32 bits wrapping) the sentence carrying `utc` was received: add it to
    /// `utc` to get the present time. `None` without a `utc`. Counted modulo
    /// 2³² ms (49.7 days): exact for any fix the decoder gives out, since it
    /// forgets a fix once stale ([`FixFusion::current`]). A `now_ms` earlier
    /// than [`GpsFix::utc_received_ms`] reads as an age near 2³² ms, never
    /// as a fresh one.
    ///
    /// ```
    /// use drivers::gps::{parse_sentence, FixFusion, GpsFix};
    ///
    /// // u-blox's RMC example, completed at 10 000 ms on the caller's clock.
    /// let mut fusion = FixFusion::new(2_000);
    /// let rmc = parse_sentence(
    ///     "$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57",
    /// )?;
    /// fusion.update(&rmc, 10_000);
    /// let fix = fusion.flush().unwrap();
    /// assert_eq!(fix.utc_age_ms(10_350), Some(350)); // 08:35:59 was 350 ms ago
    /// assert_eq!(fix.utc_age_ms(9_000), Some(u32::MAX - 999)); // before it: not fresh
    /// assert_eq!(GpsFix::NONE.utc_age_ms(10_350), None);
    /// # Ok::<(), drivers::gps::ParseError>(())
    /// ```
    pub fn utc_age_ms(&self, now_ms: u32) -> Option<u32> {
        self.utc?;
        self.utc_received_ms
            .map(|received_ms| now_ms.wrapping_sub(received_ms))
    }
}

#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
struct Epoch {
    key: Option<TimeOfDayMs>,
    gga: Option<Gga>,
    rmc: Option<Rmc>,
    /// The caller's clock when the RMC was completed.
    rmc_ms: u32,
    emitted: bool,
    last_ms: u32,
}

impl Epoch {
    /// Writes the epoch's fix into `fix`, field by field from references to
    /// its sentences (built as a value, from combinators on the
    /// `Option<Gga>`/`Option<Rmc>` values, it was copied whole several
    /// times on the AVR).
    // Out of line on the AVR: the fix is written where it is kept.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn write_fix(&self, fix: &mut GpsFix) {
        *fix = GpsFix::NONE;
        if let Some(utc) = self.rmc.as_ref().and_then(|r| r.utc) {
            fix.utc = Some(utc);
            fix.utc_received_ms = Some(self.rmc_ms);
        }
        if let Some(gga) = &self.gga {
            fix.satellites = gga.satellites;
        }
        // Every sentence the epoch has must report a fix; a contradiction
        // (RMC V with GGA 1, or RMC A with GGA 0) counts as no fix.
        let rmc_ok = self.rmc.as_ref().is_none_or(|r| r.valid);
        let gga_ok = self
            .gga
            .as_ref()
            .is_none_or(|g| g.quality != FixQuality::Invalid);
        if !(rmc_ok && gga_ok && self.has_data()) {
            return;
        }
        fix.quality = self.gga.as_ref().map_or(FixQuality::Gps, |g| g.quality);
        // The GGA position (with its altitude) first, else the RMC's: the
        // source chosen by reference, then copied once.
        let gga_position = self.gga.as_ref().and_then(|g| {
            Some((
                g.latitude_deg.as_ref()?,
                g.longitude_deg.as_ref()?,
                g.altitude_m,
            ))
        });
        let rmc_position = self
            .rmc
            .as_ref()
            .and_then(|r| Some((r.latitude_deg.as_ref()?, r.longitude_deg.as_ref()?, None)));
        if let Some((lat, lon, alt)) = gga_position.or(rmc_position) {
            fix.latitude_deg = Some(*lat);
            fix.longitude_deg = Some(*lon);
            fix.altitude_m = alt;
        }
    }

    fn has_data(&self) -> bool {
        self.gga.is_some() || self.rmc.is_some()
    }
}

/// Gathers GGA and RMC sentences into fixes; see the module docs.
///
/// ```
/// use drivers::gps::{parse_sentence, FixFusion, FixQuality};
///
/// // A GGA with quality 0 and an RMC with status V (checksums computed in
/// // Python): the epoch is invalid, so the fix has no position.
/// let mut fusion = FixFusion::new(2_000);
/// fusion.update(&parse_sentence("$GPGGA,092725.00,,,,,0,00,99.99,,,,,,*6D")?, 0);
/// let fix = fusion
///     .update(&parse_sentence("$GPRMC,092725.00,V,,,,,,,091202,,,N*7E")?, 10)
///     .unwrap();
/// assert_eq!(fix.quality, FixQuality::Invalid);
/// assert!(!fix.has_position());
/// # Ok::<(), drivers::gps::ParseError>(())
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FixFusion {
    stale_after_ms: u32,
    epoch: Epoch,
    /// The last epoch's fix; given out only while `last_ms` is `Some`.
    last_fix: GpsFix,
    /// The caller's clock at the last sentence of that epoch; `None` before
    /// the first epoch and once the fix is forgotten.
    last_ms: Option<u32>,
}

impl FixFusion {
    /// A fusion whose fix goes stale `stale_after_ms` after the last GGA/RMC.
    ///
    /// ```
    /// use drivers::gps::{FixFusion, GpsFix};
    ///
    /// let mut fusion = FixFusion::new(2_000);
    /// assert!(fusion.is_stale(0));
    /// assert_eq!(fusion.current(0), GpsFix::NONE);
    /// ```
    pub const fn new(stale_after_ms: u32) -> Self {
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
            last_fix: GpsFix::NONE,
            last_ms: None,
        }
    }

    /// Takes one parsed sentence seen at `now_ms`; returns a fix when an
    /// epoch is complete. A sentence with impossible values is ignored.
    ///
    /// ```
    /// use drivers::gps::{parse_sentence, Coordinate, FixFusion, Gga, Sentence};
    ///
    /// let mut fusion = FixFusion::new(2_000);
    /// // u-blox's GGA example: the epoch 09:27:25 starts.
    /// let gga = parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")?;
    /// assert_eq!(fusion.update(&gga, 0), None);
    /// // A hand-built GGA of a later epoch with a latitude of 95°: ignored.
    /// let bad = Sentence::Gga(Gga {
    ///     time_of_day_ms: Some(34_046_000),
    ///     latitude_deg: Coordinate::from_deg(95.0),
    ///     longitude_deg: Coordinate::from_deg(8.0),
    ///     ..Gga::default()
    /// });
    /// assert_eq!(fusion.update(&bad, 1_000), None);
    /// // The next epoch's GGA (checksum computed in Python) closes the first.
    /// let next = parse_sentence(
    ///     "$GPGGA,092726.00,4717.11400,N,00833.91590,E,1,08,1.01,499.7,M,48.0,M,,*5E",
    /// )?;
    /// let fix = fusion.update(&next, 1_000).unwrap();
    /// assert_eq!(fix.altitude_m, Some(499.6));
    /// # Ok::<(), drivers::gps::ParseError>(())
    /// ```
    // Its own stack frame on the AVR (see `parse_sentence`).
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub fn update(&mut self, sentence: &Sentence, now_ms: u32) -> Option<GpsFix> {
        self.update_completes(sentence, now_ms)
            .then_some(self.last_fix)
    }

    /// [`FixFusion::update`] saying only whether an epoch completed: its
    /// fix is then [`FixFusion::last_fix`]. The decoder passes this on
    /// instead of an `Option<GpsFix>` (41 bytes, copied at every level on
    /// the AVR).
    // Out of line on the AVR: its own frame, not the byte loop's.
    #[cfg_attr(target_arch = "avr", inline(never))]
    pub(super) fn update_completes(&mut self, sentence: &Sentence, now_ms: u32) -> bool {
        if !sentence_is_plausible(sentence) {
            return false;
        }
        let key = match sentence {
            Sentence::Gga(g) => g.time_of_day_ms,
            Sentence::Rmc(r) => r.time_of_day_ms,
            Sentence::Other => return false,
        };
        let mut done = false;
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
        if !done && self.epoch.gga.is_some() && self.epoch.rmc.is_some() {
            done = self.finish_epoch();
        }
        done
    }

    /// Gives out the epoch being gathered, if it has not been given out yet
    /// (call at the end of a log).
    ///
    /// ```
    /// use drivers::gps::{parse_sentence, FixFusion};
    ///
    /// // u-blox's GGA example alone.
    /// let mut fusion = FixFusion::new(2_000);
    /// fusion.update(&parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")?, 0);
    /// let fix = fusion.flush().unwrap();
    /// assert!(fix.has_position());
    /// assert_eq!(fusion.flush(), None); // only once
    /// # Ok::<(), drivers::gps::ParseError>(())
    /// ```
    pub fn flush(&mut self) -> Option<GpsFix> {
        self.finish_epoch().then_some(self.last_fix)
    }

    /// The fix of the last epoch given out (whether or not stale since).
    pub(super) fn last_fix(&self) -> GpsFix {
        self.last_fix
    }

    /// Gives out the epoch being gathered into `last_fix`; whether it did.
    fn finish_epoch(&mut self) -> bool {
        if self.epoch.emitted || !self.epoch.has_data() {
            return false;
        }
        self.epoch.emitted = true;
        self.epoch.write_fix(&mut self.last_fix);
        self.last_ms = Some(self.epoch.last_ms);
        true
    }

    /// Whether nothing (no completed epoch) was heard within `stale_after_ms`
    /// before `now_ms` (a wrapping difference of the 32-bit clock).
    ///
    /// ```
    /// use drivers::gps::{parse_sentence, FixFusion};
    ///
    /// let mut fusion = FixFusion::new(2_000);
    /// fusion.update(&parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")?, 5_000);
    /// fusion.update(&parse_sentence("$GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54")?, 5_100);
    /// assert!(!fusion.is_stale(7_100)); // 2 000 ms after the last sentence
    /// assert!(fusion.is_stale(7_101));
    /// # Ok::<(), drivers::gps::ParseError>(())
    /// ```
    pub fn is_stale(&self, now_ms: u32) -> bool {
        match self.last_ms {
            Some(at_ms) => now_ms.wrapping_sub(at_ms) > self.stale_after_ms,
            None => true,
        }
    }

    /// The latest fix, or [`GpsFix::NONE`] once it is stale (and from then
    /// on: the stale fix is forgotten).
    ///
    /// ```
    /// use drivers::gps::{parse_sentence, FixFusion, GpsFix};
    ///
    /// let mut fusion = FixFusion::new(2_000);
    /// fusion.update(&parse_sentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B")?, 0);
    /// let fix = fusion.update(&parse_sentence("$GPRMC,092725.00,A,4717.11399,N,00833.91590,E,0.004,77.52,091202,,,A*54")?, 0).unwrap();
    /// assert_eq!(fusion.current(1_000), fix);
    /// assert_eq!(fusion.current(2_001), GpsFix::NONE);
    /// # Ok::<(), drivers::gps::ParseError>(())
    /// ```
    pub fn current(&mut self, now_ms: u32) -> GpsFix {
        if self.is_stale(now_ms) {
            // Forgotten: never given out again.
            self.last_ms = None;
            GpsFix::NONE
        } else {
            self.last_fix
        }
    }
}
