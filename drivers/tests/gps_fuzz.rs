//! Property run of random and mutated byte streams through the sentence
//! assembler, the GGA/RMC reader and the fusion, and through the whole
//! [`GpsDecoder`].
//!
//! Properties: nothing panics; every accepted sentence starts with '$', is at
//! most 82 printable ASCII characters and has a right checksum by an
//! independent check (`common::checksum_is_right`); every unmutated sentence
//! is accepted (so the test fails if the assembler rejects all); every
//! checksum-valid impossible sentence injected on purpose (latitude 91..99°,
//! longitude 181..999°, minutes 60..99, a hemisphere letter other than N/S or
//! E/W, `nan`/`inf` spellings in a number, altitude outside −500..20,000 m,
//! hour/minute/second out of range, 30 February and other missing days, month
//! 0 or 13..99) is rejected as a parse error; and every fix the decoder gives
//! out (from `push`, `finish` and `current`) passes a plausibility check
//! written here independently of the driver (`fix_is_wrong`). The figures are
//! printed: `cargo test -p suntracker-drivers --test gps_fuzz -- --nocapture`.
//!
//! `fuzz_1m_streams` runs 1,000,000 streams (ignored by default:
//! `cargo test -p suntracker-drivers --test gps_fuzz -- --ignored --nocapture`; add
//! `--release`: about 12 s on the 2-core dev machine); `fuzz_20k_streams`, about
//! 2 s in a debug build, is the always-on smaller run
//! with another seed.

mod common;

use drivers::gps::{
    parse_sentence, FixFusion, FixQuality, GpsDecoder, GpsFix, SentenceAssembler, MAX_SENTENCE_LEN,
};

/// xorshift64* (Vigna 2016), deterministic and dependency-free.
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
}

const TALKERS: [&str; 6] = ["GP", "GN", "GL", "GA", "BD", "GB"];

fn digits(rng: &mut Rng, n: usize) -> String {
    (0..n)
        .map(|_| char::from(b'0' + rng.below(10) as u8))
        .collect()
}

fn field(rng: &mut Rng, good: impl FnOnce(&mut Rng) -> String) -> String {
    // Sometimes empty, sometimes junk, mostly plausible.
    match rng.below(20) {
        0 => String::new(),
        1 => {
            let n = rng.below(12);
            digits(rng, n)
        }
        2 => "-".to_owned() + &digits(rng, 3),
        3 => "nan".to_owned(),
        _ => good(rng),
    }
}

fn decimal(rng: &mut Rng, int: usize, frac: usize) -> String {
    let i = digits(rng, int);
    let f = digits(rng, frac);
    format!("{i}.{f}")
}

fn random_body(rng: &mut Rng) -> String {
    let talker = TALKERS[rng.below(TALKERS.len())];
    let time = field(rng, |r| decimal(r, 6, 2));
    let lat = field(rng, |r| decimal(r, 4, 5));
    let lon = field(rng, |r| decimal(r, 5, 5));
    let ns = ["N", "S", "", "X"][rng.below(4)];
    let ew = ["E", "W", "", "Q"][rng.below(4)];
    match rng.below(5) {
        0 | 1 => {
            let quality = rng.below(10);
            let sats = digits(rng, 2);
            let hdop = field(rng, |_| "1.02".to_owned());
            let alt = field(rng, |r| decimal(r, 3, 1));
            let geoid = field(rng, |_| "18.3".to_owned());
            format!("{talker}GGA,{time},{lat},{ns},{lon},{ew},{quality},{sats},{hdop},{alt},M,{geoid},M,,")
        }
        2 | 3 => {
            let status = ["A", "V", "D", ""][rng.below(4)];
            let speed = field(rng, |_| "0.012".to_owned());
            let date = field(rng, |r| digits(r, 6));
            let mode = ["A", "N", "D", ""][rng.below(4)];
            format!("{talker}RMC,{time},{status},{lat},{ns},{lon},{ew},{speed},,{date},,,{mode}")
        }
        _ => {
            let a = digits(rng, 2);
            let b = digits(rng, 2);
            format!("{talker}GSV,1,1,03,{a},{b},120,30")
        }
    }
}

