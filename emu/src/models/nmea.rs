//! NMEA 0183 feeder for the GPS port (USART1, 9600 8N1).
//!
//! Sentences end in `*hh` (XOR of the bytes between `$` and `*`) and CR LF
//! (NMEA 0183 §5.3). Three sources: silent; generated RMC + GGA for a site,
//! with or without a fix; or a recorded log, grouped into epochs by the UTC
//! time field (the RMC of an epoch gives its date).
//!
//! Timing: each epoch is queued so that its last byte arrives when emulated
//! UTC reaches the epoch's time (a byte takes 10/9600 s of CPU time, i.e.
//! timescale × that of emulated time), which is how a receiver stamps and
//! sends its epochs. Recorded epochs already past are skipped.
//!
//! Order: the image stamps an epoch's time when its RMC arrives (the age of
//! the fix runs from there, and time older than 1.5 s is not trusted). On the
//! wire at 9600 baud a GGA takes 75 ms (the bench sends epochs at real
//! time; under its 60× compression a GGA would take 4.5 emulated s), so an
//! RMC sent before the GGA would be older than the epoch's end. Every epoch
//! therefore ends with its RMC (as SiRF receivers send them: GGA … RMC); a
//! recorded log's epochs are reordered that way.

use drivers::time::{civil_from_days, days_from_civil};

/// Checksum of a sentence body (between `$` and `*`).
pub fn checksum(body: &str) -> u8 {
    body.bytes().fold(0, |a, b| a ^ b)
}

/// `$body*hh\r\n`.
pub fn sentence(body: &str) -> String {
    format!("${body}*{:02X}\r\n", checksum(body))
}

/// Whether a line carries a correct checksum.
pub fn checksum_ok(line: &str) -> bool {
    let line = line.trim_end();
    let Some(rest) = line.strip_prefix('$') else {
        return false;
    };
    let Some((body, cs)) = rest.rsplit_once('*') else {
        return false;
    };
    u8::from_str_radix(cs, 16).ok() == Some(checksum(body))
}

fn hms(unix_s: i64) -> String {
    let s = unix_s.rem_euclid(86_400);
    format!("{:02}{:02}{:02}.00", s / 3600, s / 60 % 60, s % 60)
}

fn dmy(unix_s: i64) -> String {
    let (y, m, d) = civil_from_days(unix_s.div_euclid(86_400)).unwrap_or((2000, 1, 1));
    format!("{d:02}{m:02}{:02}", y % 100)
}

fn lat_field(lat: f64) -> String {
    let a = lat.abs();
    let deg = a.floor();
    format!(
        "{:02}{:07.4},{}",
        deg as u32,
        (a - deg) * 60.0,
        if lat >= 0.0 { 'N' } else { 'S' }
    )
}

fn lon_field(lon: f64) -> String {
    let a = lon.abs();
    let deg = a.floor();
    format!(
        "{:03}{:07.4},{}",
        deg as u32,
        (a - deg) * 60.0,
        if lon >= 0.0 { 'E' } else { 'W' }
    )
}

/// A generated site.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsSite {
    /// Latitude, degrees north.
    pub lat_deg: f64,
    /// Longitude, degrees east.
    pub lon_deg: f64,
    /// Height above mean sea level, m.
    pub elevation_m: f64,
}

impl GpsSite {
    /// Kano, Nigeria: 11.9683 N, 8.4261 E, 480 m.
    pub fn kano() -> Self {
        GpsSite {
            lat_deg: 11.9683,
            lon_deg: 8.4261,
            elevation_m: 480.0,
        }
    }
}

/// GGA + RMC of one epoch (RMC last: see the module documentation).
pub fn epoch_sentences(site: &GpsSite, unix_s: i64, fix: bool) -> String {
    let t = hms(unix_s);
    if fix {
        let pos = format!("{},{}", lat_field(site.lat_deg), lon_field(site.lon_deg));
        sentence(&format!(
            "GPGGA,{t},{pos},1,08,0.9,{:.1},M,23.1,M,,",
            site.elevation_m
        )) + &sentence(&format!("GPRMC,{t},A,{pos},0.0,0.0,{},,,A", dmy(unix_s)))
    } else {
        sentence(&format!("GPGGA,{t},,,,,0,00,99.9,,,,,,"))
            + &sentence(&format!("GPRMC,{t},V,,,,,,,{},,,N", dmy(unix_s)))
    }
}

