//! The texts of the configuration's ranges and rules (`Reason::text`), as
//! the console prints them after `error <key>: `. They are the product's
//! documented replies, written out here as they were before the texts were
//! built from `config::ranges`; a change to a range that changes a reply
//! fails this test. The book's table of the ranges is checked against
//! `config::ranges` too, printed by the same formatter.

use suntracker::config::range_text::{self, Num, Piece};
use suntracker::config::{ranges, Reason};

/// The documented text of each reason; a `match` without a wildcard, so a
/// new reason does not compile until its text is written here.
fn expected(r: Reason) -> &'static str {
    match r {
        Reason::CountsPerMotorRev => {
            "1...16,777,216 full steps or encoder counts per motor revolution"
        }
        Reason::Microsteps => "1...256 microsteps per full step",
        Reason::GearRatio => "1...10,000 motor revolutions per axis revolution",
        Reason::CountsPerDeg => {
            "counts * microsteps * gear / 360 must be 1...1,000,000 counts per degree"
        }
        Reason::LimitDeg => "-360...360 deg",
        Reason::AboveMinDeg => "must be above min_deg",
        Reason::HomeNearMinDeg => {
            "min_deg - 5 deg ... min_deg + 10 deg and at most max_deg: \
             the switch is at the low end of the travel"
        }
        Reason::Deg0To5 => "0...5 deg",
        Reason::SpeedDegS => "0.01...30 deg/s",
        Reason::Latitude => "-90...90 deg",
        Reason::Deg180 => "-180...180 deg",
        Reason::ElevationM => "-500...10,000 m",
        Reason::TableStepS => "60...43,200 s",
        Reason::WholeMinutesOfDay => "whole minutes dividing a day (86,400 s)",
        Reason::S0To3600 => "0...3,600 s",
        Reason::S1To3600 => "1...3,600 s",
        Reason::S1To86400 => "1...86,400 s",
        Reason::S0To86400 => "0...86,400 s",
        Reason::StowHz => "0.1...1,000 Hz",
        Reason::S0To600 => "0...600 s",
        Reason::MaxDeviationDeg => "0.1...45 deg",
        Reason::S1To600 => "1...600 s",
        Reason::MaxRetries => "0...20",
        Reason::BelowMaxDeviation => "must be below safety.max_deviation_deg",
        Reason::TiltOffsetDeg => "-45...45 deg",
        Reason::StatusMin => "0...1,440 min (0: no periodic status line)",
        Reason::ModbusAddress => "1...247",
        Reason::ModbusBaud => "1200, 2400, 4800, 9600, 19200, 38400, 57600 or 115200 baud",
        Reason::ModbusParity => "0 none (2 stop bits), 1 odd, 2 even",
        Reason::Switch => "0 off, 1 on",
        Reason::SlopeDeg => "0...90 deg",
        Reason::ActiveLevel => "0 low, 1 high",
        Reason::SupplyMv => "0...60,000 mV (0: off)",
        Reason::AtLeastStowMv => "must be at least supply.stow_mv",
        Reason::OvercastRatio => "0...1 of the clear sky (0: off)",
        Reason::OvercastMoves => "1...8 changes an hour",
        Reason::WholeCountsPerTurn => {
            "needs a whole axis.c.gear_ratio (whole motor counts per turn)"
        }
        Reason::UtcOffsetH => "-12...14 h east of UTC",
        Reason::WindMSPerHz => "0...10 m/s per Hz (0: not known)",
        Reason::DriveKind => {
            "0 stepper, 1 servo_encoder, 2 dc_hall, 3 linear_hall, 4 linear_pot, 5 timed"
        }
        Reason::DriveNotOnBoard => "no driver for it on this board",
        Reason::MaxCurrentMa => "100...40,000 mA",
        Reason::OvercurrentMs => "10...5,000 ms",
        Reason::LengthMm => "10...5,000 mm",
        Reason::PulsesPerMm => "0.01...1,000 pulses per mm",
        Reason::AdcCounts => "0...4,095 ADC counts",
        Reason::LinearGeometry => {
            "no triangle: |a - b| < retracted length, extended length < a + b"
        }
        Reason::WithinStroke => "must lie within the actuator's stroke",
        Reason::HomeAtRetracted => {
            "must be the angle fully retracted (linear_pot), within 0.01 deg"
        }
        Reason::PotSpan => "must differ from pot_retracted_counts",
    }
}

#[test]
fn every_reason_prints_its_documented_text() {
    assert_eq!(Reason::ALL.len(), 50);
    let mut wrong = Vec::new();
    for &r in Reason::ALL {
        let text = r.text();
        println!("{text}");
        if text != expected(r) {
            wrong.push(format!("{text:?} (expected {:?})", expected(r)));
        }
        // The other ways of reading a reason agree with `text`.
        assert_eq!(format!("{r}"), text.as_str());
        assert_eq!(format!("{r:?}"), text.as_str());
        assert_eq!(r == expected(r), text == expected(r));
    }
    assert!(wrong.is_empty(), "texts changed:\n{}", wrong.join("\n"));
}

