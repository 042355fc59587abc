//! The golden log tests/data/gps_golden_mixed.nmea (see make_golden.py there)
//! through the whole pipeline. Expected values are read off the sentences by
//! hand: ddmm.mmmm -> dd + mm.mmmm / 60, S and W negative.

mod common;

use common::MockSerial;
use drivers::gps::{FixQuality, GpsDecoder, GpsFix, GpsReader};
use drivers::time::DateTime;

const LOG: &[u8] = include_bytes!("data/gps_golden_mixed.nmea");

fn utc(h: u8, m: u8, s: u8) -> Option<DateTime> {
    Some(DateTime::new(2024, 6, 15, h, m, s).unwrap())
}

fn pos(fix: &GpsFix) -> Option<(f64, f64)> {
    Some((fix.latitude_deg?.deg(), fix.longitude_deg?.deg()))
}

fn close(a: Option<(f64, f64)>, b: (f64, f64)) -> bool {
    a.is_some_and(|(x, y)| (x - b.0).abs() < 1e-9 && (y - b.1).abs() < 1e-9)
}

fn run_reader(chunk: usize) -> (Vec<GpsFix>, drivers::gps::GpsStats) {
    let mut reader = GpsReader::new(MockSerial::new(LOG, chunk), 2_000);
    let mut fixes = Vec::new();
    let mut now_ms = 0;
    loop {
        now_ms += 1;
        match reader.poll(now_ms) {
            Ok(Some(fix)) => fixes.push(fix),
            Ok(None) => {}
            Err(drivers::gps::Error::EndOfStream) => break,
            Err(e) => panic!("{e:?}"),
        }
    }
    (fixes, reader.stats())
}

#[test]
fn golden_log_fixes() {
    let (fixes, _) = run_reader(7);
    assert_eq!(fixes.len(), 10, "{fixes:#?}");

    // Cold start: nothing but the satellite count 00.
    assert_eq!(
        fixes[0],
        GpsFix {
            satellites: Some(0),
            ..GpsFix::NONE
        }
    );

    // 03:15:00, RMC V with date: time without position.
    assert_eq!(fixes[1].utc, utc(3, 15, 0));
    assert_eq!(pos(&fixes[1]), None);
    assert_eq!(fixes[1].quality, FixQuality::Invalid);
    assert_eq!(fixes[1].satellites, Some(3));
    assert_eq!(fixes[1].altitude_m, None);

    // 03:15:01, GN: 3734.00200N 12658.99800E -> 37.5667, 126.9833.
    assert_eq!(fixes[2].utc, utc(3, 15, 1));
    assert!(close(pos(&fixes[2]), (37.5667, 126.9833)));
    assert_eq!(fixes[2].altitude_m, Some(38.5));
    assert_eq!(fixes[2].quality, FixQuality::Gps);
    assert_eq!(fixes[2].satellites, Some(8));

    // 03:15:02, GP, DGPS: 34.0026/60 = 0.56671.
    assert_eq!(fixes[3].utc, utc(3, 15, 2));
    assert!(close(pos(&fixes[3]), (37.56671, 126.9833)));
    assert_eq!(fixes[3].quality, FixQuality::Dgps);
    assert_eq!(fixes[3].satellites, Some(10));
    assert_eq!(fixes[3].altitude_m, Some(38.7));

    // 03:15:03, BD: 34.003/60, 58.997/60.
    assert_eq!(fixes[4].utc, utc(3, 15, 3));
    assert!(close(
        pos(&fixes[4]),
        (37.0 + 34.003 / 60.0, 126.0 + 58.997 / 60.0)
    ));
    assert_eq!(fixes[4].satellites, Some(7));

    // 03:15:04, GL.
    assert_eq!(fixes[5].utc, utc(3, 15, 4));
    assert!(close(
        pos(&fixes[5]),
        (37.0 + 34.003 / 60.0, 126.0 + 58.996 / 60.0)
    ));
    assert_eq!(fixes[5].altitude_m, Some(39.0));

    // 03:15:05, GA: the RMC had a bad checksum, so no date-time; GGA position.
    assert_eq!(fixes[6].utc, None);
    assert!(close(pos(&fixes[6]), (37.0 + 34.003 / 60.0, 126.98325)));
    assert_eq!(fixes[6].altitude_m, Some(39.1));
    assert_eq!(fixes[6].satellites, Some(5));

    // 03:15:06: fix lost, time kept.
    assert_eq!(fixes[7].utc, utc(3, 15, 6));
    assert_eq!(pos(&fixes[7]), None);
    assert_eq!(fixes[7].quality, FixQuality::Invalid);
    assert_eq!(fixes[7].satellites, Some(2));

    // 03:15:07: GGA unparseable, RMC alone: position, no altitude, no count.
    assert_eq!(fixes[8].utc, utc(3, 15, 7));
    assert!(close(pos(&fixes[8]), (37.0 + 34.003 / 60.0, 126.98325)));
    assert_eq!(fixes[8].altitude_m, None);
    assert_eq!(fixes[8].quality, FixQuality::Gps);
    assert_eq!(fixes[8].satellites, None);

    // 2024-12-31 23:59:59.50, 33 51.5 S, 151 12.5 W.
    let t = DateTime::new(2024, 12, 31, 23, 59, 59)
        .unwrap()
        .with_millis(500)
        .unwrap();
    assert_eq!(fixes[9].utc, Some(t));
    assert!(close(
        pos(&fixes[9]),
        (-(33.0 + 51.5 / 60.0), -(151.0 + 12.5 / 60.0))
    ));
    assert_eq!(fixes[9].altitude_m, Some(-12.5));
    assert_eq!(fixes[9].satellites, Some(9));
}

