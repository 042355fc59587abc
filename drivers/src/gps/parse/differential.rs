//! The reader in `parse.rs` against the `nmea` 0.8 crate it replaced: the
//! old `parse_sentence` is kept here, word for word, and both are run on every
//! sentence of the golden logs (`drivers/tests/data/*.nmea`,
//! `tests/firmware/*.nmea` when the workspace is there), on mutations of
//! them, and on generated sentences. Both must reject the same sentences and
//! give the same values: times, dates, qualities, counts and statuses equal;
//! latitudes and longitudes within 1e-12° (the old path rounds three times,
//! the new one once); altitudes equal or, past 7 significant digits, within
//! one f32 step.

extern crate std;

use std::string::String;
use std::vec::Vec;
use std::{format, println};

use chrono::{Datelike, Timelike};
use nmea::sentences::rmc::RmcStatusOfFix;
use nmea::sentences::FixType;
use nmea::ParseResult;

use super::super::assembler::nmea_checksum;
use super::super::plausible::{reference::check_fields, Kind};
use super::*;

impl From<FixType> for FixQuality {
    fn from(f: FixType) -> Self {
        match f {
            FixType::Invalid => FixQuality::Invalid,
            FixType::Gps => FixQuality::Gps,
            FixType::DGps => FixQuality::Dgps,
            FixType::Pps => FixQuality::Pps,
            FixType::Rtk => FixQuality::Rtk,
            FixType::FloatRtk => FixQuality::FloatRtk,
            FixType::Estimated => FixQuality::Estimated,
            FixType::Manual => FixQuality::Manual,
            FixType::Simulation => FixQuality::Simulation,
        }
    }
}

fn old_time_of_day_ms(t: &chrono::NaiveTime) -> TimeOfDayMs {
    let millis = (t.nanosecond() / 1_000_000).min(999);
    t.num_seconds_from_midnight() * 1000 + millis
}

fn old_to_datetime(date: &chrono::NaiveDate, time: &chrono::NaiveTime) -> Option<DateTime> {
    let year = u16::try_from(date.year()).ok()?;
    let month = u8::try_from(date.month()).ok()?;
    let day = u8::try_from(date.day()).ok()?;
    let hour = u8::try_from(time.hour()).ok()?;
    let minute = u8::try_from(time.minute()).ok()?;
    let second = u8::try_from(time.second()).ok()?;
    let millis = u16::try_from((time.nanosecond() / 1_000_000).min(999)).ok()?;
    DateTime::new(year, month, day, hour, minute, second)
        .and_then(|dt| dt.with_millis(millis))
        .ok()
}

/// `parse_sentence` as it was with the `nmea` crate.
fn old_parse_sentence(sentence: &str) -> Result<Sentence, ParseError> {
    let kind = match sentence.get(3..6).ok_or(ParseError)? {
        "GGA" => Kind::Gga,
        "RMC" => Kind::Rmc,
        _ => return Ok(Sentence::Other),
    };
    if !check_fields(kind, sentence) {
        return Err(ParseError);
    }
    let parsed = match nmea::parse_str(sentence) {
        Ok(ParseResult::GGA(g)) => Ok(Sentence::Gga(Gga {
            time_of_day_ms: g.fix_time.as_ref().map(old_time_of_day_ms),
            quality: g.fix_type.map(FixQuality::from).unwrap_or_default(),
            latitude_deg: g.latitude.and_then(Coordinate::from_deg),
            longitude_deg: g.longitude.and_then(Coordinate::from_deg),
            altitude_m: g.altitude,
            satellites: g.fix_satellites.map(|n| u8::try_from(n).unwrap_or(u8::MAX)),
        })),
        Ok(ParseResult::RMC(r)) => Ok(Sentence::Rmc(Rmc {
            time_of_day_ms: r.fix_time.as_ref().map(old_time_of_day_ms),
            utc: match (r.fix_date.as_ref(), r.fix_time.as_ref()) {
                (Some(d), Some(t)) => old_to_datetime(d, t),
                _ => None,
            },
            valid: matches!(
                r.status_of_fix,
                RmcStatusOfFix::Autonomous | RmcStatusOfFix::Differential
            ),
            latitude_deg: r.lat.and_then(Coordinate::from_deg),
            longitude_deg: r.lon.and_then(Coordinate::from_deg),
        })),
        _ => Err(ParseError),
    }?;
    if sentence_is_plausible(&parsed) {
        Ok(parsed)
    } else {
        Err(ParseError)
    }
}

/// Largest latitude/longitude difference allowed between the two.
const ANGLE_TOLERANCE_DEG: f64 = 1e-12;

fn angle_same(a: Option<Coordinate>, b: Option<Coordinate>, max_diff: &mut f64) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(x), Some(y)) => {
            let d = (x.deg::<f64>() - y.deg::<f64>()).abs();
            *max_diff = max_diff.max(d);
            d <= ANGLE_TOLERANCE_DEG
        }
        _ => false,
    }
}