#[test]
fn reasons_are_distinct() {
    for (i, &a) in Reason::ALL.iter().enumerate() {
        for &b in &Reason::ALL[i + 1..] {
            assert_ne!(a.text(), b.text());
        }
    }
}

/// A range as the book writes it: `−500…10,000`, and `±90` for a range
/// symmetric about zero; an offset `min_deg − 5`. Printed by the same
/// formatter as the reasons.
fn book(pieces: &[Piece]) -> String {
    let mut buf = [0u8; 128];
    let n = range_text::write(pieces, &mut buf);
    let text = std::str::from_utf8(&buf[..n]).unwrap();
    text.replace("...", "…").replace('-', "−")
}

/// The forms the book may write `range` in.
fn book_range(range: Piece) -> Vec<String> {
    let full = book(&[range]);
    let mut forms = Vec::new();
    if let Some((lo, hi)) = full.split_once('…') {
        if lo.strip_prefix('−') == Some(hi) {
            forms.push(format!("±{hi}"));
        }
    }
    forms.push(full);
    forms
}

/// The ranges of each row of the book's "Configuration ranges" table
/// (docs/src/reliability.md), by the row's first cell, in the order the
/// row writes them.
fn book_rows() -> Vec<(&'static str, Vec<Vec<String>>)> {
    use ranges as r;
    let f = |x: (f32, f32)| book_range(range_text::f32s(x));
    let u = |x: (u32, u32)| book_range(range_text::u32s(x));
    let home = |x: f32| vec![book(&[Piece::Str("min_deg"), Piece::Offset(Num::f32(x))])];
    vec![
        (
            "`site.lat_deg`, `site.lon_deg`, `site.elevation_m`, `site.utc_offset_h`",
            vec![
                f(r::LAT_DEG),
                f(r::LON_DEG),
                f(r::ELEVATION_M),
                f(r::UTC_OFFSET_H),
            ],
        ),
        (
            "`schedule.table_step_s`",
            vec![
                u(r::TABLE_STEP_S),
                u(r::HOLD_S),
                u(r::RECHECK_S),
                u(r::MAX_TICK_GAP_S),
                u(r::MAX_BACKWARD_S),
            ],
        ),
        (
            "`axis.*.counts_per_motor_rev`",
            vec![u(r::COUNTS_PER_MOTOR_REV)],
        ),
        (
            "`axis.*.microsteps`, `axis.*.gear_ratio`",
            vec![
                book_range(range_text::u16s(r::MICROSTEPS)),
                f(r::GEAR_RATIO),
                vec![book(&[Piece::Num(Num::f32(r::COUNTS_PER_DEG.1))])],
            ],
        ),
        (
            "`axis.*.min_deg`, `max_deg`, `home_deg`",
            vec![
                f(r::LIMIT_DEG),
                home(r::HOME_ABOVE_MIN_DEG.0),
                home(r::HOME_ABOVE_MIN_DEG.1),
            ],
        ),
        (
            "`axis.*.backlash_deg`, `deadband_deg`, `max_speed_deg_s`",
            vec![
                f(r::BACKLASH_DEG),
                f(r::DEADBAND_DEG),
                f(r::MAX_SPEED_DEG_S),
            ],
        ),
        (
            "`axis.c.continuous`",
            vec![book_range(range_text::u8s(r::SWITCH))],
        ),
        (
            "`axis.*.drive`, `max_current_ma`, `overcurrent_ms`",
            vec![
                book_range(range_text::u8s(r::DRIVE)),
                book_range(range_text::u16s(r::MAX_CURRENT_MA)),
                book_range(range_text::u16s(r::OVERCURRENT_MS)),
            ],
        ),
        ("`axis.*.back_speed_deg_s`", vec![f(r::MAX_SPEED_DEG_S)]),
        (
            "`axis.*.pivot_a_mm`, `pivot_b_mm`, `pivot_offset_deg`, `retracted_mm`, `stroke_mm`, `pulses_per_mm`, `pot_retracted_counts`, `pot_extended_counts`",
            vec![
                f(r::LENGTH_MM),
                f(r::LENGTH_MM),
                f(r::LIMIT_DEG),
                f(r::LENGTH_MM),
                f(r::LENGTH_MM),
                f(r::PULSES_PER_MM),
                book_range(range_text::u16s(r::ADC_COUNTS)),
                book_range(range_text::u16s(r::ADC_COUNTS)),
            ],
        ),
        (
            "`wind.stow_hz`, `wind.hold_s`, `wind.release_s`, `wind.m_s_per_hz`",
            vec![
                f(r::STOW_HZ),
                u(r::WIND_HOLD_S),
                u(r::WIND_RELEASE_S),
                f(r::WIND_M_S_PER_HZ),
            ],
        ),
        (
            "`safety.max_deviation_deg`, `stall_timeout_s`, `sensor_timeout_s`, `max_retries`",
            vec![
                f(r::MAX_DEVIATION_DEG),
                u(r::STALL_TIMEOUT_S),
                u(r::SENSOR_TIMEOUT_S),
                book_range(range_text::u8s(r::MAX_RETRIES)),
            ],
        ),
        (
            "`calibration.declination_deg`, `heading_offset_deg`, `tilt_x/y_offset_deg`",
            vec![f(r::HEADING_DEG), f(r::HEADING_DEG), f(r::TILT_OFFSET_DEG)],
        ),
        (
            "`log.status_min`",
            vec![book_range(range_text::u16s(r::STATUS_MIN))],
        ),
        (
            "`modbus.address`, `baud`, `parity`, `write`, `timeout_s`, `timeout_stow`",
            vec![
                book_range(range_text::u8s(r::MODBUS_ADDRESS)),
                u(r::MODBUS_BAUD),
                book_range(range_text::u8s(r::MODBUS_PARITY)),
                book_range(range_text::u8s(r::SWITCH)),
                u(r::WIND_RELEASE_S),
                book_range(range_text::u8s(r::SWITCH)),
            ],
        ),
        (
            "`stow.snow_slope_deg`, `snow_release_s`, `hail_slope_deg`, `hail_release_s`, `external_slope_deg`, `external_active`, `on_sensor_fault`",
            vec![
                f(r::STOW_SLOPE_DEG),
                u(r::WIND_RELEASE_S),
                f(r::STOW_SLOPE_DEG),
                u(r::WIND_RELEASE_S),
                f(r::STOW_SLOPE_DEG),
                book_range(range_text::u8s(r::ACTIVE_LEVEL)),
                book_range(range_text::u8s(r::SWITCH)),
            ],
        ),
        (
            "`supply.stow_mv`, `supply.resume_mv`",
            vec![
                book_range(range_text::u16s(r::SUPPLY_MV)),
                book_range(range_text::u16s(r::SUPPLY_MV)),
            ],
        ),
        (
            "`supply.calibration_mv`",
            vec![book_range(range_text::u16s(r::SUPPLY_MV))],
        ),
        (
            "`overcast.ratio`, `enter_s`, `leave_s`, `max_moves_per_hour`",
            vec![
                f(r::OVERCAST_RATIO),
                u(r::WIND_RELEASE_S),
                u(r::WIND_RELEASE_S),
                book_range(range_text::u8s(r::OVERCAST_MOVES)),
            ],
        ),
    ]
}

