//! The configuration console (src/console/): the line buffer, the parser,
//! every key's get and set against the ranges documented in src/config/mod.rs,
//! postal codes, and the reply lines.

mod common;

use common::host_io::Buf;
use sun_algos::UtcTime;
use suntracker::config::{Config, DriveKind, DriveSet};
use suntracker::console::{
    self, apply_set, Command, Decimal, Key, LineBuffer, LineError, NumberError, Outcome,
    ParseError, RxRing, SetError, StatusView, TimeSetError, Value, KEYS, LINE_LEN,
};
use suntracker::log::SiteSource;
use suntracker::persist::{LoadReport, MemError, SaveError, SlotState};
use suntracker::safety::{AxisId, Fault, FaultManager, Mode, MAX_ACTIVE};
use suntracker::site::PostalError;
use suntracker::time::TimeOrigin;

/// The drive kinds of the board these tests stand for: every kind (a
/// board with fewer is tested in `drive_kinds_the_board_lacks_are_refused`).
const DRIVES: DriveSet = DriveSet::STEPPER
    .with(DriveKind::ServoEncoder)
    .with(DriveKind::DcHall)
    .with(DriveKind::LinearHall)
    .with(DriveKind::LinearPot)
    .with(DriveKind::Timed);

/// Runs one line as a board would: parse, the configuration commands, the
/// rest answered with a plain `ok NAME`. Returns the reply.
fn run(config: &mut Config, line: &str) -> String {
    let mut out = Buf::default();
    match console::parse(line) {
        Err(e) => console::write_parse_error(&mut out, &e),
        Ok(cmd) => {
            if let Outcome::Pass(cmd) = console::run_config(&mut out, config, DRIVES, cmd) {
                console::write_ok(&mut out, cmd.name());
            }
        }
    }
    let reply = out.take();
    for l in reply.lines() {
        assert!(
            l.starts_with("ok") || l.starts_with("error "),
            "{line:?} -> {l:?}"
        );
    }
    reply
}

/// The reply of `get KEY`, without `ok KEY=` and the newline.
fn get_text(config: &Config, key: Key) -> String {
    let mut out = Buf::default();
    console::format_get(&mut out, config, key);
    let s = out.take();
    let prefix = format!("ok {}=", key.name());
    s.strip_prefix(&prefix)
        .and_then(|v| v.strip_suffix('\n'))
        .unwrap_or_else(|| panic!("get {}: {s:?}", key.name()))
        .to_string()
}

fn is_read_only(key: Key) -> bool {
    key.name().to_string().ends_with("counts_per_deg")
}

// ---------------------------------------------------------------------------
// Ranges as documented in src/config/mod.rs

/// Doc comments of src/config/mod.rs, one line of text (`///` stripped, lines
/// joined by a space).
fn config_docs() -> String {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/config/mod.rs"))
        .expect("src/config/mod.rs");
    src.lines()
        .filter_map(|l| l.trim_start().strip_prefix("///"))
        .map(str::trim)
        .collect::<Vec<_>>()
        .join(" ")
}

/// The documented range of each key (the A axis's fields are documented
/// under their C-axis keys), as written in src/config/mod.rs.
const DOC_RANGES: &[(&str, &str)] = &[
    ("site.lat_deg", "−90…90"),
    ("site.lon_deg", "−180…180"),
    ("site.elevation_m", "−500…10,000"),
    ("schedule.table_step_s", "60…43,200"),
    ("schedule.hold_s", "0…3,600"),
    ("schedule.recheck_s", "1…3,600"),
    ("schedule.max_tick_gap_s", "1…86,400"),
    ("schedule.max_backward_s", "0…86,400"),
    ("axis.c.counts_per_motor_rev", "1…16,777,216"),
    ("axis.c.microsteps", "1…256"),
    ("axis.c.gear_ratio", "1…10,000"),
    ("axis.c.min_deg", "−360…360"),
    ("axis.c.max_deg", "−360…360"),
    ("axis.c.backlash_deg", "0…5"),
    ("axis.c.max_speed_deg_s", "0.01…30"),
    ("axis.c.deadband_deg", "0…5"),
    ("wind.stow_hz", "0.1…1,000"),
    ("wind.hold_s", "0…600"),
    ("wind.release_s", "0…86,400"),
    ("safety.max_deviation_deg", "0.1…45"),
    ("safety.stall_timeout_s", "1…600"),
    ("safety.sensor_timeout_s", "1…3,600"),
    ("safety.max_retries", "0…20"),
    ("calibration.declination_deg", "−180…180"),
    ("calibration.heading_offset_deg", "−180…180"),
    ("calibration.tilt_x_offset_deg", "−45…45"),
    ("calibration.tilt_y_offset_deg", "−45…45"),
    ("log.status_min", "0…1,440"),
    ("modbus.address", "1…247"),
    ("modbus.baud", "1,200…115,200"),
    ("modbus.parity", "0…2"),
    ("modbus.write", "0…1"),
    ("modbus.timeout_s", "0…86,400"),
    ("stow.snow_slope_deg", "0…90"),
    ("stow.snow_release_s", "0…86,400"),
    ("stow.hail_slope_deg", "0…90"),
    ("stow.hail_release_s", "0…86,400"),
    ("stow.external_slope_deg", "0…90"),
    ("stow.external_active", "0…1"),
    ("stow.on_sensor_fault", "0…1"),
    ("supply.stow_mv", "0…60,000"),
    ("supply.resume_mv", "0…60,000"),
    ("overcast.ratio", "0…1"),
    ("overcast.enter_s", "0…86,400"),
    ("overcast.leave_s", "0…86,400"),
    ("overcast.max_moves_per_hour", "1…8"),
    ("axis.c.continuous", "0…1"),
    ("site.utc_offset_h", "−12…14"),
    ("wind.m_s_per_hz", "0…10"),
    ("modbus.timeout_stow", "0…1"),
    ("axis.c.drive", "0…5"),
    ("axis.c.max_current_ma", "100…40,000"),
    ("axis.c.overcurrent_ms", "10…5,000"),
    ("axis.c.back_speed_deg_s", "0.01…30"),
    ("supply.calibration_mv", "0…60,000"),
    ("axis.c.pivot_a_mm", "10…5,000"),
    ("axis.c.pivot_b_mm", "10…5,000"),
    ("axis.c.pivot_offset_deg", "−360…360"),
    ("axis.c.retracted_mm", "10…5,000"),
    ("axis.c.stroke_mm", "10…5,000"),
    ("axis.c.pulses_per_mm", "0.01…1,000"),
    ("axis.c.pot_retracted_counts", "0…4,095"),
    ("axis.c.pot_extended_counts", "0…4,095"),
];

