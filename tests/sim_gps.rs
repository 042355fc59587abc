//! `sim::gps::GpsReceiverModel`: its NMEA text goes through the drivers'
//! `GpsDecoder` (good fix, no fix, rollover date, stepped time), and the
//! text of impossible positions is checked as written.

use drivers::gps::{nmea_checksum, FixQuality, GpsDecoder, GpsFix};
use drivers::time::DateTime;
use sim::gps::{GpsModelError, GpsReceiverModel, EPOCH_BUF_LEN};
use sun_algos::UtcTime;

/// Kano, Nigeria, and a south-western site, to exercise both hemispheres.
const KANO: (f64, f64, f64) = (11.968_3, 8.426_1, 480.0);
const SOUTH_WEST: (f64, f64, f64) = (-33.456_789, -70.654_321, 570.5);

fn utc(y: i32, mo: u8, d: u8, h: u8, mi: u8, s: u8) -> UtcTime {
    UtcTime::from_ymd_hms(y, mo, d, h, mi, s).unwrap()
}

fn epoch_text(model: &GpsReceiverModel, now: UtcTime) -> String {
    let mut buf = [0u8; EPOCH_BUF_LEN];
    let n = model.epoch(now, &mut buf).unwrap();
    String::from_utf8(buf[..n].to_vec()).unwrap()
}

/// Feeds the text to a fresh decoder; returns the fixes and the decoder.
fn decode(text: &str) -> (Vec<GpsFix>, GpsDecoder) {
    let mut decoder = GpsDecoder::new(5_000);
    let fixes = text
        .bytes()
        .filter_map(|b| decoder.push(b, 0))
        .collect::<Vec<_>>();
    (fixes, decoder)
}

/// The one fix of an epoch, checking that both sentences were accepted.
fn decode_one(text: &str) -> GpsFix {
    let (fixes, decoder) = decode(text);
    let stats = decoder.stats();
    assert_eq!(stats.accepted, 2, "{text}\n{stats:?}");
    assert_eq!(
        stats.rejected_checksum + stats.rejected_other,
        0,
        "{stats:?}"
    );
    assert_eq!(fixes.len(), 1, "{text}");
    fixes[0]
}

/// Splits `$BODY*hh` lines, checks each checksum and returns the fields.
fn sentences(text: &str) -> Vec<Vec<String>> {
    assert!(text.ends_with("\r\n"));
    text.split_terminator("\r\n")
        .map(|line| {
            let (body, hex) = line[1..].split_once('*').unwrap();
            assert!(line.starts_with('$'));
            let sum = u8::from_str_radix(hex, 16).unwrap();
            assert_eq!(sum, nmea_checksum(body.as_bytes()), "{line}");
            assert_eq!(hex, hex.to_uppercase());
            body.split(',').map(str::to_owned).collect()
        })
        .collect()
}

#[test]
fn good_epoch_gives_position_time_and_altitude() {
    for (lat, lon, alt) in [KANO, SOUTH_WEST] {
        let model = GpsReceiverModel::new(lat, lon, alt);
        let now = UtcTime::from_ymd_hms_milli(2025, 12, 1, 13, 14, 15, 500).unwrap();
        let text = epoch_text(&model, now);
        let fix = decode_one(&text);
        assert_eq!(fix.quality, FixQuality::Gps);
        assert!(
            (fix.latitude_deg.unwrap().deg::<f64>() - lat).abs() < 1e-6,
            "{text}"
        );
        assert!(
            (fix.longitude_deg.unwrap().deg::<f64>() - lon).abs() < 1e-6,
            "{text}"
        );
        assert!((f64::from(fix.altitude_m.unwrap()) - alt).abs() < 0.05);
        assert_eq!(fix.satellites, Some(8));
        let expected = DateTime::new(2025, 12, 1, 13, 14, 15)
            .unwrap()
            .with_millis(500)
            .unwrap();
        assert_eq!(fix.utc, Some(expected));
    }
}

