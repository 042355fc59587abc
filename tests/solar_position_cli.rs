//! The batch tool of `examples/solar_position.rs`, through its CSV module.

#[path = "../examples/solar_position_support/batch.rs"]
mod batch;

use batch::{parse_args, run, Config, FloatKind};
use sun_algos::{Algorithm, SunPosition};

fn run_str(cfg: &Config, input: &str) -> Vec<Vec<String>> {
    run_bytes(cfg, input.as_bytes())
}

/// Runs the tool on raw input bytes; the output read back with an
/// RFC 4180 reader (quoted fields stay one field), header row included.
fn run_bytes(cfg: &Config, input: &[u8]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    run(cfg, input, &mut out).expect("run");
    let text = String::from_utf8(out).expect("utf8 output");
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes())
        .records()
        .map(|r| {
            r.expect("output is CSV")
                .iter()
                .map(str::to_owned)
                .collect()
        })
        .collect()
}

fn cfg(args: &[&str]) -> Config {
    parse_args(args).expect("args")
}

/// Reference rows (skyfield + DE421, geometric) from sun_algos/tests/data.
fn reference_rows(n: usize) -> Vec<Vec<String>> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/sun_algos/tests/data/sun_2020_2050.csv"
    );
    std::fs::read_to_string(path)
        .expect("reference table")
        .lines()
        .skip(1)
        .take(n)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

#[test]
fn parses_the_documented_interface() {
    let c = cfg(&["--algorithm", "psa-2020", "--float", "f32"]);
    assert_eq!(c.algorithm, Algorithm::Psa2020);
    assert_eq!(c.float, FloatKind::F32);
    assert_eq!(c.atmosphere, None);
    assert!(!c.allow_out_of_range);
    let c = cfg(&[
        "--float",
        "f64",
        "--algorithm",
        "michalsky",
        "--pressure",
        "1010",
        "--temperature",
        "12.5",
        "--allow-out-of-range",
    ]);
    assert_eq!(c.atmosphere, Some((1010.0, 12.5)));
    assert!(c.allow_out_of_range);
    for bad in [
        &["--algorithm", "psa", "--float", "f32"][..],
        &["--algorithm", "psa-2020", "--float", "f16"],
        &["--algorithm", "psa-2020"],
        &["--float", "f64"],
        &[
            "--algorithm",
            "psa-2020",
            "--float",
            "f64",
            "--pressure",
            "1000",
        ],
        &[
            "--algorithm",
            "psa-2020",
            "--float",
            "f64",
            "--pressure",
            "-3",
            "--temperature",
            "0",
        ],
        &["--algorithm"],
        &["--algorithm", "psa-2020", "--float", "f64", "--verbose"],
    ] {
        assert!(parse_args(bad).is_err(), "{bad:?}");
    }
}

#[test]
fn reproduces_the_reference_in_both_floats() {
    let rows = reference_rows(40);
    let mut input = String::from("utc,latitude,longitude,delta_t,zenith,azimuth\n");
    for r in &rows {
        input.push_str(&r.join(","));
        input.push('\n');
    }
    for float in ["f32", "f64"] {
        let out = run_str(&cfg(&["--algorithm", "psa-2020", "--float", float]), &input);
        assert_eq!(
            out[0],
            ["utc", "latitude", "longitude", "zenith", "azimuth", "error"]
        );
        assert_eq!(out.len(), rows.len() + 1);
        for (o, r) in out[1..].iter().zip(&rows) {
            assert_eq!(o[..3], r[..3], "input order and echo");
            assert_eq!(o[5], "");
            // At least 7 decimals.
            assert!(o[3].split('.').nth(1).is_some_and(|d| d.len() >= 7));
            let ours = SunPosition::new(o[3].parse::<f64>().unwrap(), o[4].parse().unwrap(), false);
            let reference =
                SunPosition::new(r[4].parse::<f64>().unwrap(), r[5].parse().unwrap(), false);
            // PSA+ is within 0.008° (f64) / 0.011° (f32) above the horizon;
            // below it there is no parallax subtlety either.
            let d = ours.angular_distance_deg(&reference);
            assert!(d < 0.011, "{float} {:?}: {d}", r);
        }
    }
}

#[test]
fn columns_in_any_order_extra_columns_and_no_delta_t() {
    // Row 1 of sun_2020_2050.csv, columns shuffled, no delta_t (the
    // built-in ΔT is unused by PSA anyway).
    let input = "id,longitude,note,utc,latitude\n\
                 7,-92.64742,x,2034-09-01T21:58:29Z,44.28637\n";
    let out = run_str(&cfg(&["--algorithm", "psa-2020", "--float", "f64"]), input);
    assert_eq!(
        out[1][..3],
        ["2034-09-01T21:58:29Z", "44.28637", "-92.64742"]
    );
    let z: f64 = out[1][3].parse().unwrap();
    let a: f64 = out[1][4].parse().unwrap();
    // Reference: zenith 61.1155447°, azimuth 251.5567681°.
    assert!((z - 61.115_544_7).abs() < 0.01 && (a - 251.556_768_1).abs() < 0.02);
}