#[test]
fn golden_log_counters() {
    // Counted by hand from make_golden.py: 33 lines; 27 frame correctly, one of
    // them (the GGA with quality 'X') does not parse; 1 bad checksum; other
    // rejections: no '$', overflow, cut by '$', non-ASCII, cut by end of log.
    let (_, stats) = run_reader(5);
    assert_eq!(stats.sentences, 33);
    assert_eq!(stats.accepted, 26);
    assert_eq!(stats.rejected_checksum, 1);
    assert_eq!(stats.rejected_other, 6);
    assert_eq!(stats.parse_errors, 1);
    assert_eq!(stats.framing.missing_start, 1);
    assert_eq!(stats.framing.overflow, 1);
    assert_eq!(stats.framing.partial, 2);
    assert_eq!(stats.framing.non_ascii, 1);
}

#[test]
fn chunk_size_does_not_matter() {
    // Only the receive times differ: run_reader's clock ticks once per poll,
    // and a bigger chunk needs fewer polls.
    fn without_receive_time(fixes: Vec<GpsFix>) -> Vec<GpsFix> {
        fixes
            .into_iter()
            .map(|f| {
                assert_eq!(f.utc.is_some(), f.utc_received_ms.is_some(), "{f:?}");
                GpsFix {
                    utc_received_ms: None,
                    ..f
                }
            })
            .collect()
    }
    let (one, s1) = run_reader(1);
    let (big, s2) = run_reader(64);
    assert_eq!(without_receive_time(one), without_receive_time(big));
    assert_eq!(s1, s2);
}

#[test]
fn read_errors_are_comm_errors() {
    let mut reader = GpsReader::new(MockSerial::new(LOG, 8).failing_reads(), 1000);
    assert!(matches!(reader.poll(0), Err(drivers::gps::Error::Comm(_))));
    let _serial: MockSerial = reader.destroy();
}