/// The home switch's range is relative to `min_deg` (documented as
/// "`min_deg − 5`…`min_deg + 10`").
const HOME_DOC: &str = "`min_deg − 5`…`min_deg + 10`";

fn doc_number(s: &str) -> f64 {
    s.replace('−', "-").replace(',', "").parse().unwrap()
}

/// (lo, hi) of a key from [`DOC_RANGES`], after checking that
/// src/config/mod.rs states that range next to the key.
fn doc_range(docs: &str, key: &str) -> Option<(f64, f64)> {
    let c_key = key.replace("axis.a.", "axis.c.");
    let (_, range) = DOC_RANGES.iter().find(|(k, _)| *k == c_key)?;
    let needle = format!("`{c_key}`");
    let near = docs.match_indices(&needle).any(|(i, _)| {
        let chars_before: String = docs[..i].chars().rev().take(80).collect();
        let before: String = chars_before.chars().rev().collect();
        let after: String = docs[i..]
            .chars()
            .take(needle.chars().count() + 30)
            .collect();
        before.contains(range) || after.contains(range)
    });
    assert!(
        near,
        "src/config/mod.rs does not state {range} next to {needle}"
    );
    let (lo, hi) = range.split_once('…').unwrap();
    Some((doc_number(lo), doc_number(hi)))
}

fn is_integer_key(config: &Config, key: Key) -> bool {
    matches!(console::get(config, key), Value::U32(_))
}

/// Axis index of an `axis.*` key.
fn axis_of(key: &str) -> usize {
    if key.starts_with("axis.a.") {
        1
    } else {
        0
    }
}

/// A configuration in which `value` of `key` can be valid: the related
/// fields moved out of its way (rules between fields, the derived counts
/// per degree).
fn base_for(key: &str, value: f64) -> Config {
    let mut c = Config::default();
    c.safety.max_deviation_deg = 45.0;
    // The resume level is at least the stow level.
    if key == "supply.stow_mv" {
        c.supply.resume_mv = 60_000;
    }
    let i = axis_of(key);
    let field = key.rsplit('.').next().unwrap();
    if key.starts_with("axis.") {
        match field {
            "counts_per_motor_rev" if value > 1_000.0 => {
                c.axes[i].microsteps = 1;
                c.axes[i].gear_ratio = 1.0;
            }
            "counts_per_motor_rev" => {
                c.axes[i].microsteps = 256;
                c.axes[i].gear_ratio = 10_000.0;
            }
            "min_deg" => {
                c.axes[i].max_deg = 360.0;
                c.axes[i].home_deg = value as f32;
            }
            "max_deg" => {
                c.axes[i].min_deg = -360.0;
                c.axes[i].home_deg = -360.0;
            }
            _ => {}
        }
    }
    c
}

/// Values of `key` inside its documented range that can be valid (the
/// range's ends, unless a rule between fields excludes them, and some in
/// between).
fn valid_values(docs: &str, key: Key) -> Vec<f64> {
    let name = &key.name().to_string();
    let defaults = Config::default();
    if name.ends_with(".home_deg") {
        assert!(
            docs.contains(HOME_DOC),
            "src/config/mod.rs does not state {HOME_DOC}"
        );
        let min = f64::from(defaults.axes[axis_of(name)].min_deg);
        return vec![min - 5.0, min - 1.25, min, min + 3.3, min + 10.0];
    }
    let Some((lo, hi)) = doc_range(docs, name) else {
        return vec![];
    };
    let (lo, hi) = if name.ends_with(".min_deg") {
        // At most just below max_deg (≤ 360).
        (lo, hi - 1.0)
    } else if name.ends_with(".max_deg") {
        // Above min_deg (≥ −360).
        (lo + 1.0, hi)
    } else {
        (lo, hi)
    };
    if is_integer_key(&defaults, key) {
        let mut v = vec![lo, hi, ((lo + hi) / 2.0).floor(), lo + 1.0];
        if name == "schedule.table_step_s" {
            // Whole minutes dividing a day.
            v = vec![lo, hi, 240.0, 3_600.0, 21_600.0];
        }
        if name == "modbus.baud" {
            // The standard rates only.
            v = vec![lo, hi, 9_600.0, 19_200.0, 57_600.0];
        }
        v
    } else {
        let span = hi - lo;
        vec![
            lo,
            hi,
            lo + span * 0.296_163,
            lo + span * 0.707_113,
            lo + span * 0.123_456_789,
        ]
    }
}

/// `value` as typed by a person: an integer, or up to six decimals.
fn typed(value: f64, integer: bool) -> String {
    if integer {
        format!("{}", value as i64)
    } else {
        let s = format!("{value:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.').to_string();
        if s == "-0" {
            "0".into()
        } else {
            s
        }
    }
}

// ---------------------------------------------------------------------------
// Keys

#[test]
fn key_table_names_every_field_once_and_the_docs_list_them() {
    let mut names: Vec<String> = KEYS.iter().map(|k| k.name().to_string()).collect();
    assert_eq!(names.len(), 87);
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), 87, "duplicate keys");
    let docs = config_docs();
    let module =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/src/console/mod.rs"))
            .expect("src/console/mod.rs");
    for k in KEYS.iter() {
        let name = &k.name().to_string();
        // Every key is a field key of src/config/mod.rs's docs (where its
        // unit and range are written, once), or one the console's docs name.
        let c_name = name.replace("axis.a.", "axis.c.");
        assert!(
            docs.contains(&format!("`{c_name}`")) || module.contains(&format!("`{name}`")),
            "{name} not in the docs"
        );
        assert_eq!(console::key_from_name(name), Some(k));
        assert_eq!(console::key_from_name(&name.to_uppercase()), Some(k));
    }
    // The console's docs point to the ranges instead of repeating them.
    assert!(module.contains("[`crate::config::ranges`]"));
    assert!(module.contains("`site.postal_code`"));
    assert_eq!(console::key_from_name("site.lat"), None);
    assert_eq!(console::key_from_name(""), None);
}