#[test]
fn sentence_text_is_rmc_then_gga_with_checksums() {
    let model = GpsReceiverModel::new(KANO.0, KANO.1, KANO.2);
    let text = epoch_text(&model, utc(2026, 3, 20, 6, 7, 8));
    // 11.9683° = 11° 58.0980', 8.4261° = 8° 25.5660'; checksums from
    // Python: functools.reduce(lambda a, c: a ^ ord(c), body, 0).
    assert_eq!(
        text,
        "$GPRMC,060708.00,A,1158.0980,N,00825.5660,E,0.0,,200326,,,A*7A\r\n\
         $GPGGA,060708.00,1158.0980,N,00825.5660,E,1,08,0.9,480.0,M,0.0,M,,*5E\r\n"
    );
    sentences(&text);
}

#[test]
fn positions_round_to_the_nearest_ten_thousandth_minute_with_carry() {
    let mut model = GpsReceiverModel::new(0.0, 0.0, 0.0);
    // 10° 59.99999' rounds up to 11° 00.0000'; -0.0 stays north/east.
    model.position_override = Some((10.0 + 59.999_99 / 60.0, -0.0));
    let s = sentences(&epoch_text(&model, utc(2026, 1, 1, 0, 0, 0)));
    assert_eq!(s[0][3..7], ["1100.0000", "N", "00000.0000", "E"]);
    assert_eq!(s[1][2..6], ["1100.0000", "N", "00000.0000", "E"]);
}

#[test]
fn whole_day_of_epochs_decodes_within_1e_6_degrees() {
    // A different fractional position every minute of a day.
    let mut model = GpsReceiverModel::new(0.0, 0.0, 0.0);
    let start = utc(2026, 6, 21, 0, 0, 0);
    for minute in 0..1440_i64 {
        let f = minute as f64 / 1440.0;
        let lat = -89.9 + 179.8 * f;
        let lon = 179.9 - 359.8 * (f * 7.0).fract();
        model.position_override = Some((lat, lon));
        let now = start.add_seconds(minute * 60).unwrap();
        let fix = decode_one(&epoch_text(&model, now));
        assert!(
            (fix.latitude_deg.unwrap().deg::<f64>() - lat).abs() < 1e-6,
            "{lat}"
        );
        assert!(
            (fix.longitude_deg.unwrap().deg::<f64>() - lon).abs() < 1e-6,
            "{lon}"
        );
        let (h, mi, s, _) = now.hms_milli();
        assert_eq!(fix.utc, Some(DateTime::new(2026, 6, 21, h, mi, s).unwrap()));
    }
}

#[test]
fn no_fix_gives_time_but_no_position() {
    let mut model = GpsReceiverModel::new(KANO.0, KANO.1, KANO.2);
    model.fix = false;
    let text = epoch_text(&model, utc(2026, 3, 20, 6, 7, 8));
    assert_eq!(
        text,
        "$GPRMC,060708.00,V,,,,,,,200326,,,N*71\r\n\
         $GPGGA,060708.00,,,,,0,00,99.99,,,,,,*6F\r\n"
    );
    sentences(&text);
    let fix = decode_one(&text);
    assert!(!fix.has_position());
    assert_eq!(fix.altitude_m, None);
    assert_eq!(fix.quality, FixQuality::Invalid);
    assert_eq!(fix.utc, Some(DateTime::new(2026, 3, 20, 6, 7, 8).unwrap()));
    // Switching the fix back on restores the position.
    model.fix = true;
    assert!(decode_one(&epoch_text(&model, utc(2026, 3, 20, 6, 7, 9))).has_position());
}

#[test]
fn rollover_date_is_reported_with_the_true_time_of_day() {
    let mut model = GpsReceiverModel::new(KANO.0, KANO.1, KANO.2);
    model.date_override = Some((2006, 4, 16));
    let fix = decode_one(&epoch_text(&model, utc(2025, 12, 1, 10, 20, 30)));
    assert_eq!(
        fix.utc,
        Some(DateTime::new(2006, 4, 16, 10, 20, 30).unwrap())
    );
    assert!(fix.has_position());
    // A 1999 rollover date: the two-digit year 99 reads as 1999.
    model.date_override = Some((1999, 8, 22));
    let fix = decode_one(&epoch_text(&model, utc(2025, 12, 1, 10, 20, 30)));
    assert_eq!(
        fix.utc,
        Some(DateTime::new(1999, 8, 22, 10, 20, 30).unwrap())
    );
    // An impossible override is an error, not a sentence.
    model.date_override = Some((2025, 2, 29));
    let mut buf = [0u8; EPOCH_BUF_LEN];
    assert_eq!(
        model.epoch(utc(2025, 12, 1, 0, 0, 0), &mut buf),
        Err(GpsModelError::InvalidDate)
    );
}