#[test]
fn fix_goes_stale_after_silence() {
    let mut d = GpsDecoder::new(1_500);
    let mut last = None;
    for line in [
        "$GNRMC,031501.00,A,3734.00200,N,12658.99800,E,0.012,,150624,,,A*6E\r\n",
        "$GNGGA,031501.00,3734.00200,N,12658.99800,E,1,08,1.02,38.5,M,18.3,M,,*7A\r\n",
    ] {
        for &b in line.as_bytes() {
            if let Some(f) = d.push(b, 10_000) {
                last = Some(f);
            }
        }
    }
    let fix = last.expect("epoch complete after GGA + RMC");
    assert!(fix.has_position());
    assert_eq!(d.current(10_000), fix);
    assert_eq!(d.current(11_500), fix);
    assert!(!d.is_stale(11_500));
    assert!(d.is_stale(11_501));
    assert_eq!(d.current(11_501), GpsFix::NONE);
    // Forgotten once found stale: 2^32 ms later (the 32-bit clock has come
    // round to the same reading) it does not come back.
    assert_eq!(
        d.current(10_000u32.wrapping_add(u32::MAX).wrapping_add(1)),
        GpsFix::NONE
    );
    assert!(d.is_stale(10_000));
    // Before any epoch: stale.
    assert!(GpsDecoder::new(1_500).is_stale(0));
}

#[test]
fn ages_and_staleness_run_across_the_32_bit_wrap() {
    // The epoch is completed 300 ms before the monotonic clock wraps.
    let rmc = framed("GNRMC,031501.00,A,3734.00200,N,12658.99800,E,0.012,,150624,,,A");
    let gga = framed("GNGGA,031501.00,3734.00200,N,12658.99800,E,1,08,1.02,38.5,M,18.3,M,,");
    let before_wrap = u32::MAX - 299;
    let (fixes, _, mut d) = decode_lines(&[rmc.as_str(), gga.as_str()], &[before_wrap; 2]);
    let fix = fixes[0];
    // 1,000 ms later the clock reads 700: the fix is 1,000 ms old and fresh.
    assert_eq!(fix.utc_age_ms(700), Some(1_000));
    assert_eq!(d.current(700), fix);
    // The decoder's 60 s limit, counted across the wrap.
    assert_eq!(d.current(59_700), fix);
    assert_eq!(d.current(59_701), GpsFix::NONE);
}

#[test]
fn poll_if_ready_does_not_block_on_an_idle_port() {
    // An empty port that is "not ready": poll_if_ready must not read (a read
    // here would report end of stream).
    let mut reader = GpsReader::new(MockSerial::new(&[], 8), 1000);
    assert_eq!(reader.poll_if_ready(0), Ok(None));
    assert_eq!(reader.poll(0), Err(drivers::gps::Error::EndOfStream));
    // With data, it gets the same fixes as poll.
    let mut reader = GpsReader::new(MockSerial::new(LOG, 16), 1000);
    let mut n = 0;
    while let Ok(r) = reader.poll_if_ready(0) {
        if r.is_some() {
            n += 1;
        }
        if reader.stats().sentences >= 32 {
            break;
        }
    }
    assert_eq!(n, 10);
}

/// Feeds `lines` (one sentence each, CR LF added) to a decoder, line `i` at
/// `now_ms[i]`; returns the fixes (with the end-of-log flush) and, per line,
/// whether it was rejected as a parse error.
fn decode_lines(lines: &[&str], now_ms: &[u32]) -> (Vec<GpsFix>, Vec<bool>, GpsDecoder) {
    let mut d = GpsDecoder::new(60_000);
    let mut fixes = Vec::new();
    let mut rejected = Vec::new();
    for (line, &t) in lines.iter().zip(now_ms) {
        let before = d.stats().parse_errors;
        for &b in line.as_bytes().iter().chain(b"\r\n") {
            fixes.extend(d.push(b, t));
        }
        rejected.push(d.stats().parse_errors > before);
    }
    fixes.extend(d.finish());
    (fixes, rejected, d)
}

const IMPOSSIBLE_LOG: &str = include_str!("data/gps_impossible.nmea");