#[test]
fn bad_rows_give_error_rows_and_never_stop_the_run() {
    let input = "utc,latitude,longitude,delta_t\n\
                 2030-06-01T12:00:00Z,91,0,69\n\
                 2030-06-01T12:00:00Z,45,200,69\n\
                 2030-02-30T12:00:00Z,45,0,69\n\
                 2030-06-01T25:00:00Z,45,0,69\n\
                 not-a-date,45,0,69\n\
                 2030-06-01T12:00:00Z,abc,0,69\n\
                 2030-06-01T12:00:00Z,45,0,NaN\n\
                 2030-06-01T12:00:00Z,45\n\
                 2060-06-01T12:00:00Z,45,0,69\n\
                 2030-06-01T12:00:00Z,45,0,\n";
    let out = run_str(&cfg(&["--algorithm", "psa-2020", "--float", "f32"]), input);
    assert_eq!(out.len(), 11);
    for (i, o) in out[1..10].iter().enumerate() {
        assert_eq!(o.len(), 6, "row {i}: {o:?}");
        assert_eq!(o[3], "", "row {i}");
        assert_eq!(o[4], "", "row {i}");
        assert!(!o[5].is_empty(), "row {i}");
    }
    assert!(out[1][5].contains("latitude"));
    assert!(out[2][5].contains("longitude"));
    assert!(out[3][5].contains("date"));
    assert!(out[9][5].contains("validity"), "{:?}", out[9]);
    // Empty delta_t cell: the built-in model; a valid row.
    assert_eq!(out[10][5], "");
    // Opting in computes the 2060 row.
    let out = run_str(
        &cfg(&[
            "--algorithm",
            "psa-2020",
            "--float",
            "f32",
            "--allow-out-of-range",
        ]),
        input,
    );
    assert_eq!(out[9][5], "");
    assert!(out[9][3].parse::<f64>().is_ok());
}

#[test]
fn pressure_gives_apparent_positions() {
    let input = "utc,latitude,longitude\n2034-09-01T21:58:29Z,44.28637,-92.64742\n";
    let app = run_str(
        &cfg(&[
            "--algorithm",
            "psa-2020",
            "--float",
            "f64",
            "--pressure",
            "1010",
            "--temperature",
            "10",
        ]),
        input,
    );
    let geo_psa = run_str(&cfg(&["--algorithm", "psa-2020", "--float", "f64"]), input);
    let (zg, za): (f64, f64) = (geo_psa[1][3].parse().unwrap(), app[1][3].parse().unwrap());
    // Elevation 28.884°: Bennett/NREL refraction at 1010 hPa, 10 °C is
    // 1.02/tan(28.884° + 10.3/33.994°)/60 = 0.03043° (hand computation).
    assert!((zg - za - 0.030_43).abs() < 0.0002, "{zg} {za}");
}

#[test]
fn missing_header_columns_are_an_error() {
    let mut out = Vec::new();
    let c = cfg(&["--algorithm", "psa-2020", "--float", "f64"]);
    assert!(run(&c, "time,lat,lon\n".as_bytes(), &mut out).is_err());
    assert!(run(&c, "".as_bytes(), &mut out).is_err());
}

#[test]
fn usage_names_every_flag() {
    for flag in [
        "--algorithm",
        "--float",
        "--pressure",
        "--temperature",
        "--allow-out-of-range",
    ] {
        assert!(batch::USAGE.contains(flag), "{flag}");
    }
}

/// Row 1 of sun_2020_2050.csv (skyfield + DE421): the site and instant, and
/// the geometric zenith and azimuth there.
const ROW1: &str = "2034-09-01T21:58:29Z";
const ROW1_SITE: (&str, &str) = ("44.28637", "-92.64742");
const ROW1_ZA: (f64, f64) = (61.115_544_7, 251.556_768_1);

fn assert_row1(o: &[String]) {
    assert_eq!(o.len(), 6, "{o:?}");
    assert_eq!(o[..3], [ROW1, ROW1_SITE.0, ROW1_SITE.1], "{o:?}");
    assert_eq!(o[5], "", "{o:?}");
    let z: f64 = o[3].parse().unwrap();
    let a: f64 = o[4].parse().unwrap();
    assert!(
        (z - ROW1_ZA.0).abs() < 0.01 && (a - ROW1_ZA.1).abs() < 0.02,
        "{o:?}"
    );
}

fn psa_f64() -> Config {
    cfg(&["--algorithm", "psa-2020", "--float", "f64"])
}