fn frame(body: &str) -> Vec<u8> {
    let cs = body.bytes().fold(0u8, |a, b| a ^ b);
    format!("${body}*{cs:02X}\r\n").into_bytes()
}

fn mutate(rng: &mut Rng, bytes: &mut Vec<u8>) {
    for _ in 0..=rng.below(4) {
        if bytes.is_empty() {
            bytes.push(rng.next() as u8);
            continue;
        }
        let i = rng.below(bytes.len());
        match rng.below(6) {
            0 => bytes[i] ^= 1 << rng.below(8),
            1 => bytes[i] = rng.next() as u8,
            2 => bytes.insert(i, rng.next() as u8),
            3 => {
                bytes.remove(i);
            }
            4 => bytes.truncate(i),
            _ => {
                let junk = [b'$', b'*', b'\r', b'\n', b',', 0x80, 0xff][rng.below(7)];
                bytes.insert(i, junk)
            }
        }
    }
}

/// Gregorian days in a month, written here so as not to borrow the driver's.
fn month_days(year: u32, month: u32) -> u32 {
    let leap = (year.is_multiple_of(4) && !year.is_multiple_of(100)) || year.is_multiple_of(400);
    match month {
        4 | 6 | 9 | 11 => 30,
        2 if leap => 29,
        2 => 28,
        _ => 31,
    }
}

fn two(n: usize) -> String {
    format!("{n:02}")
}

fn between(rng: &mut Rng, lo: usize, hi: usize) -> usize {
    lo + rng.below(hi - lo + 1)
}

/// Plausible fields of one sentence; `impossible_body` spoils one of them.
struct Fields {
    time: String,
    lat: String,
    ns: String,
    lon: String,
    ew: String,
    alt: String,
    hdop: String,
    speed: String,
    date: String,
}

fn plausible_fields(rng: &mut Rng) -> Fields {
    let (h, m, s) = (rng.below(24), rng.below(60), rng.below(60));
    let frac = digits(rng, 2);
    let lat = format!(
        "{}{}.{}",
        two(rng.below(90)),
        two(rng.below(60)),
        digits(rng, 5)
    );
    let lon = format!(
        "{:03}{}.{}",
        rng.below(180),
        two(rng.below(60)),
        digits(rng, 5)
    );
    let alt = format!("{}.{}", between(rng, 0, 19_999) as i64 - 499, rng.below(10));
    let year = between(rng, 0, 99);
    let month = between(rng, 1, 12);
    let full_year = if year >= 83 { 1900 + year } else { 2000 + year } as u32;
    let day = between(rng, 1, month_days(full_year, month as u32) as usize);
    Fields {
        time: format!("{}{}{}.{frac}", two(h), two(m), two(s)),
        lat,
        ns: ["N", "S"][rng.below(2)].to_owned(),
        lon,
        ew: ["E", "W"][rng.below(2)].to_owned(),
        alt,
        hdop: format!("{}.{}", rng.below(10), digits(rng, 2)),
        speed: format!("{}.{}", rng.below(100), digits(rng, 3)),
        date: format!("{}{}{}", two(day), two(month), two(year)),
    }
}

const NON_FINITE: [&str; 9] = [
    "nan", "NaN", "NAN", "inf", "-inf", "+inf", "Infinity", "-nan", "INF",
];

