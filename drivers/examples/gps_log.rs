//! Reads an NMEA 0183 log on stdin and prints one CSV line per new fix, then
//! the sentence counters:
//!
//! ```text
//! cargo run -p suntracker-drivers --example gps_log < drivers/tests/data/gps_golden_mixed.nmea
//! ```
//!
//! Columns: `utc` (ISO 8601), `latitude` and `longitude` (degrees, north and
//! east positive), `altitude` (metres above mean sea level), `quality` (the
//! GGA digit), `satellites`. Unknown values are empty. An epoch with neither a
//! time nor a position is not printed.

use std::io::{Read as _, Write as _};

use drivers::gps::{GpsFix, GpsReader};

/// stdin as an `embedded_io::Read` (the `std` feature of embedded-io 0.6
/// provides the error conversions but no adapter for `Stdin`).
struct Stdin(std::io::Stdin);

impl embedded_io::ErrorType for Stdin {
    type Error = std::io::Error;
}

impl embedded_io::Read for Stdin {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, std::io::Error> {
        self.0.read(buf)
    }
}

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

fn csv(fix: &GpsFix) -> String {
    format!(
        "{},{},{},{},{},{}",
        opt(fix.utc),
        opt(fix.latitude_deg.map(|v| format!("{v:.7}"))),
        opt(fix.longitude_deg.map(|v| format!("{v:.7}"))),
        opt(fix.altitude_m.map(|v| format!("{v:.1}"))),
        fix.quality.code(),
        opt(fix.satellites),
    )
}

fn main() {
    if let Err(e) = run() {
        // A closed pipe (`gps_log < log | head`) is a normal way to stop.
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("gps_log: {e}");
            std::process::exit(1);
        }
    }
}

fn run() -> std::io::Result<()> {
    // A log replay has no monotonic clock: time is held at 0 and staleness
    // (a matter for live receivers) is switched off.
    let mut reader = GpsReader::new(Stdin(std::io::stdin()), u64::MAX);
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    writeln!(out, "utc,latitude,longitude,altitude,quality,satellites")?;
    loop {
        match reader.poll(0) {
            Ok(Some(fix)) if fix.utc.is_some() || fix.has_position() => {
                writeln!(out, "{}", csv(&fix))?
            }
            Ok(_) => {}
            Err(drivers::gps::Error::EndOfStream) => break,
            Err(drivers::gps::Error::Comm(e)) => return Err(e),
        }
    }
    let s = reader.stats();
    writeln!(
        out,
        "sentences={} accepted={} rejected_checksum={} rejected_other={}",
        s.sentences, s.accepted, s.rejected_checksum, s.rejected_other
    )?;
    out.flush()
}