#[test]
fn every_key_round_trips_get_set_get() {
    let docs = config_docs();
    for key in KEYS.iter() {
        let name = &key.name().to_string();
        if is_read_only(key) {
            let mut c = Config::default();
            let v = get_text(&c, key);
            // 200 × 16 × 100 / 360
            assert_eq!(v, "888.889", "{name}");
            let reply = run(&mut c, &format!("set {name} {v}"));
            assert_eq!(reply, format!("error {name}: read only\n"));
            assert_eq!(c, Config::default());
            continue;
        }
        let integer = is_integer_key(&Config::default(), key);
        let mut values = valid_values(&docs, key);
        assert!(!values.is_empty(), "{name}: no documented range");
        values.push(f64::NAN); // the default value
        for value in values {
            let mut c = if value.is_nan() {
                Config::default()
            } else {
                base_for(name, value)
            };
            let text = if value.is_nan() {
                get_text(&c, key)
            } else {
                typed(value, integer)
            };
            let reply = run(&mut c, &format!("set {name} {text}"));
            assert!(
                reply.starts_with(&format!("ok {name}=")),
                "{name} {text}: {reply}"
            );
            // The reply is the value as stored, and `get` says the same.
            let got = get_text(&c, key);
            assert_eq!(reply, format!("ok {name}={got}\n"));
            let stored = match console::get(&c, key) {
                Value::F32(v) => f64::from(v),
                Value::U32(v) => f64::from(v),
            };
            let tol = if integer {
                0.0
            } else {
                1e-6 * stored.abs().max(1.0)
            };
            assert!(
                (stored - text.parse::<f64>().unwrap()).abs() <= tol,
                "{name} {text} stored {stored}"
            );
            assert!(
                (got.parse::<f64>().unwrap() - stored).abs() <= 5e-5 * stored.abs().max(1.0),
                "{name}: printed {got}, stored {stored}"
            );
            // get → set → get: the same text, and then the same bits.
            let before = c;
            assert_eq!(run(&mut c, &format!("set {name} {got}")), reply);
            assert_eq!(get_text(&c, key), got, "{name}");
            let again = c;
            assert_eq!(run(&mut c, &format!("set {name}={got}")), reply);
            assert_eq!(c, again, "{name}: {got} is not a fixed point");
            let _ = before;
            assert!(c.is_valid());
        }
    }
}

#[test]
fn every_out_of_range_value_is_refused_naming_the_field() {
    let docs = config_docs();
    let mut checked = 0;
    for key in KEYS.iter() {
        let name = &key.name().to_string();
        if is_read_only(key) {
            continue;
        }
        let integer = is_integer_key(&Config::default(), key);
        let mut bad: Vec<f64> = if name.ends_with(".home_deg") {
            let min = f64::from(Config::default().axes[axis_of(name)].min_deg);
            vec![min - 5.01, min + 10.01, min - 90.0, 400.0]
        } else {
            let (lo, hi) = doc_range(&docs, name).unwrap();
            let d = if integer { 1.0 } else { 0.01 };
            vec![lo - d, hi + d, lo - 1_000.0, hi + 1_000.0, hi * 10.0 + 1.0]
        };
        if integer {
            bad.push(4_294_967_295.0);
        }
        for value in bad {
            let original = Config::default();
            let mut c = original;
            let text = typed(value, integer);
            let reply = run(&mut c, &format!("set {name} {text}"));
            assert_eq!(c, original, "{name} {text} changed the config");
            let Command::Set(k, v) = console::parse(&format!("set {name} {text}")).unwrap() else {
                panic!("{name} {text}: not a set");
            };
            assert_eq!(k, key);
            let err = apply_set(&mut c, k, v, DRIVES).unwrap_err();
            assert_eq!(c, original);
            let SetError::Invalid(e) = err else {
                panic!("{name} {text}: {err:?}");
            };
            assert_eq!(e.field, key, "{name} {text}: {reply}");
            assert_eq!(reply, format!("error {name}: {}\n", e.reason.text()));
            checked += 1;
        }
    }
    assert!(checked >= 36 * 5, "{checked}");
}

#[test]
fn integer_keys_take_whole_numbers_only() {
    let mut c = Config::default();
    assert_eq!(
        run(&mut c, "set schedule.hold_s 60.0"),
        "ok schedule.hold_s=60\n"
    );
    assert_eq!(
        run(&mut c, "set schedule.hold_s 1.5"),
        "error schedule.hold_s: whole number expected\n"
    );
    assert_eq!(
        run(&mut c, "set safety.max_retries 0.0000000000000001"),
        "error safety.max_retries: whole number expected\n"
    );
    assert_eq!(
        run(&mut c, "set safety.max_retries 300"),
        "error safety.max_retries: 0...20\n"
    );
    assert_eq!(
        run(&mut c, "set axis.a.microsteps 70000"),
        "error axis.a.microsteps: 1...256 microsteps per full step\n"
    );
    assert_eq!(
        run(&mut c, "set wind.hold_s -1"),
        "error wind.hold_s: 0...600 s\n"
    );
    assert_eq!(run(&mut c, "set wind.hold_s -0"), "ok wind.hold_s=0\n");
    assert_eq!(
        run(&mut c, "set axis.c.counts_per_motor_rev 99999999999"),
        "error axis.c.counts_per_motor_rev: number too large\n"
    );
    let mut d = Config::default();
    d.schedule.hold_s = 60;
    d.wind.hold_s = 0;
    assert_eq!(c, d);
}

#[test]
fn rules_between_fields_name_the_field_and_two_keys_change_together() {
    let original = Config::default();
    let mut c = original;
    // The home switch must stay near min_deg: neither alone can go to −360.
    assert_eq!(
        run(&mut c, "set axis.c.min_deg -360"),
        "error axis.c.home_deg: min_deg - 5 deg ... min_deg + 10 deg and at most max_deg: the switch is at the low end of the travel\n"
    );
    assert!(run(&mut c, "set axis.c.home_deg -360").starts_with("error axis.c.home_deg: "));
    assert_eq!(
        run(&mut c, "set axis.c.min_deg 200"),
        "error axis.c.max_deg: must be above min_deg\n"
    );
    assert_eq!(
        run(&mut c, "set axis.c.gear_ratio 10000 axis.c.microsteps 256"),
        "error axis.c.counts_per_deg: counts * microsteps * gear / 360 must be 1...1,000,000 counts per degree\n"
    );
    assert_eq!(
        run(
            &mut c,
            "set axis.c.deadband_deg 0.5 safety.max_deviation_deg 0.4"
        ),
        "error axis.c.deadband_deg: must be below safety.max_deviation_deg\n"
    );
    assert_eq!(c, original);
    // Both at once; all or nothing.
    assert_eq!(
        run(&mut c, "set axis.c.min_deg -360 axis.c.home_deg=-360"),
        "ok axis.c.min_deg=-360 axis.c.home_deg=-360\n"
    );
    assert_eq!(c.axes[0].min_deg, -360.0);
    assert_eq!(c.axes[0].home_deg, -360.0);
    let before = c;
    assert_eq!(
        run(&mut c, "set wind.stow_hz 30 axis.a.max_deg 400"),
        "error axis.a.max_deg: -360...360 deg\n"
    );
    assert_eq!(
        run(&mut c, "set wind.stow_hz 30 axis.a.counts_per_deg 4"),
        "error axis.a.counts_per_deg: read only\n"
    );
    assert_eq!(c, before);
    assert_eq!(
        run(&mut c, "set wind.stow_hz 30 wind.hold_s"),
        "error missing argument\n"
    );
    assert_eq!(
        run(&mut c, "set wind.stow_hz 30 wind.holds 4"),
        "error unknown key\n"
    );
    assert_eq!(
        run(&mut c, "set wind.stow_hz 30 site.postal_code DZ:16000"),
        "error unexpected argument\n"
    );
    assert_eq!(c, before);
}

