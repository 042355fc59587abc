//! The PC monitor of a tracker's serial log.
//!
//! ```text
//! cargo run --profile host --example monitor -- --port /dev/ttyUSB0 [--baud 115200]
//! cargo run --profile host --example monitor -- --port /dev/ttyACM0 --send status --send faults
//! cargo run --profile host --example monitor -- --file day.log --csv day.csv --svg day.svg
//! ```
//!
//! Reads the log every image writes (`src/log.rs`; the line shapes and how
//! they are read are in `monitor_support/board_log.rs`) from the board's
//! serial port (`monitor_support/port.rs`, the `serialport` crate) or from
//! a file, and echoes every line to stdout: lines it does not know are
//! passed through. It follows the mode and the active faults, writes one
//! CSV row per set-point with the mode and faults in force (`--csv`), draws
//! the day (`--svg`, `monitor_support/svg.rs`: sun elevation and azimuth,
//! commanded c and a, mode band, fault rows), and types `--send` lines into
//! the board's console (`src/console/`), showing the `ok`/`error`
//! replies. `--help` lists every option with its default.

use std::process::ExitCode;

#[path = "monitor_support/run.rs"]
mod run;

fn main() -> ExitCode {
    run::cli::main(run::TOOL, run::run)
}