/// The lines of gps_impossible.nmea that are impossible (see make_golden.py):
/// 91°, 90°00.5', 200°, 180°00.1' W, minutes 60 and 99, hemisphere X, nan and
/// inf minutes, altitude nan / 25 km / −600 m, HDOP NaN, negative minutes,
/// an exponent, hour 24, minute 60, second 60 (leap second, rejected by
/// design), second 61, 31 June, 29 Feb 2023, 30 Feb 2024, month 13, month 0,
/// day 0, speed inf, course -nan, 95° S.
const IMPOSSIBLE_LINES: std::ops::RangeInclusive<usize> = 1..=28;

#[test]
fn impossible_log_rejects_exactly_the_impossible_lines() {
    let lines: Vec<&str> = IMPOSSIBLE_LOG.lines().collect();
    assert_eq!(lines.len(), 35);
    let now_ms: Vec<u32> = (0..35).map(|i| 1_000 * i).collect();
    let (_, rejected, d) = decode_lines(&lines, &now_ms);
    let rejected_lines: Vec<usize> = (0..35).filter(|&i| rejected[i]).collect();
    assert_eq!(rejected_lines, IMPOSSIBLE_LINES.collect::<Vec<_>>());
    let stats = d.stats();
    assert_eq!(stats.sentences, 35);
    assert_eq!(stats.accepted, 7);
    assert_eq!(stats.rejected_checksum, 0);
    assert_eq!(stats.parse_errors, 28);
    assert_eq!(stats.rejected_other, 28);
}

#[test]
fn impossible_log_gives_positions_only_from_the_possible_lines() {
    let lines: Vec<&str> = IMPOSSIBLE_LOG.lines().collect();
    let now_ms: Vec<u32> = (0..35).map(|i| 1_000 * i).collect();
    let (fixes, _, _) = decode_lines(&lines, &now_ms);
    let lat0 = 37.0 + 34.003 / 60.0;
    let lon0 = 126.0 + 58.995 / 60.0;
    // Lines 0 and 29..=34, in order; nothing from lines 1..=28.
    let expected: [((f64, f64), Option<f32>); 7] = [
        ((lat0, lon0), Some(39.0)),
        ((90.0, lon0), Some(39.0)),
        ((lat0, -180.0), Some(39.0)),
        ((37.0 + 59.99999 / 60.0, lon0), Some(-500.0)),
        ((lat0, lon0), Some(20_000.0)),
        ((lat0, lon0), None),
        ((0.0, 0.0), None),
    ];
    assert_eq!(fixes.len(), expected.len(), "{fixes:#?}");
    for (fix, (position, altitude_m)) in fixes.iter().zip(expected) {
        assert!(close(pos(fix), position), "{fix:?}");
        assert_eq!(fix.altitude_m, altitude_m, "{fix:?}");
        assert_ne!(fix.quality, FixQuality::Invalid);
    }
    let leap_day = DateTime::new(2024, 2, 29, 23, 59, 59)
        .unwrap()
        .with_millis(990)
        .unwrap();
    assert_eq!(fixes[5].utc, Some(leap_day));
    assert_eq!(fixes[5].utc_received_ms, Some(33_000));
    assert_eq!(
        fixes[6].utc,
        Some(DateTime::new(2025, 3, 1, 0, 0, 0).unwrap())
    );
    assert_eq!(fixes[6].utc_received_ms, Some(34_000));
}

/// Checksum-valid sentences, written with `common::frame`-style checksums
/// computed here so that the bodies stay readable.
fn framed(body: &str) -> String {
    let cs = body.bytes().fold(0u8, |a, b| a ^ b);
    format!("${body}*{cs:02X}")
}