#[test]
fn drive_kinds_the_board_lacks_are_refused() {
    // A board of steppers and DC gear motors on Hall counts (the
    // ATmega2560's kinds).
    let board = DriveSet::STEPPER.with(DriveKind::DcHall);
    let run_on = |c: &mut Config, line: &str| {
        let mut out = Buf::default();
        let cmd = console::parse(line).unwrap();
        assert!(!matches!(
            console::run_config(&mut out, c, board, cmd),
            Outcome::Pass(_)
        ));
        out.take()
    };
    let original = Config::default();
    let mut c = original;
    for (kind, name) in [
        (1, "servo_encoder"),
        (3, "linear_hall"),
        (4, "linear_pot"),
        (5, "timed"),
    ] {
        assert_eq!(
            DriveKind::from_code(kind).map(|k| k as u8),
            Some(kind),
            "{name}"
        );
        assert_eq!(
            run_on(&mut c, &format!("set axis.a.drive {kind}")),
            "error axis.a.drive: no driver for it on this board\n"
        );
        // Refused whole with a change the board takes.
        assert_eq!(
            run_on(&mut c, &format!("set axis.c.drive 2 axis.c.drive={kind}")),
            "error axis.c.drive: no driver for it on this board\n"
        );
        assert_eq!(c, original);
    }
    assert_eq!(
        run_on(&mut c, "set axis.a.drive 6"),
        "error axis.a.drive: 0 stepper, 1 servo_encoder, 2 dc_hall, 3 linear_hall, 4 linear_pot, 5 timed\n"
    );
    assert_eq!(DriveKind::from_code(6), None);
    assert_eq!(c, original);
    assert_eq!(
        run_on(
            &mut c,
            "set axis.a.drive 2 axis.a.max_current_ma 4500 axis.a.overcurrent_ms 250"
        ),
        "ok axis.a.drive=2 axis.a.max_current_ma=4500 axis.a.overcurrent_ms=250\n"
    );
    assert_eq!(
        (
            c.axes[1].drive,
            c.axes[1].max_current_ma,
            c.axes[1].overcurrent_ms
        ),
        (DriveKind::DcHall as u8, 4_500, 250)
    );
    assert!(c.check_drives(board).is_ok());
    assert!(c.check_drives(DriveSet::STEPPER).is_err());
    // Back to a stepper.
    assert_eq!(run_on(&mut c, "set axis.a.drive 0"), "ok axis.a.drive=0\n");
}

// ---------------------------------------------------------------------------
// Postal codes (data/postal_codes.csv)

#[test]
fn postal_code_sets_the_site_with_or_without_leading_zero() {
    let original = Config::default();
    // DZ,16000,Alger Gare,36.779443,3.061738 (stored at 1e-4°)
    let mut c = original;
    assert_eq!(
        run(&mut c, "set site.postal_code DZ:16000"),
        "ok site.lat_deg=36.7794 site.lon_deg=3.0617\n"
    );
    assert!((c.site.latitude_deg - 36.7794).abs() < 1e-5);
    assert!((c.site.longitude_deg - 3.0617).abs() < 1e-5);
    assert_eq!(c.site.elevation_m, original.site.elevation_m);
    // DZ,09000,Blida,36.473571,2.832315, typed with and without its zero.
    for line in [
        "set site.postal_code DZ:09000",
        "set site.postal_code DZ:9000",
        "SET Site.Postal_Code dz:9000",
        "set site.postal_code=DZ:9000",
        "set   site.postal_code   DZ : 9000  ",
    ] {
        let mut c = original;
        assert_eq!(
            run(&mut c, line),
            "ok site.lat_deg=36.4736 site.lon_deg=2.8323\n",
            "{line}"
        );
        assert_eq!(c.site.elevation_m, original.site.elevation_m);
    }
    // DZ,01000,Adrar,27.8743,-0.2939; DZ,09002,Sidi Kebir,36.458546,2.849169
    let mut c = original;
    assert_eq!(
        run(&mut c, "set site.postal_code DZ:1000"),
        "ok site.lat_deg=27.8743 site.lon_deg=-0.2939\n"
    );
    assert_eq!(
        run(&mut c, "set site.postal_code DZ:9002"),
        "ok site.lat_deg=36.4585 site.lon_deg=2.8492\n"
    );
    let e = console::find_postal("DZ:16081").unwrap();
    assert_eq!(e.place(), "Baba Hassen");
}

#[test]
fn bad_postal_codes_change_nothing() {
    let original = Config::default();
    let mut c = original;
    for (line, reply) in [
        (
            "set site.postal_code DZ:99999",
            "error site.postal_code: not in the table\n",
        ),
        (
            "set site.postal_code DZ:59",
            "error site.postal_code: not in the table\n",
        ),
        (
            "set site.postal_code FR:16000",
            "error site.postal_code: not in the table\n",
        ),
        (
            "set site.postal_code 16000",
            "error site.postal_code: expected CC:CODE, e.g. DZ:16000\n",
        ),
        (
            "set site.postal_code D1:16000",
            "error site.postal_code: country must be two letters\n",
        ),
        (
            "set site.postal_code DZ:",
            "error site.postal_code: postal code must be 1-10 of 0-9, A-Z, space, -\n",
        ),
        (
            "set site.postal_code DZ:12345678901",
            "error site.postal_code: postal code must be 1-10 of 0-9, A-Z, space, -\n",
        ),
        ("set site.postal_code", "error missing argument\n"),
        ("set site.postal_code=", "error missing argument\n"),
        ("get site.postal_code", "error site.postal_code: set only\n"),
    ] {
        assert_eq!(run(&mut c, line), reply, "{line}");
        assert_eq!(c, original, "{line}");
    }
    assert_eq!(
        console::find_postal("DZ:0"),
        Err(PostalError::UnknownPostalCode)
    );
    assert_eq!(
        console::parse("set site.postal_code GB:SW1A 1AA"),
        Ok(Command::SetPostalCode("GB:SW1A 1AA"))
    );
    assert_eq!(
        console::parse("set site.postal_codex 5"),
        Err(ParseError::UnknownKey)
    );
}

// ---------------------------------------------------------------------------
// Numbers