/// The epochs of a receiver that may lie, for [`GpsFeed::Recorded`]: one
/// every `period_s` seconds of true time from `first_unix_s` up to (not
/// including) `end_unix_s`, each with a fix and delivered (its last byte)
/// when emulated UTC reaches its true time; epoch `k`, due at true time
/// `u`, says the position and the time `say(k, u)` returns (GGA + RMC as
/// [`epoch_sentences`]).
pub fn lying_epochs(
    first_unix_s: i64,
    end_unix_s: i64,
    period_s: i64,
    mut say: impl FnMut(usize, i64) -> (GpsSite, i64),
) -> Vec<Epoch> {
    (first_unix_s..end_unix_s)
        .step_by(period_s.max(1) as usize)
        .enumerate()
        .map(|(k, u)| {
            let (site, said_unix_s) = say(k, u);
            Epoch {
                unix_s: u,
                text: epoch_sentences(&site, said_unix_s, true),
            }
        })
        .collect()
}

/// One epoch of a recorded log.
#[derive(Debug, Clone, PartialEq)]
pub struct Epoch {
    /// UTC of the epoch, Unix seconds.
    pub unix_s: i64,
    /// Its sentences, CR LF terminated.
    pub text: String,
}

/// Splits a recorded log into epochs by the UTC time field; dates come from
/// the RMC sentences (a GGA-only epoch takes the last date seen, or
/// `default_day` before any). Within an epoch the RMC sentences move to the
/// end, the others keep their order.
pub fn parse_log(text: &str, default_day: i64) -> Vec<Epoch> {
    let mut out: Vec<Epoch> = Vec::new();
    let mut day = default_day;
    let mut pending: Vec<(u32, String, Option<i64>)> = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if !line.starts_with('$') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        let kind = fields
            .first()
            .map(|f| f.get(3..6).unwrap_or(""))
            .unwrap_or("");
        let Some(tf) = fields.get(1).filter(|t| t.len() >= 6) else {
            continue;
        };
        let Ok(sod) = tf[..6]
            .parse::<u32>()
            .map(|v| v / 10_000 * 3600 + v / 100 % 100 * 60 + v % 100)
        else {
            continue;
        };
        let date = if kind == "RMC" {
            fields.get(9).and_then(|d| {
                let v: u32 = d.get(..6)?.parse().ok()?;
                let (dd, mm, yy) = (v / 10_000, v / 100 % 100, v % 100);
                Some(days_from_civil(2000 + yy as u16, mm as u8, dd as u8))
            })
        } else {
            None
        };
        pending.push((sod, format!("{line}\r\n"), date));
    }
    // Group consecutive sentences with the same time field.
    let mut i = 0;
    while i < pending.len() {
        let sod = pending[i].0;
        let mut j = i;
        let (mut text, mut rmc) = (String::new(), String::new());
        while j < pending.len() && pending[j].0 == sod {
            if let Some(d) = pending[j].2 {
                day = d;
            }
            let line = &pending[j].1;
            let is_rmc = line.get(3..6) == Some("RMC");
            (if is_rmc { &mut rmc } else { &mut text }).push_str(line);
            j += 1;
        }
        text.push_str(&rmc);
        out.push(Epoch {
            unix_s: day * 86_400 + i64::from(sod),
            text,
        });
        i = j;
    }
    out
}

/// Where GPS sentences come from.
#[derive(Debug, Clone, PartialEq)]
pub enum GpsFeed {
    /// Nothing on the port.
    Silent,
    /// RMC + GGA generated every `period_s` emulated seconds.
    Generated {
        /// The site.
        site: GpsSite,
        /// Whether the receiver has a fix.
        fix: bool,
        /// Emulated seconds between epochs.
        period_s: f64,
    },
    /// A recorded log, already split.
    Recorded(Vec<Epoch>),
}

