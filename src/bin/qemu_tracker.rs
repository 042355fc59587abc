//! Cortex-M4F tracker image for QEMU's `mps2-an386` board.
//!
//! The whole tracker over the simulator's peripherals: GPS NMEA read from
//! the emulated UART0 (CMSDK APB UART at 0x4000_4000) and decoded with the
//! `drivers` crate; the site and the date come from the fix (the stored
//! site and the equinox without one); then one *compressed day* on a
//! simulated clock starting at the GPS time, one tick per simulated minute,
//! of the library's [`Controller`](suntracker::controller::Controller):
//! the seed jimoh-2019 scheduler (4-minute table) over `psa-2020` in `f64`
//! (software double on the M4F), the attitude module (a level mount,
//! seed portable-tracker eq. 15–21), safety and two closed-loop stepper
//! axes simulated by `sim::MotorPlant` (the axes of `examples/simulate.rs`).
//! Prints over semihosting, at each set-point or mode change, the time, the
//! set-point (slope/azimuth), the commanded pose γ,α, where the plants'
//! axes are and the pointing error against the sun (`psa-2020`, `f64`); at
//! the end the day's p95 and maximum pointing error while tracking and the
//! faults raised and left unrecovered. Exits with the firmware's status,
//! which QEMU returns as its own.
//!
//! `cargo run --release --target thumbv7em-none-eabihf --bin qemu_tracker`
//! (the runner in `.cargo/config.toml` feeds `tests/firmware/
//! gps_kano_2026-03-20.nmea` into UART0).
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(all(target_arch = "arm", target_os = "none"))]
#[path = "fw/fmt.rs"]
mod fmt;
#[cfg(all(target_arch = "arm", target_os = "none"))]
#[path = "fw/track.rs"]
mod track;