#[test]
fn malformed_numbers_are_refused() {
    let huge = "9".repeat(1000);
    let huge_neg = format!("-{huge}");
    for s in [
        "", "-", "+", ".", "1.2.3", "1e5", "1E5", "nan", "NaN", "inf", "-inf", "Infinity", "1.",
        ".5", "-.5", " 1", "1 ", "0x10", "1,5", "--1", "+-1", "1-", "١", "½", "1_000",
    ] {
        assert_eq!(Decimal::parse(s), Err(NumberError::Invalid), "{s:?}");
    }
    for s in [
        "4294967296",
        "99999999999",
        huge.as_str(),
        huge_neg.as_str(),
    ] {
        assert_eq!(Decimal::parse(s), Err(NumberError::TooLarge), "{s:?}");
    }
    let mut c = Config::default();
    for (line, reply) in [
        (
            "set site.lat_deg 1.2.3",
            "error site.lat_deg: not a number\n",
        ),
        ("set site.lat_deg 1e5", "error site.lat_deg: not a number\n"),
        ("set site.lat_deg nan", "error site.lat_deg: not a number\n"),
        ("set site.lat_deg inf", "error site.lat_deg: not a number\n"),
        ("set site.lat_deg -", "error site.lat_deg: not a number\n"),
        ("set site.lat_deg", "error missing argument\n"),
        ("set site.lat_deg=", "error missing argument\n"),
        ("set site.lat_deg 1 2", "error missing argument\n"),
        ("jog c 1e5", "error not a number\n"),
        ("jog c 99999999999", "error number too large\n"),
    ] {
        assert_eq!(run(&mut c, line), reply, "{line}");
    }
    let line = format!("set site.lat_deg {huge}");
    assert_eq!(run(&mut c, &line), "error site.lat_deg: number too large\n");
    assert_eq!(c, Config::default());
}

#[test]
fn numbers_are_read_exactly() {
    let n = |s: &str| Decimal::parse(s).unwrap();
    assert_eq!(n("4294967295").to_u32(), Some(u32::MAX));
    assert_eq!(n("16777217").to_u32(), Some(16_777_217));
    assert_eq!(n("000000000000000000000000000001").to_u32(), Some(1));
    assert_eq!(n("+5").to_u32(), Some(5));
    assert_eq!(n("5.000").to_u32(), Some(5));
    assert_eq!(n("-0").to_u32(), Some(0));
    assert_eq!(n("-5").to_u32(), None);
    assert_eq!(n("5.5").to_u32(), None);
    assert!(n("5.5").has_fraction());
    assert!(!n("-5").has_fraction());
    assert_eq!(n("-12.375").to_f32(), -12.375);
    assert_eq!(n("0.1").to_f32(), 0.1);
    assert_eq!(n("36.47357").to_f32(), 36.47357);
    assert_eq!(n("-179.1234").to_f32(), -179.1234);
    assert_eq!(n("10000").to_f32(), 10_000.0);
    // Fraction digits beyond what the digits hold only count if non-zero.
    assert_eq!(n("0.12345678901234567890").to_f32(), 0.123_456_79);
    assert_eq!(n("7.000000000000000000000000").to_u32(), Some(7));
    assert_eq!(n("7.000000000000000000000001").to_u32(), None);
    assert_eq!(n("0.0000000000000000000001").to_f32(), 0.0);
    assert_eq!(Decimal::from_u32(42).to_u32(), Some(42));
    // Every f32 that the parser returns is finite.
    for s in ["4294967295.999999", "0.000000000001"] {
        assert!(n(s).to_f32().is_finite());
    }
}

/// A small deterministic generator (no crate for it).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }
    fn unit(&mut self) -> f64 {
        self.next() as f64 / (1u64 << 31) as f64
    }
}

#[test]
fn printed_numbers_read_back_and_print_the_same() {
    let mut rng = Lcg(7);
    for i in 0..200_000i32 {
        let exp = i % 10 - 3; // 1e-3 … 1e6
        let sign = if rng.next() & 1 == 0 { 1.0 } else { -1.0 };
        let v = (sign * rng.unit() * 10f64.powi(exp)) as f32;
        let mut out = Buf::default();
        console::write_number(&mut out, v);
        let printed = out.take();
        let back = Decimal::parse(&printed)
            .unwrap_or_else(|e| panic!("{v}: {printed:?} {e:?}"))
            .to_f32();
        let mut out = Buf::default();
        console::write_number(&mut out, back);
        assert_eq!(out.take(), printed, "{v}");
        // Six significant digits at least, or six decimals.
        let err = (f64::from(back) - f64::from(v)).abs();
        assert!(
            err <= (5e-6 * f64::from(v).abs()).max(6e-7),
            "{v} printed {printed}"
        );
    }
    let print = |v: f32| {
        let mut out = Buf::default();
        console::write_number(&mut out, v);
        out.take()
    };
    assert_eq!(print(25.0), "25");
    assert_eq!(print(0.05), "0.05");
    assert_eq!(print(0.2), "0.2");
    assert_eq!(print(-0.0), "0");
    assert_eq!(print(11.9683), "11.9683");
    assert_eq!(print(-179.1234), "-179.1234");
    assert_eq!(print(16_777_216.0), "16777216");
    assert_eq!(print(f32::NAN), "nan");
    assert_eq!(print(f32::INFINITY), "nan");
}

// ---------------------------------------------------------------------------
// The line buffer

/// Feeds `bytes`; the lines and errors it yields, as strings.
fn feed<const N: usize>(lb: &mut LineBuffer<N>, bytes: &[u8]) -> Vec<Result<String, LineError>> {
    let mut got = Vec::new();
    for &b in bytes {
        if let Some(r) = lb.push(b) {
            got.push(r.map(str::to_string));
        }
    }
    got
}

#[test]
fn line_endings_and_backspace() {
    let mut lb = LineBuffer::<LINE_LEN>::new();
    let ok = |s: &str| Ok(s.to_string());
    assert_eq!(
        feed(&mut lb, b"help\r\nstatus\rfaults\nclear\n\rget\r\r\n\n"),
        vec![
            ok("help"),
            ok("status"),
            ok("faults"),
            ok("clear"),
            ok("get")
        ]
    );
    assert_eq!(feed(&mut lb, b"hepl\x08\x08lp\r\n"), vec![ok("help")]);
    assert_eq!(feed(&mut lb, b"x\x7f\x7f\x7fstow\n"), vec![ok("stow")]);
    assert_eq!(
        feed(&mut lb, b"\tget\t site.lat_deg \n"),
        vec![ok("\tget\t site.lat_deg ")]
    );
    // A line split over several calls.
    assert_eq!(feed(&mut lb, b"sta"), vec![]);
    assert_eq!(feed(&mut lb, b"tus\r"), vec![ok("status")]);
    assert_eq!(feed(&mut lb, b"\nhome\n"), vec![ok("home")]);
    lb.push(b'x');
    lb.clear();
    assert_eq!(feed(&mut lb, b"home\n"), vec![ok("home")]);
}

