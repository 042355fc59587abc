//! The batch logic of `examples/solar_position.rs`: arguments, CSV in, CSV
//! out. Kept apart so that `tests/solar_position_cli.rs` can include it.

use std::io::{Read, Write};

use sun_algos::{Algorithm, Atmosphere, Float, Options, Site, UtcTime};

/// Floating-point type to compute in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FloatKind {
    /// Single precision.
    F32,
    /// Double precision.
    F64,
}

/// Parsed command line.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    pub algorithm: Algorithm,
    pub float: FloatKind,
    /// Pressure (hPa) and temperature (°C): apparent positions when given.
    pub atmosphere: Option<(f64, f64)>,
    /// Compute rows outside the algorithm's validity range instead of
    /// reporting an error for them.
    pub allow_out_of_range: bool,
}

/// Usage text.
pub const USAGE: &str = "usage: solar_position --algorithm NAME --float f32|f64 \
[--pressure HPA --temperature C] [--allow-out-of-range] < in.csv > out.csv\n\
input: CSV (quoted fields, BOM and CRLF allowed) with a header containing\n\
utc,latitude,longitude and optionally delta_t\n\
output: utc,latitude,longitude,zenith,azimuth,error (degrees; geometric without --pressure),\n\
one row per input row; a row that cannot be decoded or computed gets an error text";

/// Parses the arguments (without the program name).
pub fn parse_args<S: AsRef<str>>(args: &[S]) -> Result<Config, String> {
    let mut algorithm = None;
    let mut float = None;
    let mut pressure = None;
    let mut temperature = None;
    let mut allow_out_of_range = false;
    let mut it = args.iter().map(AsRef::as_ref);
    while let Some(arg) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .ok_or_else(|| format!("{name} needs a value"))
                .map(str::to_owned)
        };
        match arg {
            "--algorithm" => {
                let v = value(arg)?;
                let names: Vec<&str> = Algorithm::ALL.iter().map(|a| a.name()).collect();
                algorithm = Some(Algorithm::from_name(&v).ok_or_else(|| {
                    format!("unknown algorithm {v:?}; one of: {}", names.join(", "))
                })?);
            }
            "--float" => {
                float = Some(match value(arg)?.as_str() {
                    "f32" => FloatKind::F32,
                    "f64" => FloatKind::F64,
                    other => return Err(format!("--float must be f32 or f64, not {other:?}")),
                });
            }
            "--pressure" => pressure = Some(parse_number(&value(arg)?, "--pressure")?),
            "--temperature" => temperature = Some(parse_number(&value(arg)?, "--temperature")?),
            "--allow-out-of-range" => allow_out_of_range = true,
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    let atmosphere = match (pressure, temperature) {
        (None, None) => None,
        (Some(p), Some(t)) => {
            Atmosphere::new(p, t).map_err(|e| format!("atmosphere: {e}"))?;
            Some((p, t))
        }
        _ => return Err("--pressure and --temperature go together".into()),
    };
    Ok(Config {
        algorithm: algorithm.ok_or("--algorithm is required")?,
        float: float.ok_or("--float is required")?,
        atmosphere,
        allow_out_of_range,
    })
}

fn parse_number(s: &str, what: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .map_err(|_| format!("{what}: not a number: {s:?}"))
}

/// Column positions of the input header.
struct Columns {
    utc: usize,
    latitude: usize,
    longitude: usize,
    delta_t: Option<usize>,
    /// Number of header fields; every data row must have as many.
    len: usize,
}

fn columns(header: &csv::ByteRecord) -> Result<Columns, String> {
    let names: Vec<String> = header
        .iter()
        .map(|f| {
            String::from_utf8_lossy(f)
                .trim_start_matches('\u{feff}')
                .trim()
                .to_owned()
        })
        .collect();
    let find = |n: &str| names.iter().position(|h| h.eq_ignore_ascii_case(n));
    let need = |n: &str| find(n).ok_or_else(|| format!("input header has no {n} column"));
    Ok(Columns {
        utc: need("utc")?,
        latitude: need("latitude")?,
        longitude: need("longitude")?,
        delta_t: find("delta_t"),
        len: names.len(),
    })
}

/// A line holding nothing but blanks: not a data row (as a blank line).
fn is_blank(record: &csv::ByteRecord) -> bool {
    record.len() <= 1 && record.iter().all(<[u8]>::is_empty)
}