/// A GGA (quality 1..8) or RMC (status A/D) with a right checksum and one
/// impossible field; without that field it would give a position.
fn impossible_body(rng: &mut Rng) -> String {
    let mut f = plausible_fields(rng);
    let mut gga = rng.below(2) == 0;
    let letters = b"ABCDFGHIJKLMOPQRTUVXYZnsew01-";
    match rng.below(13) {
        0 => {
            f.lat = format!(
                "{}{}.{}",
                between(rng, 91, 99),
                two(rng.below(60)),
                digits(rng, 3)
            )
        }
        1 => {
            f.lat = format!(
                "{}{}.{}",
                two(rng.below(91)),
                between(rng, 60, 99),
                digits(rng, 3)
            )
        }
        2 => {
            f.lon = format!(
                "{}{}.{}",
                between(rng, 181, 999),
                two(rng.below(60)),
                digits(rng, 3)
            )
        }
        3 => {
            f.lon = format!(
                "{:03}{}.{}",
                rng.below(181),
                between(rng, 60, 99),
                digits(rng, 3)
            )
        }
        4 => f.ns = char::from(letters[rng.below(letters.len())]).to_string(),
        5 => f.ew = char::from(letters[rng.below(letters.len())]).to_string(),
        6 => {
            let word = NON_FINITE[rng.below(NON_FINITE.len())].to_owned();
            match rng.below(6) {
                0 => f.lat = format!("{}{word}", two(rng.below(90))),
                1 => f.lon = format!("{:03}{word}", rng.below(180)),
                2 => {
                    gga = true;
                    f.alt = word
                }
                3 => {
                    gga = true;
                    f.hdop = word
                }
                4 => {
                    gga = false;
                    f.speed = word
                }
                _ => f.time = format!("{}{}{word}", two(rng.below(24)), two(rng.below(60))),
            }
        }
        7 => {
            gga = true;
            f.alt = if rng.below(2) == 0 {
                format!("-{}.{}", between(rng, 501, 9_999), rng.below(10))
            } else {
                format!("{}.{}", between(rng, 20_001, 99_999), rng.below(10))
            };
        }
        8 => {
            f.time = format!(
                "{}{}{}.00",
                between(rng, 24, 99),
                two(rng.below(60)),
                two(rng.below(60))
            )
        }
        9 => {
            f.time = format!(
                "{}{}{}.00",
                two(rng.below(24)),
                between(rng, 60, 99),
                two(rng.below(60))
            )
        }
        10 => {
            f.time = format!(
                "{}{}{}.00",
                two(rng.below(24)),
                two(rng.below(60)),
                between(rng, 60, 99)
            )
        }
        11 => {
            gga = false;
            let year = between(rng, 0, 99);
            let full_year = if year >= 83 { 1900 + year } else { 2000 + year } as u32;
            let (day, month) = match rng.below(4) {
                0 => (0, between(rng, 1, 12)),
                1 => {
                    let month = between(rng, 1, 12);
                    let first_missing = month_days(full_year, month as u32) as usize + 1;
                    (between(rng, first_missing, 99), month)
                }
                2 => (between(rng, 1, 28), [0, 13, 20, 99][rng.below(4)]),
                // 30 February, or 29 February of a year that has none.
                _ => {
                    let leap = month_days(full_year, 2) == 29;
                    (if leap { 30 } else { between(rng, 29, 30) }, 2)
                }
            };
            f.date = format!("{}{}{}", two(day), two(month), two(year));
        }
        _ => {
            if rng.below(2) == 0 {
                f.lat = format!("9000.{}{}", digits(rng, 2), between(rng, 1, 9));
            } else {
                f.lon = format!("18000.{}{}", digits(rng, 2), between(rng, 1, 9));
            }
        }
    }
    let talker = TALKERS[rng.below(TALKERS.len())];
    let Fields {
        time,
        lat,
        ns,
        lon,
        ew,
        alt,
        hdop,
        speed,
        date,
    } = f;
    if gga {
        let quality = between(rng, 1, 8);
        format!("{talker}GGA,{time},{lat},{ns},{lon},{ew},{quality},08,{hdop},{alt},M,18.3,M,,")
    } else {
        let status = ["A", "D"][rng.below(2)];
        format!("{talker}RMC,{time},{status},{lat},{ns},{lon},{ew},{speed},,{date},,,A")
    }
}