#[test]
fn long_lines_non_ascii_and_control_bytes_are_errors() {
    let mut lb = LineBuffer::<8>::new();
    let ok = |s: &str| Ok(s.to_string());
    assert_eq!(feed(&mut lb, b"12345678\n"), vec![ok("12345678")]);
    assert_eq!(
        feed(&mut lb, b"123456789\nhelp\n"),
        vec![Err(LineError::TooLong), ok("help")]
    );
    // Backspace does not rescue a line that overflowed.
    assert_eq!(
        feed(&mut lb, b"123456789\x08\x08\r\n"),
        vec![Err(LineError::TooLong)]
    );
    assert_eq!(
        feed(&mut lb, "sét\r\nstow\r\n".as_bytes()),
        vec![Err(LineError::NonAscii), ok("stow")]
    );
    assert_eq!(
        feed(&mut lb, b"\x1b[Astow\n\x00\n"),
        vec![Err(LineError::Control), Err(LineError::Control)]
    );
    // The first problem is the one reported.
    assert_eq!(
        feed(&mut lb, "123456789é\n".as_bytes()),
        vec![Err(LineError::TooLong)]
    );
    let mut out = Buf::default();
    for e in [
        LineError::TooLong,
        LineError::NonAscii,
        LineError::Control,
        LineError::Lost,
    ] {
        console::write_line_error(&mut out, e);
    }
    assert_eq!(
        out.take(),
        "error line too long\nerror non-ASCII input\nerror control character\nerror input lost\n"
    );
}

#[test]
fn a_line_with_lost_input_is_never_run() {
    // A board's ring overflowed inside `set wind.stow_hz 25`: the `2` is
    // gone and the ring marked the gap. Without the marker the line would
    // be a valid `set` of 5 Hz.
    assert_eq!(console::LOST_INPUT, 0x18);
    let mut lb = LineBuffer::<LINE_LEN>::new();
    let mut line = b"set wind.stow_hz ".to_vec();
    line.push(console::LOST_INPUT);
    line.extend_from_slice(b"5\r\nstatus\r\n");
    assert_eq!(
        feed(&mut lb, &line),
        vec![Err(LineError::Lost), Ok("status".to_string())]
    );
    // Lost input is the problem reported, whatever came before it in the
    // line; a marker that ended a line's end (the newline lost) takes the
    // next line with it, answered once.
    let mut lb = LineBuffer::<8>::new();
    let mut bytes = b"123456789".to_vec();
    bytes.push(console::LOST_INPUT);
    bytes.extend_from_slice(b"status\n");
    assert_eq!(feed(&mut lb, &bytes), vec![Err(LineError::Lost)]);
    // The marker alone on a line is a line of lost input.
    assert_eq!(
        feed(&mut lb, &[console::LOST_INPUT, b'\n']),
        vec![Err(LineError::Lost)]
    );
}

#[test]
fn a_flood_never_panics_and_ends_in_one_error() {
    let mut lb = LineBuffer::<LINE_LEN>::new();
    // 10,000 bytes without an end of line: nothing until the end of line,
    // then one error, then the next line is fine.
    assert!(feed(&mut lb, &[b'a'; 10_000]).is_empty());
    assert_eq!(
        feed(&mut lb, b"\r\nstatus\r\n"),
        vec![Err(LineError::TooLong), Ok("status".to_string())]
    );
    assert!(feed(&mut lb, &[0xC3; 10_000]).is_empty());
    assert_eq!(feed(&mut lb, b"\n"), vec![Err(LineError::NonAscii)]);
    // 10,000 end-of-line bytes: blank lines, no replies.
    assert!(feed(&mut lb, &[b'\n'; 10_000]).is_empty());
    // 10,000 random bytes, then everything through the parser and replies.
    let mut rng = Lcg(1);
    let bytes: Vec<u8> = (0..10_000).map(|_| (rng.next() & 0xFF) as u8).collect();
    let mut config = Config::default();
    let mut out = Buf::default();
    let mut lines = 0;
    for &b in &bytes {
        match lb.push(b) {
            None => {}
            Some(Err(e)) => console::write_line_error(&mut out, e),
            Some(Ok(text)) => {
                assert!(text.len() <= LINE_LEN && text.is_ascii());
                lines += 1;
                match console::parse(text) {
                    Err(e) => console::write_parse_error(&mut out, &e),
                    Ok(cmd) => {
                        if let Outcome::Pass(cmd) =
                            console::run_config(&mut out, &mut config, DRIVES, cmd)
                        {
                            console::write_ok(&mut out, cmd.name());
                        }
                    }
                }
            }
        }
    }
    let reply = out.take();
    assert!(reply.lines().count() > 10);
    for l in reply.lines() {
        assert!(l.starts_with("ok") || l.starts_with("error "), "{l:?}");
    }
    let _ = lines;
    assert!(config.is_valid());
    // Printable garbage of every length through the parser.
    let mut config = Config::default();
    for len in 0..200 {
        let line: String = (0..len)
            .map(|_| char::from(b' ' + (rng.next() % 95) as u8))
            .collect();
        let _ = run(&mut config, &line);
    }
    assert!(config.is_valid());
}

// ---------------------------------------------------------------------------
// Commands

#[test]
fn every_command_parses() {
    let t = UtcTime::from_ymd_hms(2026, 3, 20, 6, 30, 5).unwrap();
    let lat = console::key_from_name("site.lat_deg").unwrap();
    let cases: Vec<(&str, Command)> = vec![
        ("help", Command::Help),
        ("status", Command::Status),
        ("get", Command::GetAll),
        ("get site.lat_deg", Command::Get(lat)),
        (
            "set site.lat_deg -12.5",
            Command::Set(lat, Decimal::parse("-12.5").unwrap()),
        ),
        (
            "set site.lat_deg=-12.5",
            Command::Set(lat, Decimal::parse("-12.5").unwrap()),
        ),
        (
            "set site.postal_code DZ:16000",
            Command::SetPostalCode("DZ:16000"),
        ),
        ("save", Command::Save),
        ("load", Command::Load),
        ("defaults", Command::Defaults),
        ("time set 2026-03-20T06:30:05Z", Command::TimeSet(t)),
        ("time set 2026-03-20t06:30:05z", Command::TimeSet(t)),
        ("stow", Command::Stow),
        ("resume", Command::Resume),
        ("home", Command::Home),
        ("jog c 5", Command::Jog(AxisId::C, 5.0)),
        ("jog A -2.25", Command::Jog(AxisId::A, -2.25)),
        ("manual off", Command::ManualOff),
        ("service on", Command::Service(true)),
        ("Service OFF", Command::Service(false)),
        ("faults", Command::Faults),
        ("clear", Command::Clear),
        ("  STATUS  ", Command::Status),
        ("\tManual\tOFF\t", Command::ManualOff),
    ];
    for (line, cmd) in cases {
        assert_eq!(console::parse(line), Ok(cmd), "{line}");
    }
    let Ok(Command::SetMany(a)) = console::parse("set wind.stow_hz 30 wind.hold_s=5") else {
        panic!("set with two pairs");
    };
    let pairs: Vec<_> = a.iter().collect();
    assert_eq!(pairs.len(), 2);
    assert_eq!(pairs[0].0.name(), "wind.stow_hz");
    assert_eq!(pairs[1].1.to_u32(), Some(5));
    assert_eq!(Command::ManualOff.name(), "manual off");
    assert_eq!(Command::TimeSet(t).name(), "time set");
    assert_eq!(Command::Service(true).name(), "service on");
    assert_eq!(Command::Service(false).name(), "service off");
}

