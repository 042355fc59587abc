//! The batch logic of `examples/solar_position.rs`: arguments, CSV in, CSV
//! out. Kept apart so that `tests/solar_position_cli.rs` can include it.

use std::io::{BufRead, Write};

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
input: CSV with a header containing utc,latitude,longitude and optionally delta_t\n\
output: utc,latitude,longitude,zenith,azimuth,error (degrees; geometric without --pressure)";

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
}

fn split(line: &str) -> Vec<&str> {
    line.split(',')
        .map(|f| f.trim().trim_matches('"').trim())
        .collect()
}

fn columns(header: &str) -> Result<Columns, String> {
    let names = split(header.trim_start_matches('\u{feff}'));
    let find = |n: &str| names.iter().position(|&h| h.eq_ignore_ascii_case(n));
    let need = |n: &str| find(n).ok_or_else(|| format!("input header has no {n} column"));
    Ok(Columns {
        utc: need("utc")?,
        latitude: need("latitude")?,
        longitude: need("longitude")?,
        delta_t: find("delta_t"),
    })
}

/// Reads the CSV from `input` and writes one result row per data row to
/// `output`. Errors only for I/O and a missing header; a bad row gives an
/// error row.
pub fn run<R: BufRead, W: Write>(cfg: &Config, input: R, mut output: W) -> Result<(), String> {
    let mut lines = input.lines();
    let header = loop {
        match lines.next() {
            None => return Err("empty input: no header".into()),
            Some(line) => {
                let line = line.map_err(|e| format!("read: {e}"))?;
                if !line.trim().is_empty() {
                    break line;
                }
            }
        }
    };
    let cols = columns(&header)?;
    let io = |e: std::io::Error| format!("write: {e}");
    writeln!(output, "utc,latitude,longitude,zenith,azimuth,error").map_err(io)?;
    for line in lines {
        let line = line.map_err(|e| format!("read: {e}"))?;
        if line.trim().is_empty() {
            continue;
        }
        let fields = split(&line);
        let field = |i: usize| fields.get(i).copied().unwrap_or("");
        let result = match cfg.float {
            FloatKind::F32 => row::<f32>(cfg, &cols, &fields),
            FloatKind::F64 => row::<f64>(cfg, &cols, &fields),
        };
        let (utc, lat, lon) = (field(cols.utc), field(cols.latitude), field(cols.longitude));
        match result {
            Ok((z, a)) => writeln!(output, "{utc},{lat},{lon},{z:.9},{a:.9},"),
            Err(e) => writeln!(output, "{utc},{lat},{lon},,,{}", e.replace(',', ";")),
        }
        .map_err(io)?;
    }
    output.flush().map_err(io)
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