fn altitude_same(a: Option<f32>, b: Option<f32>, not_bitwise: &mut u32) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(x), Some(y)) if x.to_bits() == y.to_bits() => true,
        (Some(x), Some(y)) => {
            *not_bitwise += 1;
            x.to_bits().abs_diff(y.to_bits()) <= 1
        }
        _ => false,
    }
}

/// Largest angle difference and altitudes not bitwise equal, so far.
#[derive(Default)]
struct Spread {
    angle_deg: f64,
    altitudes: u32,
}

fn same(
    old: &Result<Sentence, ParseError>,
    new: &Result<Sentence, ParseError>,
    spread: &mut Spread,
) -> bool {
    let max_diff = &mut spread.angle_deg;
    match (old, new) {
        (Err(_), Err(_)) | (Ok(Sentence::Other), Ok(Sentence::Other)) => true,
        (Ok(Sentence::Gga(a)), Ok(Sentence::Gga(b))) => {
            a.time_of_day_ms == b.time_of_day_ms
                && a.quality == b.quality
                && a.satellites == b.satellites
                && altitude_same(a.altitude_m, b.altitude_m, &mut spread.altitudes)
                && angle_same(a.latitude_deg, b.latitude_deg, max_diff)
                && angle_same(a.longitude_deg, b.longitude_deg, max_diff)
        }
        (Ok(Sentence::Rmc(a)), Ok(Sentence::Rmc(b))) => {
            a.time_of_day_ms == b.time_of_day_ms
                && a.utc == b.utc
                && a.valid == b.valid
                && angle_same(a.latitude_deg, b.latitude_deg, max_diff)
                && angle_same(a.longitude_deg, b.longitude_deg, max_diff)
        }
        _ => false,
    }
}

/// `$body*hh` with the right checksum.
fn frame(body: &str) -> String {
    format!("${body}*{:02X}", nmea_checksum(body.as_bytes()))
}

/// Every GGA/RMC body (between `$` and `*`) of the logs that exist.
fn log_bodies() -> Vec<String> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut bodies = Vec::new();
    for sub in ["tests/data", "../tests/firmware"] {
        let Ok(entries) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        let mut paths: Vec<_> = entries.filter_map(|e| Some(e.ok()?.path())).collect();
        paths.sort();
        for path in paths {
            if path.extension().is_none_or(|e| e != "nmea") {
                continue;
            }
            let bytes = std::fs::read(&path).unwrap();
            for line in String::from_utf8_lossy(&bytes).lines() {
                let Some(start) = line.rfind('$') else {
                    continue;
                };
                let Some(rest) = line.get(start + 1..) else {
                    continue;
                };
                let body = rest.split('*').next().unwrap_or(rest);
                if body.get(2..5).is_some_and(|t| t == "GGA" || t == "RMC") {
                    bodies.push(body.into());
                }
            }
        }
    }
    bodies
}

/// xorshift64* (Vigna 2016).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.below(items.len())]
    }
}

const CHARS: &[u8] = b"0123456789.,-+NSEWAVDMnsewavdm e";

/// Field values at and around every limit.
const SPECIAL: &[&str] = &[
    "",
    "0",
    "1",
    "8",
    "9",
    "10",
    "00",
    "+1",
    "-0",
    "-1",
    "1e5",
    "nan",
    "inf",
    ".5",
    "5.",
    "60",
    "5960.0",
    "5959.99999",
    "9000.0000",
    "9000.0001",
    "8959.9999999999999",
    "18000.0",
    "18000.0000001",
    "17959.999999",
    "0000.0000",
    "00000.0000",
    "3734.002",
    "12658.998",
    "3734.00200000000000001",
    "12658.998000000000001",
    "373.4",
    "03734.0",
    "3760.0",
    "4294967295",
    "4294967296",
    "99999999999999999999999",
    "255",
    "256",
    "300",
    "123456",
    "123456.",
    "123456.5",
    "123456.9995",
    "123456.9999999999",
    "123459.99999999995",
    "235959.9999999999",
    "235959.99999999949",
    "235960",
    "240000",
    "000000.000",
    "290224",
    "300224",
    "290223",
    "311299",
    "010183",
    "311282",
    "000000",
    "151324",
    "M",
    "F",
    "MM",
    "A",
    "D",
    "V",
    "AV",
    "X",
    "E",
    "W",
    "N",
    "S",
    "n",
    "e",
    "w",
    "s",
    "20000",
    "20000.0000000001",
    "-500",
    "-500.0000001",
    "38.5",
    "-12.5",
    "+38.7",
    "38.1234567891234",
    "0.0000000001",
    "16777217",
    "19999.999999",
    "-499.9999999",
];