#[test]
fn malformed_commands_get_errors() {
    let mut c = Config::default();
    for line in [
        "foo",
        "reboot now",
        "time",
        "time get 2026-03-20T06:30:05Z",
        "manual",
        "manual on",
        "service maybe",
        "helpme",
        "st0w",
        "é",
    ] {
        assert_eq!(run(&mut c, line), "error unknown command\n", "{line}");
    }
    for (line, reply) in [
        ("", ""),
        ("   \t ", ""),
        ("help me", "error unexpected argument\n"),
        ("stow now", "error unexpected argument\n"),
        ("manual off now", "error unexpected argument\n"),
        ("service", "error missing argument\n"),
        ("service on now", "error unexpected argument\n"),
        (
            "get site.lat_deg site.lon_deg",
            "error unexpected argument\n",
        ),
        ("get site.lat", "error unknown key\n"),
        ("set foo 1", "error unknown key\n"),
        ("set", "error missing argument\n"),
        ("jog", "error missing argument\n"),
        ("jog c", "error missing argument\n"),
        ("jog b 5", "error axis must be c or a\n"),
        ("jog c 5 6", "error unexpected argument\n"),
        ("time set", "error missing argument\n"),
        (
            "time set 2026-02-30T00:00:00Z",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 2026-03-20T24:00:00Z",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 2026-03-20 06:30:05Z",
            "error unexpected argument\n",
        ),
        (
            "time set 2026-03-20T06:30:05",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 9999-03-20T06:30:05Z",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 2026-3-20T06:30:05Z",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set +026-03-20T06:30:05Z",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 2026-03-20T06.30:05Z",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 2026:03-20T06:30:05Z",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 2026-03-20X06:30:05Z",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 2026-03-20T06:30:0aZ",
            "error time must be YYYY-MM-DDTHH:MM:SSZ\n",
        ),
        (
            "time set 2026-03-20T06:30:05Z x",
            "error unexpected argument\n",
        ),
    ] {
        assert_eq!(run(&mut c, line), reply, "{line}");
    }
    assert_eq!(console::parse(""), Err(ParseError::Empty));
    assert_eq!(c, Config::default());
}

#[test]
fn help_get_all_and_defaults() {
    let mut c = Config::default();
    let help = run(&mut c, "help");
    assert_eq!(help.lines().count(), console::help_lines().len());
    for word in [
        "status",
        "get",
        "set",
        "save",
        "time set",
        "jog",
        "manual off",
        "service on",
        "service off",
        "clear",
    ] {
        assert!(help.contains(word), "{word}");
    }
    assert!(help.is_ascii());
    let all = run(&mut c, "get");
    assert_eq!(all.lines().count(), KEYS.len());
    assert!(all.starts_with("ok site.lat_deg=11.9683\nok site.lon_deg=8.4261\n"));
    assert!(all.contains("ok axis.a.min_deg=-90\n"));
    assert!(all.contains("ok wind.stow_hz=25\n"));
    assert!(all.contains("ok axis.c.deadband_deg=0.05\n"));
    assert_eq!(
        run(&mut c, "set wind.stow_hz 30.5"),
        "ok wind.stow_hz=30.5\n"
    );
    let mut out = Buf::default();
    assert_eq!(
        console::run_config(&mut out, &mut c, DRIVES, Command::Defaults),
        Outcome::Changed
    );
    assert_eq!(out.take(), "ok defaults\n");
    assert_eq!(c, Config::default());
    assert_eq!(
        console::run_config(&mut out, &mut c, DRIVES, Command::Stow),
        Outcome::Pass(Command::Stow)
    );
    assert_eq!(out.take(), "");
    let lat = console::key_from_name("site.lat_deg").unwrap();
    let bad = Command::Set(lat, Decimal::parse("91").unwrap());
    assert_eq!(
        console::run_config(&mut out, &mut c, DRIVES, bad),
        Outcome::Answered
    );
    assert_eq!(out.take(), "error site.lat_deg: -90...90 deg\n");
}

// ---------------------------------------------------------------------------
// The firmware's replies

#[test]
fn status_line() {
    let mut faults = [None; MAX_ACTIVE];
    faults[0] = Some(Fault::GpsLost);
    faults[1] = Some(Fault::MotorStalled(AxisId::C));
    let view = StatusView {
        mode: Mode::Tracking,
        time: Some((
            UtcTime::from_ymd_hms(2026, 3, 20, 12, 0, 0).unwrap(),
            TimeOrigin::Rtc,
        )),
        lat_deg: 11.9683,
        lon_deg: 8.4261,
        site_source: SiteSource::Config,
        c_deg: Some(12.5),
        a_deg: Some(-30.25),
        faults,
        wind_hz: Some(3.2),
    };
    let mut out = Buf::default();
    console::write_status(&mut out, &view);
    assert_eq!(
        out.take(),
        "ok mode=tracking utc=2026-03-20T12:00:00Z time=rtc lat=11.9683 lon=8.4261 site=config \
         c=12.50 a=-30.25 faults=gps_lost,motor_stalled_c wind_hz=3.20\n"
    );
    let view = StatusView {
        mode: Mode::WaitForTime,
        time: None,
        site_source: SiteSource::Gps,
        c_deg: None,
        a_deg: None,
        faults: [None; MAX_ACTIVE],
        wind_hz: None,
        ..view
    };
    console::write_status(&mut out, &view);
    assert_eq!(
        out.take(),
        "ok mode=wait_for_time utc=none time=none lat=11.9683 lon=8.4261 site=gps c=none a=none \
         faults=none wind_hz=none\n"
    );
    let mut m = FaultManager::new(Config::default().safety);
    m.raise(Fault::RtcInvalid, 0);
    m.raise(Fault::SetPointDeviation(AxisId::A), 5);
    let f = StatusView::faults_of(&m);
    assert_eq!(f[0], Some(Fault::RtcInvalid));
    assert_eq!(f[1], Some(Fault::SetPointDeviation(AxisId::A)));
    assert_eq!(f[2], None);
}

