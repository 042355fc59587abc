//! The `status` reply: the snapshot a board fills ([`StatusView`]) and its
//! line.

use crate::log::{Sink, SiteSource};
use crate::safety::{Fault, FaultManager, Mode, MAX_ACTIVE};
use crate::text::FlashStr;
use crate::time::TimeOrigin;
use sun_algos::UtcTime;

/// A plain snapshot of what `status` reports, filled by the firmware.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StatusView {
    /// The mode in force.
    pub mode: Mode,
    /// The UTC time and its source, `None` while no time is trusted.
    pub time: Option<(UtcTime, TimeOrigin)>,
    /// Latitude of the site in use, degrees north.
    pub lat_deg: f32,
    /// Longitude of the site in use, degrees east.
    pub lon_deg: f32,
    /// Where the site came from.
    pub site_source: SiteSource,
    /// C-axis angle, degrees (`None`: not known, e.g. before homing).
    pub c_deg: Option<f32>,
    /// A-axis angle, degrees (`None`: not known).
    pub a_deg: Option<f32>,
    /// The active faults ([`StatusView::faults_of`]).
    pub faults: [Option<Fault>; MAX_ACTIVE],
    /// The anemometer's pulse rate, Hz (`None`: no anemometer or no
    /// reading).
    pub wind_hz: Option<f32>,
}

impl StatusView {
    /// The active faults of `m`, for [`StatusView::faults`].
    pub fn faults_of(m: &FaultManager) -> [Option<Fault>; MAX_ACTIVE] {
        let mut f = [None; MAX_ACTIVE];
        for (slot, a) in f.iter_mut().zip(m.active()) {
            *slot = Some(a.fault);
        }
        f
    }
}

/// What `status` shows for a value it does not have (one copy of the
/// text).
const NONE: FlashStr = crate::flash_str!("none");

fn write_opt_number(out: &mut dyn Sink, v: Option<f32>, decimals: u8) {
    match v {
        Some(v) => out.fixed(v, decimals),
        None => out.flash(NONE),
    }
}

/// The reply to `status`, one line:
/// `ok mode=tracking utc=2026-03-20T12:00:00Z time=gps lat=11.9683
/// lon=8.4261 site=config c=12.50 a=-30.25 faults=none wind_hz=3.20`
/// (latitude and longitude with 4 decimals, angles and wind with 2, as the
/// log; `none` for what is unknown; faults by [`Fault::name`], separated
/// by commas).
pub fn write_status(out: &mut dyn Sink, s: &StatusView) {
    out.flash(crate::flash_str!("ok "));
    write_status_fields(out, s);
}

/// The fields of `status` from `mode=` to the end of the line (the
/// periodic log line is `status ` and these fields).
pub fn write_status_fields(out: &mut dyn Sink, s: &StatusView) {
    out.flash(crate::flash_str!("mode="));
    out.flash(s.mode.name());
    match &s.time {
        Some((t, source)) => {
            out.flash(crate::flash_str!(" utc="));
            out.utc(t);
            out.flash(match source {
                TimeOrigin::Gps => crate::flash_str!(" time=gps"),
                TimeOrigin::Rtc => crate::flash_str!(" time=rtc"),
            });
        }
        None => out.flash(crate::flash_str!(" utc=none time=none")),
    }
    out.flash(crate::flash_str!(" lat="));
    out.fixed(s.lat_deg, 4);
    out.flash(crate::flash_str!(" lon="));
    out.fixed(s.lon_deg, 4);
    out.flash(match s.site_source {
        SiteSource::Gps => crate::flash_str!(" site=gps"),
        SiteSource::Config => crate::flash_str!(" site=config"),
    });
    out.flash(crate::flash_str!(" c="));
    write_opt_number(out, s.c_deg, 2);
    out.flash(crate::flash_str!(" a="));
    write_opt_number(out, s.a_deg, 2);
    out.flash(crate::flash_str!(" faults="));
    let mut any = false;
    for f in s.faults.iter().flatten() {
        if any {
            out.flash(crate::flash_str!(","));
        }
        out.flash(f.name());
        any = true;
    }
    if !any {
        out.flash(NONE);
    }
    out.flash(crate::flash_str!(" wind_hz="));
    write_opt_number(out, s.wind_hz, 2);
    out.flash(crate::flash_str!("\n"));
}
