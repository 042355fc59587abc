//! The tracker's main job on a host: today's set-point table.
//!
//! ```text
//! cargo run --example daily_setpoints                       # Kano, today
//! cargo run --example daily_setpoints -- --postal-code DZ:16000 --date 2022-12-26
//! cargo run --example daily_setpoints -- --lat 25.37 --lon 51.49 --format csv
//! ```
//! Options: `--lat`/`--lon` or `--postal-code CC:CODE`, `--date YYYY-MM-DD`,
//! `--interval-min N`, `--algorithm NAME`, `--float f32|f64`,
//! `--format table|csv`, `--allow-out-of-range`; `--help` lists them with
//! their defaults and the algorithms with their validity years.
//!
//! A date outside the algorithm's validity range (`Algorithm::validity_years`,
//! e.g. psa-2020: 2020 to 2050) is refused with the reason on stderr and exit
//! code 2, unless `--allow-out-of-range` is given: then the table is computed
//! and a warning goes to stderr.

#[path = "daily_setpoints_support/run.rs"]
mod run;

use std::process::ExitCode;
use std::time::{SystemTime, UNIX_EPOCH};

use sun_algos::UtcTime;

fn main() -> ExitCode {
    let now_s = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let today = UtcTime::from_unix_seconds(now_s)
        .map(|t| t.ymd())
        .unwrap_or((2026, 1, 1));
    run::cli::main(run::TOOL, |args, out, err| {
        match run::run(args, today, out, err) {
            Ok(()) => 0,
            Err(msg) => run::cli::usage_error(run::TOOL, &msg, err),
        }
    })
}
