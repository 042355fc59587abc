//! A day or a year of the whole tracker at 1-minute resolution, against the
//! plant and sensor models of `sim`, optionally replaying a
//! scenario of field incidents and writing a per-minute trace.
//!
//! ```text
//! cargo run --profile host --example simulate -- --lat 11.9683 --lon 8.4261 \
//!     --start 2026-01-01 --days 365 --drive stepper|servo \
//!     --feedback encoder|sensors --mount level|portable [--faults] [--seed N] \
//!     [--scenario tests/scenarios/wind_clock_step_back.csv] [--trace OUT.csv] \
//!     [--svg OUT.svg]
//! ```
//!
//! Every minute the GPS receiver model writes one NMEA epoch for the true
//! time; the bytes go through the GPS decoder and the time keeper (over a
//! simulated RTC) to the controller, and the site follows GPS from the
//! stored configuration's site. A scenario file (format in
//! `sim::scenario`) steps clocks, breaks GPS, the RTC, switches,
//! motors, encoders and the attitude sensor, cycles power and sends
//! operator commands at given minutes.
//!
//! Pointing error is the angle between the true panel normal (true mount
//! attitude, true axis angles of the plants) and the sun at the true time
//! and site, over the minutes the controller is in tracking mode with the
//! sun up. Energy is clear-sky beam irradiance (ASHRAE model,
//! `sun_algos::geometry::irradiance`) times the cosine of incidence, summed
//! per minute; "ideal" has zero incidence, "fixed" is a panel tilted at the
//! latitude toward the equator.
//!
//! `--faults` adds a random schedule: daily random conditions and, about
//! once a year each, clock steps both ways, a week-rollover GPS date, an
//! impossible GPS position, a limit switch stuck closed and an RTC power
//! loss while GPS is off; a technician clears a safe stop the next morning
//! once the injected cause is gone. It adds weather days too, a handful of
//! each kind a year (`simulate_support/schedule.rs`): snow, hail warnings,
//! the plant's stow contact, a sagging supply and overcast days, with the
//! supply watch and the overcast mode turned on for the run. The summary
//! counts the minutes in each mode and the times each was entered.
//!
//! `--svg OUT.svg` draws the run (`simulate_support/svg.rs`): the pointing
//! error while tracking, the controller's mode and the active faults over
//! time. `--help` lists every option with its default.
//!
//! The release profile aborts on panic, so a run that prints its last line
//! had no panic. Bad arguments or a malformed scenario exit with code 2.

use std::process::ExitCode;

#[path = "simulate_support/run.rs"]
mod run;
#[path = "simulate_support/schedule.rs"]
mod schedule;

fn main() -> ExitCode {
    run::cli::main(run::TOOL, run::run)
}