/// Why a fix the decoder gave out cannot be true, checked without the
/// driver's own code: `None` when it is plausible.
fn fix_is_wrong(fix: &GpsFix) -> Option<&'static str> {
    if fix.latitude_deg.is_some() != fix.longitude_deg.is_some() {
        return Some("half a position");
    }
    if let Some(lat) = fix.latitude_deg.map(|c| c.deg::<f64>()) {
        if !lat.is_finite() || lat.abs() > 90.0 {
            return Some("latitude");
        }
    }
    if let Some(lon) = fix.longitude_deg.map(|c| c.deg::<f64>()) {
        if !lon.is_finite() || lon.abs() > 180.0 {
            return Some("longitude");
        }
    }
    if let Some(alt) = fix.altitude_m {
        if !alt.is_finite() || !(-500.0..=20_000.0).contains(&alt) {
            return Some("altitude");
        }
        if !fix.has_position() {
            return Some("altitude without a position");
        }
    }
    if fix.has_position() && fix.quality == FixQuality::Invalid {
        return Some("position with quality Invalid");
    }
    if fix.utc.is_some() != fix.utc_received_ms.is_some() {
        return Some("utc_received_ms without utc or the reverse");
    }
    if let Some(t) = fix.utc {
        let (y, mo, d) = (
            u32::from(t.year()),
            u32::from(t.month()),
            u32::from(t.day()),
        );
        if !(1983..=2082).contains(&y) || !(1..=12).contains(&mo) || d == 0 || d > month_days(y, mo)
        {
            return Some("date");
        }
        if t.hour() > 23 || t.minute() > 59 || t.second() > 59 || t.millis() > 999 {
            return Some("time of day");
        }
    }
    None
}

/// What a piece of a stream is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Piece {
    /// Noise or a sentence of unknown validity.
    Other,
    /// Unmutated, short enough: must be accepted by the assembler.
    MustAccept,
    /// Checksum right, framing right, content impossible: must be rejected
    /// as a parse error.
    Impossible,
}

/// Builds one stream as pieces.
fn stream(rng: &mut Rng) -> Vec<(Vec<u8>, Piece)> {
    let mut out = Vec::new();
    for _ in 0..=rng.below(3) {
        let piece = match rng.below(13) {
            // Pure noise.
            0 => (
                (0..rng.below(120)).map(|_| rng.next() as u8).collect(),
                Piece::Other,
            ),
            // Mutated after framing: mostly bad checksums.
            1..=3 => {
                let mut s = frame(&random_body(rng));
                mutate(rng, &mut s);
                (s, Piece::Other)
            }
            // Mutated body, checksum recomputed: exercises the parser.
            4..=5 => {
                let mut body = random_body(rng).into_bytes();
                mutate(rng, &mut body);
                let body: String = body
                    .into_iter()
                    .filter(|b| (0x20..0x7f).contains(b) && !matches!(b, b'$' | b'*'))
                    .map(char::from)
                    .collect();
                let kind = if body.len() + 4 <= MAX_SENTENCE_LEN {
                    Piece::MustAccept
                } else {
                    Piece::Other
                };
                (frame(&body), kind)
            }
            // Checksum-valid impossible sentence.
            6..=7 => {
                let body = impossible_body(rng);
                let kind = if body.len() + 4 <= MAX_SENTENCE_LEN {
                    Piece::Impossible
                } else {
                    Piece::Other
                };
                (frame(&body), kind)
            }
            // A plausible epoch, GGA then RMC with the same time: fixes with
            // positions for the check to look at.
            8..=9 => {
                let Fields {
                    time,
                    lat,
                    ns,
                    lon,
                    ew,
                    alt,
                    hdop,
                    speed,
                    date,
                } = plausible_fields(rng);
                let talker = TALKERS[rng.below(TALKERS.len())];
                let quality = rng.below(9);
                let status = ["A", "D", "V"][rng.below(3)];
                out.push((
                    frame(&format!(
                        "{talker}GGA,{time},{lat},{ns},{lon},{ew},{quality},08,{hdop},{alt},M,18.3,M,,"
                    )),
                    Piece::MustAccept,
                ));
                (
                    frame(&format!(
                        "{talker}RMC,{time},{status},{lat},{ns},{lon},{ew},{speed},,{date},,,A"
                    )),
                    Piece::MustAccept,
                )
            }
            // Clean sentence.
            _ => {
                let body = random_body(rng);
                let kind = if body.len() + 4 <= MAX_SENTENCE_LEN {
                    Piece::MustAccept
                } else {
                    Piece::Other
                };
                (frame(&body), kind)
            }
        };
        out.push(piece);
    }
    out
}