#[test]
fn quoted_fields_with_commas_are_one_field() {
    // A quoted note with a comma (and an escaped quote) before the site
    // columns must not shift them; a quoted "1,5" latitude is one field,
    // a bad number, and is echoed back as one field.
    let input = format!(
        "utc,note,latitude,longitude\n\
         {ROW1},\"Kano, NG \"\"roof\"\"\",{},{}\n\
         {ROW1},plain,\"1,5\",{}\n\
         \"{ROW1}\",\"\",\"{}\",\"{}\"\n",
        ROW1_SITE.0, ROW1_SITE.1, ROW1_SITE.1, ROW1_SITE.0, ROW1_SITE.1
    );
    let out = run_str(&psa_f64(), &input);
    assert_eq!(out.len(), 4, "{out:?}");
    assert_row1(&out[1]);
    assert_eq!(out[2].len(), 6, "{:?}", out[2]);
    assert_eq!(out[2][1], "1,5");
    assert_eq!((out[2][3].as_str(), out[2][4].as_str()), ("", ""));
    assert!(out[2][5].contains("latitude"), "{:?}", out[2]);
    assert_row1(&out[3]);
}

#[test]
fn bom_crlf_and_quoted_line_breaks() {
    // What spreadsheet programs write: a UTF-8 BOM, quoted header names,
    // CRLF line ends, and a quoted cell holding a line break.
    let input = format!(
        "\u{feff}\"utc\",\"latitude\",\"longitude\",\"note\"\r\n\
         {ROW1},{},{},one\r\n\
         {ROW1},{},{},\"two\r\nlines\"\r\n\
         {ROW1},{},{},three\r\n",
        ROW1_SITE.0, ROW1_SITE.1, ROW1_SITE.0, ROW1_SITE.1, ROW1_SITE.0, ROW1_SITE.1
    );
    let out = run_str(&psa_f64(), &input);
    assert_eq!(
        out[0],
        ["utc", "latitude", "longitude", "zenith", "azimuth", "error"]
    );
    assert_eq!(out.len(), 4, "one output row per data row: {out:?}");
    for o in &out[1..] {
        assert_row1(o);
    }
}

#[test]
fn undecodable_rows_give_error_rows_and_the_run_goes_on() {
    let (lat, lon) = ROW1_SITE;
    let mut input = Vec::new();
    input.extend_from_slice(b"utc,latitude,longitude,note\n");
    let good = format!("{ROW1},{lat},{lon},ok\n");
    input.extend_from_slice(good.as_bytes());
    // Latin-1 degree sign (0xB0) in the latitude: not UTF-8.
    input.extend_from_slice(format!("{ROW1},{lat}").as_bytes());
    input.extend_from_slice(b"\xb0");
    input.extend_from_slice(format!(",{lon},x\n").as_bytes());
    input.extend_from_slice(good.as_bytes());
    // Invalid UTF-8 in the utc cell.
    input.extend_from_slice(b"2034-09-01T21:58:29Z\xff\xfe,");
    input.extend_from_slice(format!("{lat},{lon},x\n").as_bytes());
    // Too many and too few fields.
    input.extend_from_slice(format!("{ROW1},{lat},{lon},x,extra\n").as_bytes());
    input.extend_from_slice(format!("{ROW1},{lat},{lon}\n").as_bytes());
    // A bad number and a bad date.
    input.extend_from_slice(format!("{ROW1},4x,{lon},x\n").as_bytes());
    input.extend_from_slice(format!("2034-02-30T21:58:29Z,{lat},{lon},x\n").as_bytes());
    // Latin-1 text in a column the tool does not read: the row is fine.
    input.extend_from_slice(format!("{ROW1},{lat},{lon},caf").as_bytes());
    input.extend_from_slice(b"\xe9\n");

    let out = run_bytes(&psa_f64(), &input);
    assert_eq!(out.len(), 1 + 9, "one output row per data row: {out:?}");
    for i in [1, 3, 9] {
        assert_row1(&out[i]);
    }
    for (i, what) in [
        (2, "latitude"),
        (4, "utc"),
        (5, "fields"),
        (6, "fields"),
        (7, "latitude"),
        (8, "utc"),
    ] {
        let o = &out[i];
        assert_eq!(o.len(), 6, "row {i}: {o:?}");
        assert_eq!((o[3].as_str(), o[4].as_str()), ("", ""), "row {i}: {o:?}");
        assert!(o[5].contains(what), "row {i}: {o:?}");
        // Same style as the other errors: no comma inside the reason.
        assert!(!o[5].contains(','), "row {i}: {o:?}");
    }
    // The readable fields are still echoed.
    assert_eq!(out[2][0], ROW1);
    assert_eq!(out[4][1], lat);
}