#[test]
fn fault_time_save_and_load_replies() {
    let mut out = Buf::default();
    let mut m = FaultManager::new(Config::default().safety);
    console::write_faults(&mut out, &m);
    assert_eq!(out.take(), "ok faults=none\n");
    m.raise(Fault::GpsLost, 0);
    m.raise(Fault::GpsLost, 60_000);
    m.raise(Fault::LimitSwitchHit(AxisId::A), 0);
    console::write_faults(&mut out, &m);
    assert_eq!(
        out.take(),
        "ok fault=gps_lost attempts=2\nok fault=limit_switch_a attempts=1\n"
    );
    let t = UtcTime::from_ymd_hms(2026, 3, 20, 6, 30, 5).unwrap();
    console::write_time_set(&mut out, &t);
    console::write_time_refused(&mut out);
    assert_eq!(
        out.take(),
        "ok utc=2026-03-20T06:30:05Z\nerror time set: GPS time is in force\n"
    );
    // Every refusal of `time set`, each its own text (TimeSetError's docs).
    for e in [
        TimeSetError::GpsInForce,
        TimeSetError::RtcFailed,
        TimeSetError::OutOfRange,
        TimeSetError::OutsideWindow,
    ] {
        console::write_time_error(&mut out, e);
    }
    assert_eq!(
        out.take(),
        "error time set: GPS time is in force\n\
         error time set: the RTC did not answer\n\
         error time set: outside the RTC's range\n\
         error time set: outside this firmware's dates\n"
    );
    console::write_saved::<MemError>(&mut out, &Ok(()));
    console::write_saved(&mut out, &Err(SaveError::<MemError>::Invalid));
    console::write_saved(&mut out, &Err(SaveError::<MemError>::TooSmall));
    console::write_saved(&mut out, &Err(SaveError::Storage(MemError::Torn)));
    assert_eq!(
        out.take(),
        "ok save\nerror save: config invalid\nerror save: storage too small\nerror save: storage failed\n"
    );
    let loaded = |defaults| LoadReport {
        defaults,
        slots: [SlotState::Good(1), SlotState::Empty],
    };
    console::write_loaded(&mut out, &loaded(false));
    console::write_loaded(&mut out, &loaded(true));
    assert_eq!(out.take(), "ok load\nerror load: no valid stored config\n");
    console::write_ok(&mut out, suntracker::flash_str!(""));
    console::write_error(&mut out, suntracker::flash_str!("busy"));
    assert_eq!(out.take(), "ok\nerror busy\n");
}

// ---------------------------------------------------------------------------
// The boards' receive ring

/// Lines pasted far faster than the loop reads them (it takes `take` bytes
/// for every `every` bytes received) into an `N`-byte ring: every line is
/// answered once, by its own reply or by `error input lost` (the line a gap
/// falls in, and each line end lost in a gap no marker stands for), and no
/// line runs with a piece missing.
fn flood<const N: usize>(lines: &[&str], ending: &str, every: usize, take: usize) -> bool {
    let mut ring = RxRing::<N>::new();
    let mut lb = LineBuffer::<LINE_LEN>::new();
    let mut answered = 0usize;
    let mut ran = Vec::new();
    let mut read = |ring: &mut RxRing<N>,
                    max: usize,
                    answered: &mut usize,
                    ran: &mut Vec<String>| {
        for _ in 0..max {
            let Some(b) = ring.pop() else {
                // Drained: the lines lost behind the last one stored.
                *answered += usize::from(ring.take_lost_lines());
                break;
            };
            match lb.push(b) {
                None => {}
                Some(Ok(line)) => {
                    *answered += 1;
                    ran.push(line.to_string());
                }
                Some(Err(LineError::Lost)) => *answered += 1 + usize::from(ring.take_lost_lines()),
                Some(Err(e)) => panic!("{e:?}"),
            }
        }
    };
    let mut received = 0usize;
    for line in lines {
        for b in line.bytes().chain(ending.bytes()) {
            ring.push(b);
            received += 1;
            if received.is_multiple_of(every) {
                read(&mut ring, take, &mut answered, &mut ran);
            }
        }
    }
    read(&mut ring, usize::MAX, &mut answered, &mut ran);
    assert_eq!(
        answered,
        lines.len(),
        "{N}-byte ring, {ending:?}, every {every} take {take}: ran {ran:?}"
    );
    assert!(ran.iter().all(|l| lines.contains(&l.as_str())), "{ran:?}");
    // The next line typed after the flood runs whole: a gap is never
    // charged to the line after it.
    let next = if N > 3 { "st" } else { "x" };
    for b in next.bytes().chain(ending.bytes()) {
        ring.push(b);
    }
    let (mut after, mut ran_after) = (0, Vec::new());
    read(&mut ring, usize::MAX, &mut after, &mut ran_after);
    assert_eq!(
        ran_after,
        [next],
        "{N}-byte ring, {ending:?}, every {every} take {take}"
    );
    assert_eq!(after, 1);
    // Whether it overflowed.
    ring.dropped() > 0
}

#[test]
fn every_line_pasted_into_a_full_ring_is_answered_once() {
    let lines: Vec<&str> = [
        "help",
        "set wind.stow_hz 25",
        "status",
        "get site.lat_deg",
        "x",
    ]
    .iter()
    .cycle()
    .take(80)
    .copied()
    .collect();
    let mut overflowed = 0;
    for ending in ["\n", "\r", "\r\n"] {
        for (every, take) in [(4, 1), (10, 3), (50, 40), (3, 1), (2, 1), (23, 22)] {
            for ran_over in [
                flood::<64>(&lines, ending, every, take),
                flood::<255>(&lines, ending, every, take),
                flood::<16>(&lines, ending, every, take),
                flood::<3>(&lines, ending, every, take),
            ] {
                overflowed += usize::from(ran_over);
            }
        }
    }
    // 72 floods, most of which overflow their ring.
    assert!(overflowed >= 60, "{overflowed} overflowed");
}

#[test]
fn a_ring_with_room_passes_every_byte() {
    let mut ring = RxRing::<8>::new();
    for b in b"get\r\n" {
        ring.push(*b);
    }
    let mut out = [0u8; 16];
    let n = ring.pop_into(&mut out);
    assert_eq!(&out[..n], b"get\r\n");
    assert_eq!((ring.dropped(), ring.take_lost_lines()), (0, 0));
    // Full: the newest byte becomes the marker; a dropped line end makes
    // it the line-ending marker.
    for b in b"set a 12\n" {
        ring.push(*b);
    }
    let n = ring.pop_into(&mut out);
    assert_eq!(&out[..n], b"set a 1\x19");
    assert_eq!(ring.dropped(), 1);
    // A receive error: a marker inside the line.
    ring.push(b'a');
    ring.lose();
    ring.push(b'\n');
    let n = ring.pop_into(&mut out);
    assert_eq!(&out[..n], b"a\x18\n");
}