#[test]
fn time_offset_steps_the_reported_time_across_midnight() {
    let mut model = GpsReceiverModel::new(KANO.0, KANO.1, KANO.2);
    model.time_offset_s = 90;
    let fix = decode_one(&epoch_text(&model, utc(2025, 12, 31, 23, 59, 0)));
    assert_eq!(fix.utc, Some(DateTime::new(2026, 1, 1, 0, 0, 30).unwrap()));
    model.time_offset_s = -3600;
    let fix = decode_one(&epoch_text(&model, utc(2026, 1, 1, 0, 30, 0)));
    assert_eq!(
        fix.utc,
        Some(DateTime::new(2025, 12, 31, 23, 30, 0).unwrap())
    );
    model.time_offset_s = i64::MAX;
    let mut buf = [0u8; EPOCH_BUF_LEN];
    assert_eq!(
        model.epoch(utc(2026, 1, 1, 0, 0, 0), &mut buf),
        Err(GpsModelError::TimeOutOfRange)
    );
}

#[test]
fn impossible_positions_are_written_as_given() {
    // Only the text is checked here: what a parser makes of it is the
    // drivers' business.
    let mut model = GpsReceiverModel::new(KANO.0, KANO.1, KANO.2);
    model.position_override = Some((91.0, 200.0));
    let s = sentences(&epoch_text(&model, utc(2026, 3, 20, 6, 7, 8)));
    assert_eq!(s[0][0], "GPRMC");
    assert_eq!(s[0][2], "A");
    assert_eq!(s[0][3..7], ["9100.0000", "N", "20000.0000", "E"]);
    assert_eq!(s[1][0], "GPGGA");
    assert_eq!(s[1][2..7], ["9100.0000", "N", "20000.0000", "E", "1"]);

    model.position_override = Some((-123.5, -1234.25));
    let s = sentences(&epoch_text(&model, utc(2026, 3, 20, 6, 7, 8)));
    assert_eq!(s[0][3..7], ["12330.0000", "S", "123415.0000", "W"]);
    assert_eq!(s[1][2..6], ["12330.0000", "S", "123415.0000", "W"]);

    model.position_override = Some((f64::NAN, 0.0));
    let mut buf = [0u8; EPOCH_BUF_LEN];
    let now = utc(2026, 3, 20, 6, 7, 8);
    assert_eq!(model.epoch(now, &mut buf), Err(GpsModelError::NonFinite));
    // Without a fix no position is written, so it does not matter.
    model.fix = false;
    assert!(model.epoch(now, &mut buf).is_ok());
}

#[test]
fn buffer_too_small_is_an_error_at_every_length() {
    let model = GpsReceiverModel::new(SOUTH_WEST.0, SOUTH_WEST.1, SOUTH_WEST.2);
    let now = utc(2026, 3, 20, 6, 7, 8);
    let full = epoch_text(&model, now);
    let mut buf = vec![0u8; full.len()];
    for len in 0..full.len() {
        assert_eq!(
            model.epoch(now, &mut buf[..len]),
            Err(GpsModelError::BufferTooSmall),
            "{len}"
        );
    }
    assert_eq!(model.epoch(now, &mut buf), Ok(full.len()));
    assert_eq!(buf, full.as_bytes());
}

#[test]
fn epoch_buf_len_holds_large_values_and_sentences_fit_nmea() {
    let mut model = GpsReceiverModel::new(-89.999_999, -179.999_999, -999.9);
    model.satellites = 99;
    let now = UtcTime::from_ymd_hms_milli(2026, 12, 31, 23, 59, 59, 999).unwrap();
    let text = epoch_text(&model, now);
    for line in text.split_terminator("\r\n") {
        assert!(line.len() <= 82, "{line}");
    }
    // Documented bound: fewer than 8 digits of degrees, altitude below 1e9 m.
    model.site_altitude_m = 999_999_999.0;
    model.position_override = Some((-9_999_999.0, -9_999_999.0));
    let mut buf = [0u8; EPOCH_BUF_LEN];
    assert!(model.epoch(now, &mut buf).is_ok());
}