#[cfg(all(target_arch = "arm", target_os = "none"))]
mod firmware {
    use crate::fmt::Sink;
    use crate::track::{self, DELTA_T_S};
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hio};
    use drivers::gps::{GpsDecoder, GpsFix};
    use sun_algos::{Algorithm, Error as SunError, Options, Site, SunPosition, UtcTime};
    use suntracker::attitude::{angle_between_deg, sun_vector_xyz, MountAttitude, Pose};
    use suntracker::axis::FeedbackMode;
    use suntracker::config::Config;
    use suntracker::controller::{AttitudeSource, Controller, ControllerOptions, TickInputs};
    use suntracker::safety::Mode;
    use suntracker::scheduler::SetPoint;
    use suntracker::sim::plant::MotorPlant;
    use suntracker::sim::sensors::MountSensors;
    use suntracker::sources::{gps_time, site_from_fix, GpsTime, TimeConfig};
    use suntracker::traits::PositionSource;

    /// The stored site, used without a GPS fix: Kano, Nigeria.
    const SITE_LAT_DEG: f64 = 11.9683;
    const SITE_LON_DEG: f64 = 8.4261;
    /// The seed's 4-minute table: 360 entries cover any day.
    const TABLE_STEP_S: u32 = 240;
    const TABLE_LEN: usize = 360;
    /// Minutes of the compressed day (one controller tick each).
    const MINUTES: usize = 24 * 60;
    /// Anemometer pulses per minute of a calm day (5 Hz, under the 25 Hz
    /// stow threshold).
    const CALM_PULSES: u32 = 300;
    /// Polls of an idle UART before the GPS counts as silent.
    const GPS_IDLE_POLLS: u32 = 50_000_000;

    /// CMSDK APB UART (ARM DDI 0479, "APB UART"): DATA, STATE, CTRL,
    /// INTSTATUS, BAUDDIV.
    struct CmsdkUart {
        base: usize,
    }

    const DATA: usize = 0x00;
    const STATE: usize = 0x04;
    const CTRL: usize = 0x08;
    const BAUDDIV: usize = 0x10;
    const STATE_RX_FULL: u32 = 1 << 1;
    const CTRL_TX_EN: u32 = 1 << 0;
    const CTRL_RX_EN: u32 = 1 << 1;

    impl CmsdkUart {
        /// UART0 of the an386 image: 9600 baud from the 25 MHz clock
        /// (BAUDDIV = 25e6 / 9600 = 2604).
        fn uart0() -> Self {
            let u = CmsdkUart { base: 0x4000_4000 };
            u.write(BAUDDIV, 2604);
            u.write(CTRL, CTRL_TX_EN | CTRL_RX_EN);
            u
        }
        fn write(&self, offset: usize, value: u32) {
            // SAFETY: a documented register of the board's UART0.
            unsafe { core::ptr::write_volatile((self.base + offset) as *mut u32, value) }
        }
        fn read(&self, offset: usize) -> u32 {
            // SAFETY: as in `write`.
            unsafe { core::ptr::read_volatile((self.base + offset) as *const u32) }
        }
        fn try_read(&self) -> Option<u8> {
            if self.read(STATE) & STATE_RX_FULL != 0 {
                Some(self.read(DATA) as u8)
            } else {
                None
            }
        }
    }

    struct Semihosting(Option<hio::HostStream>);

    impl Sink for Semihosting {
        fn put(&mut self, bytes: &[u8]) {
            if let Some(s) = self.0.as_mut() {
                let _ = s.write_all(bytes);
            }
        }
    }

    /// Reads NMEA until a fix with time and position, or until the UART has
    /// been idle for `GPS_IDLE_POLLS` polls. Returns the fix and the number
    /// of bytes read.
    fn read_gps(uart: &CmsdkUart) -> (Option<GpsFix>, u32) {
        let mut decoder = GpsDecoder::new(u64::MAX);
        let mut bytes = 0u32;
        let mut idle = 0u32;
        while idle < GPS_IDLE_POLLS {
            match uart.try_read() {
                Some(b) => {
                    idle = 0;
                    bytes = bytes.saturating_add(1);
                    if let Some(fix) = decoder.push(b, 0) {
                        if fix.utc.is_some() && fix.has_position() {
                            return (Some(fix), bytes);
                        }
                    }
                }
                None => idle += 1,
            }
        }
        (
            decoder
                .finish()
                .filter(|f| f.utc.is_some() && f.has_position()),
            bytes,
        )
    }

    /// `psa-2020` in `f64` (software double on the M4F) for the
    /// controller: one constant algorithm, so only PSA is linked.
    struct Psa2020F64 {
        site: Site<f64>,
    }

    impl PositionSource<f64> for Psa2020F64 {
        fn site(&self) -> Site<f64> {
            self.site
        }
        #[inline(never)]
        fn position(&mut self, time: &UtcTime) -> Result<SunPosition<f64>, SunError> {
            let options = Options {
                delta_t_s: Some(f64::from(DELTA_T_S)),
                ..Options::default()
            };
            Algorithm::Psa2020.position(time, &self.site, &options)
        }
    }

    type Tracker = Controller<f64, Psa2020F64, MotorPlant, MountSensors, TABLE_LEN>;

    /// Pointing errors of the tracking minutes, for the day's percentiles.
    struct Errors {
        deg: [f32; MINUTES],
        len: usize,
    }

    impl Errors {
        fn push(&mut self, e: f32) {
            if let Some(slot) = self.deg.get_mut(self.len) {
                *slot = e;
                self.len += 1;
            }
        }
        fn used(&self) -> &[f32] {
            self.deg.get(..self.len).unwrap_or(&[])
        }
        /// The value of rank `round((n − 1)·p)` in ascending order (as
        /// `examples/simulate.rs` takes percentiles), found by counting
        /// instead of sorting.
        fn percentile(&self, p: f32) -> f32 {
            let v = self.used();
            let n = v.len();
            if n == 0 {
                return 0.0;
            }
            let k = ((n - 1) as f32 * p + 0.5) as usize;
            for &x in v {
                let below = v.iter().filter(|&&y| y < x).count();
                let at_or_below = v.iter().filter(|&&y| y <= x).count();
                if below <= k && k < at_or_below {
                    return x;
                }
            }
            0.0
        }
        fn max(&self) -> f32 {
            self.used()
                .iter()
                .fold(0.0, |m, &x| if x > m { x } else { m })
        }
    }

    /// Writes `HH:MM` of an instant.
    fn hhmm(out: &mut dyn Sink, t: &UtcTime) {
        let (h, m, _, _) = t.hms_milli();
        out.u32_padded(u32::from(h), 2);
        out.text(":");
        out.u32_padded(u32::from(m), 2);
    }

    /// Angle between the panel normal (level mount, axes where the plants
    /// are) and the sun now; `None` with the sun down.
    fn pointing_error_deg(ctl: &Tracker, sun: &mut Psa2020F64, now: &UtcTime) -> Option<f64> {
        let pos = sun.position(now).ok()?;
        if !pos.is_above_horizon() {
            return None;
        }
        let s = sun_vector_xyz(pos.elevation_deg(), pos.azimuth_deg);
        let [c, a] = ctl.axes();
        let pose = Pose {
            gamma_deg: c.drive().output_deg(),
            alpha_deg: a.drive().output_deg(),
        };
        Some(angle_between_deg(
            &MountAttitude::level().normal_xyz(&pose),
            &s,
        ))
    }

    /// One compressed day of the library controller from `start`.
    fn run_day(out: &mut dyn Sink, site: Site<f64>, start: UtcTime, errors: &mut Errors) -> bool {
        let mut config = Config::default();
        config.site.latitude_deg = site.latitude_deg() as f32;
        config.site.longitude_deg = site.longitude_deg() as f32;
        config.schedule.table_step_s = TABLE_STEP_S;
        let [c, a] = config.axes;
        // The axes of examples/simulate.rs: 1.8° steppers, 16 microsteps,
        // 100:1 gear, 0.2° backlash, 2°/s, 2^16-count output encoders.
        let plant = |min: f32, max: f32, start_deg: f64| {
            MotorPlant::stepper(
                1.8,
                16,
                100.0,
                0.2,
                2.0,
                Some(1 << 16),
                f64::from(min),
                f64::from(max),
                start_deg,
            )
        };
        let plants = [
            plant(c.min_deg, c.max_deg, 10.0),
            plant(a.min_deg, a.max_deg, 20.0),
        ];
        let options = ControllerOptions {
            feedback: FeedbackMode::ClosedLoop,
            attitude: AttitudeSource::Fixed(MountAttitude::level()),
            ..ControllerOptions::default()
        };
        let source = Psa2020F64 { site };
        let mut truth = Psa2020F64 { site };
        let Some(ctl) = cortex_m::singleton!(: Option<Tracker> = None) else {
            return false;
        };
        let ctl = match Tracker::new(config, options, source, plants, None) {
            Ok(t) => ctl.insert(t),
            Err(_) => {
                out.text("error: invalid schedule configuration\n");
                return false;
            }
        };
        out.text("controller: psa-2020 f64, table_step_s=");
        out.u32(TABLE_STEP_S);
        out.text(", level mount, stepper axes closed loop, simulated clock from ");
        out.utc(&start);
        out.text(", one day\n");
        let mut last: Option<SetPoint<f64>> = None;
        let mut last_mode: Option<Mode> = None;
        // Minutes whose time the scheduler could not plan (outside the
        // algorithm's validity range, or another scheduler error).
        let mut no_set_point_minutes = 0u32;
        for m in 0..MINUTES as i64 {
            let Ok(now) = start.add_seconds(m * 60) else {
                break;
            };
            for ax in ctl.axes_mut().iter_mut() {
                ax.drive_mut().begin_tick(60.0);
            }
            // The compressed day's monotonic clock: one minute a tick.
            let now_ms = (m as u64).saturating_mul(60_000);
            let report = ctl.tick(&TickInputs {
                now_ms,
                now,
                time_valid: true,
                gps_fix: true,
                gps_time_implausible: false,
                wind_pulses: CALM_PULSES,
                wind_interval_ms: 60_000,
            });
            if report.schedule_error.is_some() {
                no_set_point_minutes = no_set_point_minutes.saturating_add(1);
            }
            let err = pointing_error_deg(ctl, &mut truth, &now);
            if report.mode == Mode::Tracking {
                if let Some(e) = err {
                    errors.push(e as f32);
                }
            }
            let new_set_point = report.set_point != last;
            if !new_set_point && last_mode == Some(report.mode) {
                continue;
            }
            last = report.set_point;
            last_mode = Some(report.mode);
            hhmm(out, &now);
            match report.set_point {
                Some(sp) if new_set_point => {
                    out.text(" set-point slope=");
                    out.fixed(sp.slope_deg as f32, 1);
                    out.text(" az=");
                    out.fixed(sp.azimuth_deg as f32, 1);
                }
                _ => out.text(" mode change"),
            }
            match report.target {
                Some(p) => {
                    out.text(" target=");
                    out.fixed(p.gamma_deg as f32, 2);
                    out.text(",");
                    out.fixed(p.alpha_deg as f32, 2);
                }
                None => out.text(" target=none"),
            }
            let [c, a] = ctl.axes();
            out.text(" axes=");
            out.fixed(c.drive().output_deg() as f32, 2);
            out.text(",");
            out.fixed(a.drive().output_deg() as f32, 2);
            out.text(" err=");
            match err {
                Some(e) => out.fixed(e as f32, 3),
                None => out.text("night"),
            }
            out.text(" mode=");
            out.text(mode_name(report.mode));
            out.text("\n");
        }
        let f = ctl.faults();
        let unrecovered = (f.active_count() as u32).saturating_add(f.dropped);
        out.text("day done: tracking minutes=");
        out.u32(errors.len as u32);
        out.text(" pointing error p95=");
        out.fixed(errors.percentile(0.95), 3);
        out.text(" max=");
        out.fixed(errors.max(), 3);
        out.text(" deg, faults raised=");
        out.u32(f.raised);
        out.text(" unrecovered=");
        out.u32(unrecovered);
        out.text(", table entries=");
        out.u32(ctl.scheduler().table().len() as u32);
        out.text("\n");
        if no_set_point_minutes > 0 {
            out.text("error: no set-point could be computed for ");
            out.u32(no_set_point_minutes);
            out.text(" minutes (time outside psa-2020's validity range 2020-2050)\n");
        }
        unrecovered == 0 && no_set_point_minutes == 0 && errors.len > 0
    }

    fn mode_name(m: Mode) -> &'static str {
        match m {
            Mode::SafeStop => "safe-stop",
            Mode::WindStow => "wind-stow",
            Mode::CommandStow => "command-stow",
            Mode::WaitForTime => "wait-for-time",
            Mode::Manual => "manual",
            Mode::Night => "night",
            Mode::Homing => "homing",
            Mode::Tracking => "tracking",
        }
    }

    #[entry]
    fn main() -> ! {
        let mut out = Semihosting(hio::hstdout().ok());
        out.text(suntracker::BANNER);
        out.text(" on qemu mps2-an386 (cortex-m4f): boot ok\n");
        let uart = CmsdkUart::uart0();
        let (fix, bytes) = read_gps(&uart);
        out.text("gps: ");
        out.u32(bytes);
        out.text(" bytes of NMEA on UART0");
        let stored = Site::new(SITE_LAT_DEG, SITE_LON_DEG);
        let mut site = stored;
        let mut start = None;
        let mut time_rejected = false;
        match fix {
            Some(f) => {
                // The GPS position only when it is a plausible one; else the
                // stored site. The decoder ran with a monotonic time of 0
                // and the fix is taken at once, so its age is 0.
                let time_cfg = TimeConfig::default();
                match gps_time(&f, 0, &time_cfg) {
                    GpsTime::Trusted(t) => start = Some(t),
                    GpsTime::Implausible(t) => {
                        time_rejected = true;
                        out.text(", date ");
                        out.utc(&t);
                        out.text(" outside the firmware's 1024-week window (GPS week rollover): not trusted");
                    }
                    GpsTime::NoFix | GpsTime::Stale => {}
                }
                match site_from_fix(&f) {
                    Some(s) => {
                        match start.as_ref() {
                            Some(t) => {
                                out.text(", fix ");
                                out.utc(t);
                            }
                            None => out.text(", position"),
                        }
                        out.text(" lat=");
                        out.fixed(s.latitude_deg() as f32, 4);
                        out.text(" lon=");
                        out.fixed(s.longitude_deg() as f32, 4);
                        out.text("\n");
                        site = Ok(s);
                    }
                    None => out.text(", no valid position -> stored site\n"),
                }
            }
            None => out.text(", no fix -> stored site\n"),
        }
        if time_rejected {
            // No RTC on this board: without a trusted time nothing tracks.
            out.text("error: no trusted time (waiting for time); 0 tracking minutes\n");
            debug::exit(debug::EXIT_FAILURE);
            #[allow(clippy::empty_loop)]
            loop {}
        }
        let start = start.or_else(track::sim_start);
        let status = match (site, start) {
            (Ok(site), Some(start)) => {
                out.text("site lat=");
                out.fixed(site.latitude_deg() as f32, 4);
                out.text(" lon=");
                out.fixed(site.longitude_deg() as f32, 4);
                out.text("\n");
                let Some(errors) = cortex_m::singleton!(: Errors = Errors {
                    deg: [0.0; MINUTES],
                    len: 0,
                }) else {
                    debug::exit(debug::EXIT_FAILURE);
                    #[allow(clippy::empty_loop)]
                    loop {}
                };
                if run_day(&mut out, site, start, errors) {
                    debug::EXIT_SUCCESS
                } else {
                    debug::EXIT_FAILURE
                }
            }
            _ => {
                out.text("error: invalid site or start time\n");
                debug::EXIT_FAILURE
            }
        };
        debug::exit(status);
        #[allow(clippy::empty_loop)]
        loop {}
    }

    #[panic_handler]
    fn panic(_info: &core::panic::PanicInfo) -> ! {
        let mut out = Semihosting(hio::hstdout().ok());
        out.text("panic\n");
        debug::exit(debug::EXIT_FAILURE);
        #[allow(clippy::empty_loop)]
        loop {}
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    println!("{} on host: boot ok", suntracker::BANNER);
}
