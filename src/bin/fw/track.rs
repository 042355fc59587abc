//! The tracking loop shared by the firmware images: the library's set-point
//! scheduler (seed jimoh-2019) over `psa-2020` in `f32`, a clock, and a
//! board that drives two axes. Prints every action over the UART.
//!
//! Without a working RTC (simavr has none on its TWI bus) the image runs a
//! *compressed day*: a simulated clock starting at [`SIM_START`] advances
//! [`SIM_STEP_S`] per loop, so a whole day passes in about a second of
//! simulated CPU time. The output says which clock it used.

// Each image uses a part.
#![allow(dead_code)]

use crate::fmt::Sink;
use sun_algos::{Algorithm, Error as SunError, Options, Site, SunPosition, UtcTime};
use suntracker::scheduler::{Action, ScheduleConfig, Scheduler, SetPoint};
use suntracker::traits::PositionSource;

/// Start of the simulated day: 2026-03-20 00:00 UTC (the March equinox).
pub const SIM_START: (i32, u8, u8) = (2026, 3, 20);
/// Simulated seconds per loop of the compressed day.
pub const SIM_STEP_S: i64 = 60;
/// ΔT for 2026 (TT − UT1, seconds; IERS Bulletin A order of magnitude).
pub const DELTA_T_S: f32 = 69.2;

/// `psa-2020` in `f32` for one site: a constant algorithm, so only PSA is
/// linked into the image.
pub struct Psa2020Source {
    pub site: Site<f32>,
}

impl PositionSource<f32> for Psa2020Source {
    fn site(&self) -> Site<f32> {
        self.site
    }
    // One out-of-line copy of PSA for every caller in the scheduler.
    #[inline(never)]
    fn position(&mut self, time: &UtcTime) -> Result<SunPosition<f32>, SunError> {
        let options = Options {
            delta_t_s: Some(DELTA_T_S),
            ..Options::default()
        };
        Algorithm::Psa2020.position(time, &self.site, &options)
    }
}

/// The start of the simulated day.
pub fn sim_start() -> Option<UtcTime> {
    let (y, mo, d) = SIM_START;
    UtcTime::from_ymd_hms(y, mo, d, 0, 0, 0).ok()
}

/// What an image's hardware does for the loop.
pub trait Board {
    /// The RTC's time, or a short reason why it cannot be read.
    fn rtc_now(&mut self) -> Result<UtcTime, &'static str>;
    /// Drives both axes to `sp` and writes what it did (after a space).
    fn drive(&mut self, sp: &SetPoint<f32>, out: &mut dyn Sink);
    /// Where a run's clock starts: `Ok(t)` follows the RTC from `t`;
    /// `Err((Some(t), why))` runs one compressed day on a simulated clock
    /// from `t`. By default the RTC, or the simulated equinox day without one.
    fn clock_start(&mut self) -> Result<UtcTime, (Option<UtcTime>, &'static str)> {
        self.rtc_now().map_err(|why| (sim_start(), why))
    }
}

/// Writes `HH:MM` of an instant.
fn hhmm(out: &mut dyn Sink, t: &UtcTime) {
    let (h, m, _, _) = t.hms_milli();
    out.u32_padded(u32::from(h), 2);
    out.text(":");
    out.u32_padded(u32::from(m), 2);
}

fn set_point(out: &mut dyn Sink, sp: &SetPoint<f32>) {
    out.text(" slope=");
    out.fixed(sp.slope_deg, 1);
    out.text(" az=");
    out.fixed(sp.azimuth_deg, 1);
}

/// The clock of a run: the RTC, or a simulated day when it cannot be read.
fn start_clock<B: Board>(board: &mut B, out: &mut dyn Sink) -> Result<Option<UtcTime>, ()> {
    match board.clock_start() {
        Ok(t) => {
            out.text("clock rtc ");
            out.utc(&t);
            out.text("\n");
            Ok(None)
        }
        Err((None, why)) => {
            out.text("clock: ");
            out.text(why);
            out.text(", no start time\n");
            Err(())
        }
        Err((Some(t), why)) => {
            out.text("clock: ");
            out.text(why);
            out.text(" -> simulated clock from ");
            out.utc(&t);
            out.text(", one day\n");
            Ok(Some(t))
        }
    }
}