/// Reads the CSV from `input` and writes one result row per data row to
/// `output`. RFC 4180 input: quoted fields (with commas, quotes, line
/// breaks), a UTF-8 BOM, LF or CRLF line ends; blank lines are skipped.
/// Errors only for I/O and a missing header; a row that cannot be decoded
/// (a used field not UTF-8, a field count unlike the header's, a bad number
/// or date) or computed gives an error row and the run goes on.
pub fn run<R: Read, W: Write>(cfg: &Config, input: R, output: W) -> Result<(), String> {
    // Byte records: a field that is not UTF-8 spoils its own row only (a
    // String reader would end the run there); decoded per field below.
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(input);
    let mut writer = csv::WriterBuilder::new().from_writer(output);
    let mut record = csv::ByteRecord::new();
    let mut next = |record: &mut csv::ByteRecord| loop {
        match reader.read_byte_record(record) {
            Ok(false) => return Ok(false),
            Ok(true) if is_blank(record) => continue,
            Ok(true) => return Ok(true),
            Err(e) => return Err(format!("read: {e}")),
        }
    };
    if !next(&mut record)? {
        return Err("empty input: no header".into());
    }
    let cols = columns(&record)?;
    let wr = |e: csv::Error| format!("write: {e}");
    writer
        .write_record(["utc", "latitude", "longitude", "zenith", "azimuth", "error"])
        .map_err(wr)?;
    while next(&mut record)? {
        let echo = |i: usize| String::from_utf8_lossy(record.get(i).unwrap_or_default());
        let (utc, lat, lon) = (echo(cols.utc), echo(cols.latitude), echo(cols.longitude));
        let result = fields(&cols, &record).and_then(|fields| match cfg.float {
            FloatKind::F32 => row::<f32>(cfg, &cols, &fields),
            FloatKind::F64 => row::<f64>(cfg, &cols, &fields),
        });
        let (z, a, error) = match result {
            Ok((z, a)) => (format!("{z:.9}"), format!("{a:.9}"), String::new()),
            Err(e) => (String::new(), String::new(), e.replace(',', ";")),
        };
        writer
            .write_record([&*utc, &*lat, &*lon, &z, &a, &error])
            .map_err(wr)?;
    }
    writer.flush().map_err(|e| format!("write: {e}"))
}

/// The fields of a data row as text: the row must have the header's number
/// of fields, and the fields the tool uses must be UTF-8 (the others are
/// ignored, whatever their bytes).
fn fields<'r>(cols: &Columns, record: &'r csv::ByteRecord) -> Result<Vec<&'r str>, String> {
    if record.len() != cols.len {
        return Err(format!(
            "wrong number of fields: {} for {} header columns",
            record.len(),
            cols.len
        ));
    }
    let used = [
        (Some(cols.utc), "utc"),
        (Some(cols.latitude), "latitude"),
        (Some(cols.longitude), "longitude"),
        (cols.delta_t, "delta_t"),
    ];
    let used_as = |i: usize| used.iter().find(|(c, _)| *c == Some(i)).map(|(_, n)| *n);
    record
        .iter()
        .enumerate()
        .map(|(i, f)| match (std::str::from_utf8(f), used_as(i)) {
            (Ok(s), _) => Ok(s),
            (Err(_), None) => Ok(""),
            (Err(_), Some(name)) => Err(format!("bad {name}: not UTF-8")),
        })
        .collect()
}

/// Zenith and azimuth (degrees) of one row, or a short reason.
fn row<T: Float>(cfg: &Config, cols: &Columns, fields: &[&str]) -> Result<(f64, f64), String> {
    let get = |i: usize, what: &str| {
        fields
            .get(i)
            .copied()
            .filter(|s| !s.is_empty())
            .ok_or_else(|| format!("missing {what}"))
    };
    let time: UtcTime = get(cols.utc, "utc")?
        .parse()
        .map_err(|e| format!("bad utc: {e}"))?;
    let number = |i: usize, what: &str| -> Result<T, String> {
        let s = get(i, what)?;
        s.parse::<f64>()
            .map(T::from_f64)
            .map_err(|_| format!("bad {what}"))
    };
    let site = Site::new(
        number(cols.latitude, "latitude")?,
        number(cols.longitude, "longitude")?,
    )
    .map_err(|e| e.to_string())?;
    let delta_t_s = match cols.delta_t {
        Some(i) if fields.get(i).is_some_and(|s| !s.is_empty()) => Some(number(i, "delta_t")?),
        _ => None,
    };
    let atmosphere = match cfg.atmosphere {
        None => None,
        Some((p, t)) => {
            Some(Atmosphere::new(T::from_f64(p), T::from_f64(t)).map_err(|e| e.to_string())?)
        }
    };
    let options = Options {
        delta_t_s,
        atmosphere,
        allow_out_of_range: cfg.allow_out_of_range,
    };
    let p = cfg
        .algorithm
        .position(&time, &site, &options)
        .map_err(|e| e.to_string())?;
    Ok((p.zenith_deg.to_f64(), p.azimuth_deg.to_f64()))
}
