//! Batch sun positions from a CSV file.
//!
//! ```text
//! cargo run --release --example solar_position -- --algorithm NAME --float f32|f64 \
//!     [--pressure HPA --temperature C] [--allow-out-of-range] < in.csv > out.csv
//! ```
//!
//! Input: CSV (RFC 4180: quoted fields may hold commas, quotes and line
//! breaks; a UTF-8 BOM and CRLF line ends are fine) whose header contains
//! `utc,latitude,longitude` and optionally `delta_t` (seconds; the built-in
//! model when the column is absent or the cell empty); other columns are
//! ignored, in any order. `utc` like `2031-04-05T06:07:08Z`.
//!
//! Output: `utc,latitude,longitude,zenith,azimuth,error`, exactly one row per
//! input data row in input order (blank lines are skipped), degrees with 9
//! decimals. Without `--pressure` the position is geometric (no refraction).
//! `error` is empty when fine, else a short reason with zenith and azimuth
//! empty: a row that cannot be decoded (a used field not UTF-8, a number of
//! fields unlike the header's, a bad number or date), a site out of range,
//! or an instant outside the algorithm's validity range (pass
//! `--allow-out-of-range` to compute those anyway). The rows after a bad
//! row go on.

#[path = "solar_position_support/batch.rs"]
mod batch;

use std::io::{stdin, stdout, BufWriter};
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("{}", batch::USAGE);
        return ExitCode::SUCCESS;
    }
    let cfg = match batch::parse_args(&args) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}\n{}", batch::USAGE);
            return ExitCode::from(2);
        }
    };
    let out = BufWriter::new(stdout().lock());
    match batch::run(&cfg, stdin().lock(), out) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