/// The instant of loop `i`: simulated (`None` after one day) or the RTC's.
fn clock_at<B: Board>(board: &mut B, simulated: Option<UtcTime>, i: i64) -> Option<UtcTime> {
    match simulated {
        Some(start) if i <= 24 * 3600 / SIM_STEP_S => start.add_seconds(i * SIM_STEP_S).ok(),
        Some(_) => None,
        None => loop {
            if let Ok(t) = board.rtc_now() {
                break Some(t);
            }
        },
    }
}

/// Seed chowdhury-2019's loop, for parts too small for a stored day table:
/// every `step_s` seconds (on whole multiples from UTC midnight) compute the
/// sun's position now and, with the sun up, drive to it; at sunset drive to
/// the morning's first set-point (seed li-2022's home) once.
pub fn run_realtime<B: Board>(board: &mut B, out: &mut dyn Sink, site: Site<f32>, step_s: u32) {
    out.text("site lat=");
    out.fixed(site.latitude_deg(), 4);
    out.text(" lon=");
    out.fixed(site.longitude_deg(), 4);
    out.text(" algorithm=psa-2020 f32 realtime step_s=");
    out.u32(step_s);
    out.text("\n");
    let Ok(simulated) = start_clock(board, out) else {
        return;
    };
    let mut source = Psa2020Source { site };
    let mut home: Option<SetPoint<f32>> = None;
    let mut tracking = false;
    let mut last_slot: Option<u32> = None;
    let mut i: i64 = 0;
    while let Some(now) = clock_at(board, simulated, i) {
        i += 1;
        let slot = now.ms_of_day() / 1000 / step_s.max(1);
        if last_slot == Some(slot) {
            continue;
        }
        last_slot = Some(slot);
        let Ok(sun) = source.position(&now) else {
            hhmm(out, &now);
            out.text(" sun position error\n");
            continue;
        };
        if sun.zenith_deg < 90.0 {
            let sp = SetPoint::facing(&sun);
            if home.is_none() {
                home = Some(sp);
            }
            tracking = true;
            hhmm(out, &now);
            out.text(" set-point");
            set_point(out, &sp);
            board.drive(&sp, out);
            out.text("\n");
        } else if tracking {
            tracking = false;
            if let Some(sp) = home {
                hhmm(out, &now);
                out.text(" home");
                set_point(out, &sp);
                board.drive(&sp, out);
                out.text("\n");
            }
        }
    }
    out.text("day done\n");
}

/// Runs the library's scheduler over one day (simulated clock) or forever
/// (RTC).
pub fn run_table<B: Board, const N: usize>(
    board: &mut B,
    out: &mut dyn Sink,
    site: Site<f32>,
    config: ScheduleConfig,
) {
    out.text("site lat=");
    out.fixed(site.latitude_deg(), 4);
    out.text(" lon=");
    out.fixed(site.longitude_deg(), 4);
    out.text(" algorithm=psa-2020 f32 table_step_s=");
    out.u32(config.table_step_s);
    out.text("\n");
    let mut scheduler: Scheduler<f32, Psa2020Source, N> =
        match Scheduler::new(config, Psa2020Source { site }) {
            Ok(s) => s,
            Err(_) => {
                out.text("error: invalid schedule configuration\n");
                return;
            }
        };
    let Ok(simulated) = start_clock(board, out) else {
        return;
    };
    let mut i: i64 = 0;
    while let Some(now) = clock_at(board, simulated, i) {
        i += 1;
        let output = scheduler.tick(now);
        match output.action {
            Action::Idle => continue,
            Action::SetPoints(sp) => {
                hhmm(out, &now);
                out.text(" set-point");
                set_point(out, &sp);
                board.drive(&sp, out);
            }
            Action::GoHome(sp) => {
                hhmm(out, &now);
                out.text(" home");
                set_point(out, &sp);
                board.drive(&sp, out);
            }
            Action::Sleep { until } => {
                hhmm(out, &now);
                out.text(" sleep until ");
                out.utc(&until);
            }
            Action::Error(_) => {
                hhmm(out, &now);
                out.text(" schedule error, retrying");
            }
        }
        if output.clock_jump {
            out.text(" (clock jump)");
        }
        out.text("\n");
    }
    out.text("day done, table entries=");
    out.u32(scheduler.table().len() as u32);
    out.text("\n");
}