/// The figures of one run.
#[derive(Debug, Default)]
struct Figures {
    streams: u64,
    sentences: u64,
    accepted: u64,
    parsed: u64,
    fixes: u64,
    fixes_with_position: u64,
    impossible_injected: u64,
    impossible_rejected: u64,
    parse_errors: u64,
    wrong_fixes: u64,
}

fn check_fix(fix: &GpsFix, figures: &mut Figures, context: &[u8]) {
    figures.fixes += 1;
    if fix.has_position() {
        figures.fixes_with_position += 1;
    }
    if let Some(why) = fix_is_wrong(fix) {
        figures.wrong_fixes += 1;
        eprintln!(
            "wrong fix ({why}): {fix:?}\n  from {:?}",
            String::from_utf8_lossy(context)
        );
    }
}

fn run(seed: u64, streams: usize) -> Figures {
    let mut rng = Rng(seed);
    let mut figures = Figures::default();
    for _ in 0..streams {
        let pieces = stream(&mut rng);
        let bytes: Vec<u8> = pieces.iter().flat_map(|(b, _)| b.iter().copied()).collect();
        let must_accept = pieces
            .iter()
            .filter(|(_, k)| *k == Piece::MustAccept)
            .count();
        let mut assembler = SentenceAssembler::new();
        let mut fusion = FixFusion::new(1000);
        let mut decoder = GpsDecoder::new(1000);
        let mut accepted = 0;
        let mut t = 0u32;
        for (piece, kind) in &pieces {
            let parse_errors_before = decoder.stats().parse_errors;
            for &b in piece {
                t += 1;
                if let Some(Ok(s)) = assembler.push(b) {
                    assert!(s.len() <= MAX_SENTENCE_LEN, "{s:?}");
                    assert!(s.bytes().all(|c| (0x20..0x7f).contains(&c)), "{s:?}");
                    assert!(common::checksum_is_right(s), "accepted bad checksum {s:?}");
                    accepted += 1;
                    if let Ok(parsed) = parse_sentence(s) {
                        figures.parsed += 1;
                        if let Some(fix) = fusion.update(&parsed, t) {
                            assert_eq!(fix_is_wrong(&fix), None, "{fix:?} from {s:?}");
                        }
                    }
                }
                if let Some(fix) = decoder.push(b, t) {
                    check_fix(&fix, &mut figures, &bytes);
                }
            }
            if *kind == Piece::Impossible {
                figures.impossible_injected += 1;
                if decoder.stats().parse_errors == parse_errors_before + 1 {
                    figures.impossible_rejected += 1;
                } else {
                    eprintln!(
                        "impossible sentence not rejected: {:?}",
                        String::from_utf8_lossy(piece)
                    );
                }
            }
        }
        assembler.finish_stream();
        let _ = fusion.flush();
        let _ = fusion.current(t);
        if let Some(fix) = decoder.finish() {
            check_fix(&fix, &mut figures, &bytes);
        }
        assert_eq!(fix_is_wrong(&decoder.current(t)), None);
        assert!(
            accepted >= must_accept,
            "accepted {accepted} < {must_accept} in {:?}",
            String::from_utf8_lossy(&bytes)
        );
        assert_eq!(assembler.stats().accepted, accepted as u32);
        let stats = decoder.stats();
        assert_eq!(stats.framing, assembler.stats());
        figures.streams += 1;
        figures.sentences += u64::from(stats.sentences);
        figures.accepted += accepted as u64;
        figures.parse_errors += u64::from(stats.parse_errors);
    }
    figures
}