/// Where `text` first holds `number` at `from` or after, not as a part
/// of a longer number (`0…5` is not in `10…50`).
fn find_number(text: &str, from: usize, number: &str) -> Option<usize> {
    let digit = |c: Option<char>| c.is_some_and(|c| c.is_ascii_digit());
    text[from..]
        .match_indices(number)
        .map(|(p, _)| from + p)
        .find(|&p| {
            let mut before = text[..p].chars().rev();
            let mut after = text[p + number.len()..].chars();
            let (b, a) = (before.next(), after.next());
            let joins = |c: Option<char>, next: Option<char>| {
                digit(c) || (matches!(c, Some(',' | '.')) && digit(next))
            };
            !joins(b, before.next()) && !joins(a, after.next())
        })
}

/// Numbers in the table that are not ranges.
const BOOK_OTHER_NUMBERS: [&str; 2] = ["200-step", "24-bit"];

#[test]
fn book_ranges_table_matches_ranges() {
    let book_text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/src/reliability.md"),
    )
    .unwrap();
    let table: Vec<(&str, &str)> = book_text
        .lines()
        .skip_while(|l| *l != "| field | range |")
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            l.trim_matches('|')
                .trim()
                .split_once(" | ")
                .unwrap_or_else(|| panic!("a row of two cells: {l}"))
        })
        .collect();
    let rows = book_rows();
    let firsts: Vec<&str> = table.iter().map(|(first, _)| *first).collect();
    let expected: Vec<&str> = rows.iter().map(|(first, _)| *first).collect();
    assert_eq!(firsts, expected, "the table's rows");
    for ((_, cell), (first, ranges)) in table.iter().zip(&rows) {
        // Each range in order; what is left has no other number.
        let mut rest = cell.to_string();
        let mut at = 0;
        for forms in ranges {
            let (pos, form) = forms
                .iter()
                .filter_map(|form| find_number(&rest, at, form).map(|p| (p, form)))
                .min()
                .unwrap_or_else(|| panic!("{first}: {forms:?} not in (the rest of) {cell:?}"));
            rest.replace_range(pos..pos + form.len(), "");
            at = pos;
        }
        for other in BOOK_OTHER_NUMBERS {
            rest = rest.replace(other, "");
        }
        assert!(
            !rest.contains(|c: char| c.is_ascii_digit()),
            "{first}: a number that is not a range of config::ranges: {rest:?}"
        );
    }
}
