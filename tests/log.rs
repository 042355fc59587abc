//! The log line shapes every image writes (src/log.rs), byte for byte.

mod common;

use common::host_io::Buf;
use sun_algos::UtcTime;
use suntracker::config::Config;
use suntracker::log::{self, ChangeLog, Sink, SiteSource};
use suntracker::safety::{AxisId, Fault, FaultManager, Mode};
use suntracker::time::TimeOrigin;

fn t(s: &str) -> UtcTime {
    s.parse().unwrap()
}

#[test]
fn every_line_shape() {
    let mut b = Buf::default();
    log::boot(&mut b, "mega");
    assert_eq!(
        b.take(),
        format!("boot suntracker {} board=mega\n", env!("CARGO_PKG_VERSION"))
    );
    log::time(&mut b, TimeOrigin::Gps, &t("2026-03-20T06:30:05Z"));
    assert_eq!(b.take(), "time source=gps utc=2026-03-20T06:30:05Z\n");
    log::time(&mut b, TimeOrigin::Rtc, &t("2031-01-02T23:59:59Z"));
    assert_eq!(b.take(), "time source=rtc utc=2031-01-02T23:59:59Z\n");
    log::site(&mut b, SiteSource::Config, 11.9683, 8.4261);
    assert_eq!(b.take(), "site source=config lat=11.9683 lon=8.4261\n");
    log::site(&mut b, SiteSource::Gps, -33.92487, -18.42406);
    assert_eq!(b.take(), "site source=gps lat=-33.9249 lon=-18.4241\n");
    log::setpoint(
        &mut b,
        &t("2026-03-20T12:00:00Z"),
        12.3456,
        181.0004,
        -1.004,
        12.34,
    );
    assert_eq!(
        b.take(),
        "setpoint utc=2026-03-20T12:00:00Z zenith=12.346 azimuth=181.000 c=-1.00 a=12.34\n"
    );
    log::setpoint_with_panel(
        &mut b,
        &t("2026-03-20T12:00:00Z"),
        12.3456,
        181.0004,
        -1.004,
        12.34,
        7_105,
    );
    assert_eq!(
        b.take(),
        "setpoint utc=2026-03-20T12:00:00Z zenith=12.346 azimuth=181.000 c=-1.00 a=12.34 panel_mv=7105\n"
    );
    log::mode(&mut b, Mode::WaitForTime);
    assert_eq!(b.take(), "mode wait_for_time\n");
    log::fault(&mut b, Fault::LimitSwitchHit(AxisId::C), true);
    assert_eq!(b.take(), "fault limit_switch_c raised\n");
    log::fault(&mut b, Fault::GpsTimeImplausible, false);
    assert_eq!(b.take(), "fault gps_time_implausible cleared\n");
}

#[test]
fn fixed_point_edges() {
    let mut b = Buf::default();
    for (v, d, want) in [
        (0.0f32, 2, "0.00"),
        (-0.004, 2, "0.00"),
        (-0.006, 2, "-0.01"),
        (359.9996, 3, "360.000"),
        (f32::NAN, 3, "nan"),
        (f32::INFINITY, 1, "nan"),
        (5.0e9, 0, "nan"),
        (1.5, 9, "1.500000"),
    ] {
        b.fixed(v, d);
        assert_eq!(b.take(), want, "{v} to {d}");
    }
}

#[test]
fn change_log_writes_only_what_changed() {
    let mut faults = FaultManager::new(Config::default().safety);
    let mut log = ChangeLog::new();
    let mut b = Buf::default();
    log.update(&mut b, &faults, Mode::Night);
    assert_eq!(b.take(), "mode night\n");
    log.update(&mut b, &faults, Mode::Night);
    assert_eq!(b.take(), "");
    faults.raise(Fault::GpsLost, 0);
    faults.raise(Fault::RtcInvalid, 0);
    log.update(&mut b, &faults, Mode::WaitForTime);
    assert_eq!(
        b.take(),
        "fault gps_lost raised\nfault rtc_invalid raised\nmode wait_for_time\n"
    );
    faults.raise(Fault::GpsLost, 60_000);
    faults.clear(Fault::RtcInvalid, 60_000);
    log.update(&mut b, &faults, Mode::Tracking);
    assert_eq!(b.take(), "fault rtc_invalid cleared\nmode tracking\n");
}