fn report(figures: &Figures, seconds: f64) {
    println!(
        "gps_fuzz: {} streams fuzzed, {} sentences ({} with a right checksum, {} parsed), \
         {} fixes given out ({} with a position), {} impossible sentences injected, \
         {} of them rejected, {} parse errors in all, {} wrong fixes accepted ({seconds:.1} s)",
        figures.streams,
        figures.sentences,
        figures.accepted,
        figures.parsed,
        figures.fixes,
        figures.fixes_with_position,
        figures.impossible_injected,
        figures.impossible_rejected,
        figures.parse_errors,
        figures.wrong_fixes,
    );
}

fn check(figures: &Figures, streams: u64) {
    assert_eq!(figures.streams, streams);
    assert_eq!(figures.wrong_fixes, 0, "{figures:?}");
    assert_eq!(
        figures.impossible_rejected, figures.impossible_injected,
        "{figures:?}"
    );
    // The generator makes plenty of valid, parseable and impossible sentences,
    // and plenty of fixes with a position.
    assert!(figures.accepted > streams, "{figures:?}");
    assert!(figures.parsed > streams / 4, "{figures:?}");
    assert!(figures.impossible_injected > streams / 4, "{figures:?}");
    assert!(figures.fixes_with_position > streams / 20, "{figures:?}");
}

#[test]
fn fuzz_20k_streams() {
    let t0 = std::time::Instant::now();
    let figures = run(0x5EED_0001, 20_000);
    report(&figures, t0.elapsed().as_secs_f64());
    check(&figures, 20_000);
}

#[test]
#[ignore = "1,000,000 streams: run with -- --ignored --nocapture"]
fn fuzz_1m_streams() {
    let t0 = std::time::Instant::now();
    let figures = run(0x5EED_1000_0000, 1_000_000);
    report(&figures, t0.elapsed().as_secs_f64());
    check(&figures, 1_000_000);
}

#[test]
fn impossible_generator_sentences_are_framed_and_rejected() {
    // Guard on the generator itself: its sentences are well framed and, apart
    // from the spoiled field, plausible (the same generator without the spoiling
    // gives positions; see plausible_fields_give_positions).
    let mut rng = Rng(7);
    for _ in 0..1_000 {
        let body = impossible_body(&mut rng);
        let s = String::from_utf8(frame(&body)).unwrap();
        let s = s.trim_end();
        assert!(common::checksum_is_right(s), "{s}");
        assert!(parse_sentence(s).is_err(), "{s}");
    }
}

#[test]
fn plausible_fields_give_positions() {
    let mut rng = Rng(8);
    for _ in 0..1_000 {
        let Fields {
            time,
            lat,
            ns,
            lon,
            ew,
            alt,
            hdop,
            speed,
            date,
        } = plausible_fields(&mut rng);
        let gga = format!("GPGGA,{time},{lat},{ns},{lon},{ew},1,08,{hdop},{alt},M,18.3,M,,");
        let rmc = format!("GPRMC,{time},A,{lat},{ns},{lon},{ew},{speed},,{date},,,A");
        for body in [gga, rmc] {
            let s = String::from_utf8(frame(&body)).unwrap();
            let parsed = parse_sentence(s.trim_end());
            assert!(
                matches!(parsed, Ok(drivers::gps::Sentence::Gga(g)) if g.latitude_deg.is_some())
                    || matches!(parsed, Ok(drivers::gps::Sentence::Rmc(r)) if r.utc.is_some() && r.latitude_deg.is_some()),
                "{s} -> {parsed:?}"
            );
        }
    }
}