impl GpsFeed {
    /// Kano with a fix, one epoch every 30 emulated seconds.
    pub fn kano() -> Self {
        GpsFeed::Generated {
            site: GpsSite::kano(),
            fix: true,
            period_s: 30.0,
        }
    }
}

/// Decides what to queue on the port as emulated time passes.
#[derive(Debug, Clone)]
pub struct NmeaFeeder {
    feed: GpsFeed,
    /// Emulated seconds one byte takes on the wire.
    byte_s: f64,
    next_generated_s: i64,
    next_recorded: usize,
    generated_len: Option<usize>,
    /// Epochs queued.
    pub epochs_sent: u32,
    /// Recorded epochs skipped as already past.
    pub epochs_skipped: u32,
}

impl NmeaFeeder {
    /// `byte_s`: emulated seconds per byte (10 / 9600 × timescale).
    pub fn new(feed: GpsFeed, start_unix_s: i64, byte_s: f64) -> Self {
        NmeaFeeder {
            feed,
            byte_s,
            next_generated_s: start_unix_s + 2,
            next_recorded: 0,
            generated_len: None,
            epochs_sent: 0,
            epochs_skipped: 0,
        }
    }

    /// At emulated UTC `now_unix_s` with the port idle: the bytes to queue now.
    pub fn poll(&mut self, now_unix_s: f64, port_idle: bool) -> Option<String> {
        if !port_idle {
            return None;
        }
        match &self.feed {
            GpsFeed::Silent => None,
            GpsFeed::Generated {
                site,
                fix,
                period_s,
            } => {
                let t = self.next_generated_s;
                // The length does not depend on the time: one format per epoch.
                let len = *self
                    .generated_len
                    .get_or_insert_with(|| epoch_sentences(site, t, *fix).len());
                let lead = len as f64 * self.byte_s;
                if now_unix_s + lead < t as f64 {
                    return None;
                }
                if now_unix_s + lead > t as f64 + 0.05 {
                    // Too late for this epoch (e.g. just after start): wait
                    // for the next whole second the last byte can make.
                    self.next_generated_s = (now_unix_s + lead).ceil() as i64;
                    return None;
                }
                let text = epoch_sentences(site, t, *fix);
                self.next_generated_s = t + (*period_s).max(1.0).round() as i64;
                self.epochs_sent += 1;
                Some(text)
            }
            GpsFeed::Recorded(epochs) => {
                while let Some(e) = epochs.get(self.next_recorded) {
                    let lead = e.text.len() as f64 * self.byte_s;
                    if (e.unix_s as f64) < now_unix_s + lead - 1.0 {
                        self.next_recorded += 1;
                        self.epochs_skipped += 1;
                        continue;
                    }
                    if now_unix_s + lead < e.unix_s as f64 {
                        return None;
                    }
                    self.next_recorded += 1;
                    self.epochs_sent += 1;
                    return Some(e.text.clone());
                }
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksums_match_the_recorded_log() {
        // From tests/firmware/gps_kano_2026-03-20.nmea.
        let line = "$GPRMC,000000.00,A,1158.0980,N,00825.5660,E,0.0,0.0,200326,,,A*5D";
        assert!(checksum_ok(line));
        assert!(!checksum_ok(&line.replace("*5D", "*5E")));
        let gen = epoch_sentences(&GpsSite::kano(), 1_782_018_000, true);
        for l in gen.lines() {
            assert!(checksum_ok(l), "{l}");
        }
        assert!(gen.starts_with("$GPGGA,050000.00,1158.0980,N,00825.5660,E,1,08,0.9,480.0,M"));
        let rmc = "$GPRMC,050000.00,A,1158.0980,N,00825.5660,E,0.0,0.0,210626,,,A*";
        assert!(gen.lines().nth(1).is_some_and(|l| l.starts_with(rmc)));
        let nofix = epoch_sentences(&GpsSite::kano(), 1_782_018_000, false);
        assert!(nofix.contains(",V,") && nofix.lines().all(checksum_ok));
    }

    #[test]
    fn generated_sentences_parse_in_the_drivers() {
        let gen = epoch_sentences(&GpsSite::kano(), 1_782_018_000, true);
        for l in gen.lines() {
            assert!(drivers::gps::parse_sentence(l).is_ok(), "{l}");
        }
    }

    #[test]
    fn recorded_log_groups_by_time_and_skips_the_past() {
        let log = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/firmware/gps_kano_2026-03-20.nmea"
        ))
        .unwrap();
        let epochs = parse_log(&log, 0);
        assert_eq!(epochs.len(), 5);
        let day = days_from_civil(2026, 3, 20);
        assert_eq!(epochs[0].unix_s, day * 86_400);
        assert_eq!(epochs[1].unix_s, day * 86_400 + 1);
        assert_eq!(epochs[0].text.lines().count(), 2);
        // RMC last whatever the log's order.
        assert!(epochs.iter().all(|e| e
            .text
            .lines()
            .last()
            .is_some_and(|l| l.starts_with("$GPRMC"))));
        let mut f = NmeaFeeder::new(GpsFeed::Recorded(epochs), 0, 0.001);
        // At 00:00:02.5 epochs 0–1 are past; epoch 2 (00:00:02) is within
        // the 1 s grace and is sent; 3 waits.
        let now = (day * 86_400) as f64 + 2.5;
        assert!(f.poll(now, true).is_some());
        assert_eq!(f.epochs_skipped, 2);
        assert!(f.poll(now, true).is_none());
    }

    #[test]
    fn recorded_epoch_is_reordered_to_end_with_its_rmc() {
        let rmc = "$GPRMC,120000.00,A,1158.0980,N,00825.5660,E,0.0,0.0,200326,,,A*5E";
        let gga = "$GPGGA,120000.00,1158.0980,N,00825.5660,E,1,08,0.9,472.0,M,23.1,M,,*69";
        let gsa = "$GPGSA,A,3,01,02,03,04,,,,,,,,,1.5,0.9,1.2*38";
        let log = format!("{rmc}\n{gga}\n{gsa}\n");
        let epochs = parse_log(&log, 0);
        // The GSA has no time field: not part of any epoch.
        assert_eq!(epochs.len(), 1);
        assert!([rmc, gga, gsa].iter().all(|l| checksum_ok(l)));
        assert_eq!(epochs[0].text, format!("{gga}\r\n{rmc}\r\n"));
        assert_eq!(
            epochs[0].unix_s,
            days_from_civil(2026, 3, 20) * 86_400 + 43_200
        );
    }

    #[test]
    fn generated_epoch_is_stamped_at_its_last_byte() {
        let byte_s = 10.0 / 9600.0 * 60.0;
        let t0 = 1_782_018_000;
        let mut f = NmeaFeeder::new(GpsFeed::kano(), t0, byte_s);
        let mut now = t0 as f64;
        let text = loop {
            if let Some(t) = f.poll(now, true) {
                break t;
            }
            now += 0.01;
        };
        let end = now + text.len() as f64 * byte_s;
        // The epoch's time field is the second its last byte arrives (the
        // first epoch after start: 2 s after it, or as soon as the ~9.4 s
        // an epoch takes on the wire at 60× allow).
        let stamp = parse_log(&text, 0)[0].unix_s;
        assert!((end - stamp as f64).abs() < 0.02, "end {end} stamp {stamp}");
        assert!(stamp - t0 <= 10, "stamp {stamp}");
    }

    #[test]
    fn lying_epochs_say_what_they_are_told_at_their_true_time() {
        let t0 = 1_782_028_800; // 2026-06-21T08:00:00Z
        let site = GpsSite {
            lat_deg: -16.5,
            lon_deg: -179.99999,
            elevation_m: 10.0,
        };
        let e = lying_epochs(t0, t0 + 90, 30, |k, u| (site, u - 3600 * k as i64));
        assert_eq!(e.len(), 3);
        assert_eq!(e[2].unix_s, t0 + 60);
        // Said one hour earlier per epoch, at their true delivery time.
        let said = parse_log(&e[2].text, 0)[0].unix_s;
        assert_eq!(said, t0 + 60 - 7200);
        assert!(e[2].text.contains(",1630.0000,S,17959.9994,W,"));
        assert!(e.iter().all(|x| x.text.lines().all(checksum_ok)));
    }
}
