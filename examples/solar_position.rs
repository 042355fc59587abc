//! Batch sun positions from a CSV file.
//!
//! ```text
//! cargo run --profile host --example solar_position -- --algorithm NAME --float f32|f64 \
//!     [--pressure HPA --temperature C] [--allow-out-of-range] [--threads N] < in.csv > out.csv
//! ```
//!
//! (`--profile host`: the workspace's optimised host build, see the root
//! Cargo.toml; `--release` works too, with the firmware's size-optimised
//! code.) `--help` lists the options with their defaults and the algorithms
//! with their validity years.
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
//!
//! Reading, computing and writing run in parallel on all cores (`--threads`
//! to choose), in chunks of whole records with a bounded number in flight:
//! constant memory for any input size, output in input order, the same
//! bytes whatever the thread count (see `solar_position_support/batch.rs`).
//!
//! Exit status: 0 when every row was handled (error rows included), 1 for
//! a read or write error or an unusable header, 2 for a usage error.

#[path = "solar_position_support/batch.rs"]
mod batch;

use std::io::stdin;
use std::process::ExitCode;

fn main() -> ExitCode {
    batch::cli::main(batch::TOOL, |args, out, err| {
        // stdout is line-buffered: each chunk of rows goes out in one write.
        batch::command(args, stdin(), out, err)
    })
}
