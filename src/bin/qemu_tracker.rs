//! Cortex-M4F tracker image for QEMU's `mps2-an386` board.
//!
//! The tracker over the simulator's peripherals: GPS NMEA read from the
//! emulated UART0 (CMSDK APB UART at 0x4000_4000) and decoded with the
//! `drivers` crate; the site and the date come from the fix (the stored
//! site without one); then one *compressed day* on a simulated clock
//! starting at the GPS time, 60 s per loop, through the library's set-point
//! scheduler (seed jimoh-2019, 4-minute table) over `psa-2020` in `f32`,
//! and two simulated stepper axes. Logs over semihosting; exits with the
//! firmware's status, which QEMU returns as its own.
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
    use crate::track;
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hio};
    use drivers::gps::{GpsDecoder, GpsFix};
    use sun_algos::{Site, UtcTime};
    use suntracker::scheduler::{ScheduleConfig, SetPoint};

    /// The stored site, used without a GPS fix: Kano, Nigeria.
    const SITE_LAT_DEG: f32 = 11.9683;
    const SITE_LON_DEG: f32 = 8.4261;
    const TABLE_STEP_S: u32 = 240;
    const TABLE_LEN: usize = 360;
    /// Steps per degree of each simulated axis (200-step motor, 50:1 gear).
    const STEPS_PER_DEG: f32 = 10_000.0 / 360.0;
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

    struct Qemu {
        gps_time: Option<UtcTime>,
        steps: [i32; 2],
    }

    impl track::Board for Qemu {
        fn rtc_now(&mut self) -> Result<UtcTime, &'static str> {
            Err("no RTC on this board")
        }

        fn clock_start(&mut self) -> Result<UtcTime, (Option<UtcTime>, &'static str)> {
            match self.gps_time {
                Some(t) => Err((Some(t), "GPS time")),
                None => Err((track::sim_start(), "no GPS time")),
            }
        }

        fn drive(&mut self, sp: &SetPoint<f32>, out: &mut dyn Sink) {
            let target = [
                (sp.slope_deg * STEPS_PER_DEG + 0.5) as i32,
                (sp.azimuth_deg * STEPS_PER_DEG + 0.5) as i32,
            ];
            let moved = [
                target[0].abs_diff(self.steps[0]),
                target[1].abs_diff(self.steps[1]),
            ];
            self.steps = target;
            out.text(" steps=");
            out.i32(target[0]);
            out.text(",");
            out.i32(target[1]);
            out.text(" moved=");
            out.u32(moved[0]);
            out.text(",");
            out.u32(moved[1]);
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
        let mut board = Qemu {
            gps_time: None,
            steps: [0, 0],
        };
        let mut site = Site::new(SITE_LAT_DEG, SITE_LON_DEG);
        match fix {
            Some(f) => {
                let lat = f.latitude_deg.unwrap_or(f64::NAN) as f32;
                let lon = f.longitude_deg.unwrap_or(f64::NAN) as f32;
                board.gps_time = f
                    .utc
                    .and_then(|t| UtcTime::from_unix_seconds(t.unix_seconds()).ok());
                out.text(", fix ");
                if let Some(t) = board.gps_time.as_ref() {
                    out.utc(t);
                }
                out.text(" lat=");
                out.fixed(lat, 4);
                out.text(" lon=");
                out.fixed(lon, 4);
                out.text("\n");
                site = Site::new(lat, lon);
            }
            None => out.text(", no fix -> stored site\n"),
        }
        let status = match site {
            Ok(site) => {
                let config = ScheduleConfig {
                    table_step_s: TABLE_STEP_S,
                    ..ScheduleConfig::default()
                };
                track::run_table::<_, TABLE_LEN>(&mut board, &mut out, site, config);
                debug::EXIT_SUCCESS
            }
            Err(_) => {
                out.text("error: invalid site\n");
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