#[test]
fn rmc_v_never_gives_a_position_or_a_time_that_looks_trusted() {
    // Some receivers repeat the last known position with status V.
    let rmc_v = framed("GNRMC,031510.00,V,3734.00300,N,12658.99500,E,0.010,,150624,,,N");
    let gga_1 = framed("GNGGA,031510.00,3734.00300,N,12658.99500,E,1,08,1.02,38.5,M,18.3,M,,");
    let rmc_a = framed("GNRMC,031511.00,A,3734.00300,N,12658.99500,E,0.010,,150624,,,A");
    let gga_0 = framed("GNGGA,031511.00,3734.00300,N,12658.99500,E,0,08,1.02,38.5,M,18.3,M,,");
    let rmc_v_alone = framed("GNRMC,031512.00,V,3734.00300,N,12658.99500,E,0.010,,150624,,,N");
    let lines = [
        rmc_v.as_str(),
        gga_1.as_str(),
        rmc_a.as_str(),
        gga_0.as_str(),
        rmc_v_alone.as_str(),
    ];
    let (fixes, rejected, _) = decode_lines(&lines, &[100, 140, 1_100, 1_140, 2_100]);
    assert!(rejected.iter().all(|r| !r));
    assert_eq!(fixes.len(), 3, "{fixes:#?}");
    for fix in &fixes {
        assert!(!fix.has_position(), "{fix:?}");
        assert_eq!(fix.altitude_m, None);
        assert_eq!(fix.quality, FixQuality::Invalid, "{fix:?}");
        assert!(fix.utc.is_some());
    }
    // RMC V + GGA 1 in one epoch: the time is the receiver's, flagged invalid.
    assert_eq!(fixes[0].utc, utc(3, 15, 10));
    assert_eq!(fixes[0].satellites, Some(8));
    // RMC A + GGA 0: the receivers' two statements disagree; no fix either.
    assert_eq!(fixes[1].utc, utc(3, 15, 11));
    assert_eq!(fixes[2].utc, utc(3, 15, 12));
}

#[test]
fn utc_received_ms_is_when_the_rmc_was_completed() {
    let rmc = framed("GNRMC,031501.00,A,3734.00200,N,12658.99800,E,0.012,,150624,,,A");
    let gga = framed("GNGGA,031501.00,3734.00200,N,12658.99800,E,1,08,1.02,38.5,M,18.3,M,,");
    let gga_alone = framed("GNGGA,031502.00,3734.00200,N,12658.99800,E,1,08,1.02,38.5,M,18.3,M,,");
    let lines = [rmc.as_str(), gga.as_str(), gga_alone.as_str()];
    let (fixes, _, mut d) = decode_lines(&lines, &[10_000, 10_040, 11_000]);
    assert_eq!(fixes.len(), 2);
    let fix = fixes[0];
    assert!(fix.has_position());
    assert_eq!(fix.utc, utc(3, 15, 1));
    // Not the GGA's 10_040, which completed the epoch: the RMC carried the time.
    assert_eq!(fix.utc_received_ms, Some(10_000));
    // A fix handed on 2.9 s late says it is 2.9 s old.
    assert_eq!(fix.utc_age_ms(12_900), Some(2_900));
    assert_eq!(fix.utc_age_ms(10_000), Some(0));
    // A clock that went backwards reads as nearly 2^32 ms old: never fresh.
    assert_eq!(fix.utc_age_ms(9_000), Some(u32::MAX - 999));
    // GGA alone: a position, but no date-time and so no age.
    assert!(fixes[1].has_position());
    assert_eq!(fixes[1].utc, None);
    assert_eq!(fixes[1].utc_received_ms, None);
    assert_eq!(fixes[1].utc_age_ms(20_000), None);
    assert_eq!(GpsFix::NONE.utc_received_ms, None);
    assert_eq!(GpsFix::NONE.utc_age_ms(u32::MAX), None);
    assert_eq!(d.current(11_000), fixes[1]);
}

#[test]
fn golden_log_receive_times() {
    // Every fix with a date-time says when its RMC arrived, and only those.
    let (fixes, _) = run_reader(7);
    for fix in &fixes {
        assert_eq!(fix.utc.is_some(), fix.utc_received_ms.is_some(), "{fix:?}");
    }
    let times: Vec<u32> = fixes.iter().filter_map(|f| f.utc_received_ms).collect();
    assert!(times.windows(2).all(|w| w[0] < w[1]), "{times:?}");
}