fn mutate(rng: &mut Rng, body: &str) -> String {
    let mut fields: Vec<String> = body.split(',').map(String::from).collect();
    for _ in 0..1 + rng.below(3) {
        let i = 1 + rng.below(fields.len().max(2) - 1);
        match rng.below(6) {
            0..=2 => {
                if let Some(f) = fields.get_mut(i) {
                    *f = rng.pick(SPECIAL).into();
                }
            }
            3 => {
                if let Some(f) = fields.get_mut(i) {
                    let mut b = f.clone().into_bytes();
                    let c = CHARS[rng.below(CHARS.len())];
                    let at = rng.below(b.len() + 1);
                    match rng.below(3) {
                        0 if at < b.len() => b[at] = c,
                        1 if at < b.len() => {
                            b.remove(at);
                        }
                        _ => b.insert(at, c),
                    }
                    *f = String::from_utf8(b).unwrap();
                }
            }
            4 => {
                if i < fields.len() && fields.len() > 2 {
                    fields.remove(i);
                }
            }
            _ => {
                let f = fields.get(i).cloned().unwrap_or_default();
                fields.insert(i.min(fields.len()), f);
            }
        }
    }
    fields.join(",")
}

fn generated(rng: &mut Rng) -> String {
    let talker = rng.pick(&["GP", "GN", "GL", "GA", "BD", "GB", "QZ"]);
    let d = |rng: &mut Rng, n: usize| -> String {
        (0..n)
            .map(|_| char::from(b'0' + rng.below(10) as u8))
            .collect()
    };
    let dec = |rng: &mut Rng, int: usize| {
        let frac = rng.below(12);
        match (int, frac) {
            (_, 0) => d(rng, int),
            (0, _) => format!(".{}", d(rng, frac)),
            _ => format!("{}.{}", d(rng, int), d(rng, frac)),
        }
    };
    let hms = format!(
        "{:02}{:02}{:02}",
        rng.below(24),
        rng.below(60),
        rng.below(60)
    );
    let time = format!("{hms}{}", &dec(rng, 0)[..]);
    let min = format!("{:02}", rng.below(60));
    let lat = format!("{:02}{min}{}", rng.below(90), &dec(rng, 0)[..]);
    let lon = format!("{:03}{min}{}", rng.below(180), &dec(rng, 0)[..]);
    let ns = rng.pick(&["N", "S"]);
    let ew = rng.pick(&["E", "W"]);
    if rng.below(2) == 0 {
        let sign = rng.pick(&["", "-", "+"]);
        let int = 1 + rng.below(5);
        let alt = format!("{sign}{}", dec(rng, int));
        let q = rng.below(9);
        let n = 1 + rng.below(3);
        let sats = d(rng, n);
        format!("{talker}GGA,{time},{lat},{ns},{lon},{ew},{q},{sats},1.0,{alt},M,18.3,M,,")
    } else {
        let date = format!(
            "{:02}{:02}{}",
            1 + rng.below(28),
            1 + rng.below(12),
            d(rng, 2)
        );
        let status = rng.pick(&["A", "D", "V"]);
        format!("{talker}RMC,{time},{status},{lat},{ns},{lon},{ew},0.0,,{date},,,A")
    }
}

#[test]
fn new_reader_agrees_with_the_nmea_crate() {
    let logs = log_bodies();
    assert!(logs.len() > 30, "{} log sentences", logs.len());
    let mut rng = Rng(0x00D1_FFE2_E7C1_A110);
    let mut bodies = logs.clone();
    for _ in 0..40 {
        for body in &logs {
            bodies.push(mutate(&mut rng, body));
        }
    }
    let mutated = bodies.len();
    for _ in 0..30_000 {
        bodies.push(generated(&mut rng));
    }
    let (mut compared, mut accepted, mut accepted_mutated) = (0u32, 0u32, 0u32);
    let mut spread = Spread::default();
    let mut differences = Vec::new();
    for (i, body) in bodies.iter().enumerate() {
        let sentence = frame(body);
        // What the assembler can give out: at most 82 characters, no '*'.
        if sentence.len() > MAX_SENTENCE_LEN || body.contains('*') {
            continue;
        }
        compared += 1;
        let old = old_parse_sentence(&sentence);
        let new = parse_sentence(&sentence);
        if new.is_ok() {
            accepted += 1;
            if i < mutated {
                accepted_mutated += 1;
            }
        }
        if !same(&old, &new, &mut spread) {
            differences.push(format!("{sentence}\n  old {old:?}\n  new {new:?}"));
        }
    }
    println!(
        "differential: {compared} sentences ({} from logs, {} mutated, the rest generated), \
         {accepted} accepted ({accepted_mutated} of the logs and mutations), \
         largest angle difference {:e}°, {} altitudes not bitwise equal, {} differences",
        logs.len(),
        mutated - logs.len(),
        spread.angle_deg,
        spread.altitudes,
        differences.len()
    );
    for d in differences.iter().take(20) {
        println!("{d}");
    }
    assert!(differences.is_empty());
    assert!(accepted > compared / 4 && accepted < compared);
}
