//! STM32F411 "Black Pill" tracker image, through `stm32f4xx-hal` 0.23
//! (embedded-hal 1.0) and the `drivers` crate.
//!
//! | function | peripheral | pins |
//! |---|---|---|
//! | DS3231 RTC | I2C1, 100 kHz | PB6 SCL, PB7 SDA |
//! | QMC5883L compass | I2C2, 100 kHz | PB10 SCL, PB9 SDA |
//! | GPS (NMEA, 9600 baud) | USART1 RX | PA10 |
//! | RS-485 inclinometer (WitMotion, Modbus RTU, 9600 baud) | USART2 + direction | PA2 TX, PA3 RX, PA1 DE/RE |
//! | log (115200 baud) | USART6 TX | PA11 |
//! | H-bridge, axis A (slope) | GPIO | PB12–PB15 |
//! | H-bridge, axis B (azimuth) | GPIO | PA4–PA7 |
//! | 1 Hz tick | TIM2 | — |
//!
//! Every tick it reads the RTC (disciplined by GPS time when a fix
//! arrives), runs the library's set-point scheduler (seed jimoh-2019,
//! 4-minute table, `psa-2020` in `f32`) and steps both axes to new
//! set-points in full steps. The inclinometer and compass are read once at
//! boot and logged; their attitude is not yet applied (a level mount facing
//! north is assumed, as on the ATmega2560 image).
//!
//! Build (own memory map, boards/stm32f411/memory.x, chosen by build.rs):
//! `cargo build --release --target thumbv7em-none-eabihf --features stm32f411 --bin blackpill_tracker`
//! Flash and run with a debug probe (ST-Link, CMSIS-DAP):
//! `probe-rs run --chip STM32F411CEUx target/thumbv7em-none-eabihf/release/blackpill_tracker`
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
    use drivers::compass::qmc5883l::{Config as CompassConfig, Qmc5883l};
    use drivers::gps::GpsDecoder;
    use drivers::rtc::{sync_from_gps, Clock, Ds3231};
    use drivers::tilt::modbus::Timeout;
    use drivers::tilt::WitInclinometer;
    use hal::gpio::{ErasedPin, Output};
    use hal::i2c::{I2c, Mode};
    use hal::pac;
    use hal::prelude::*;
    use hal::rcc::Config;
    use hal::serial::{Rx, Serial, Tx};
    use hal::timer::CounterHz;
    use stm32f4xx_hal as hal;
    use sun_algos::{Site, UtcTime};
    use suntracker::clock::DateWindow;
    use suntracker::hw::datetime_from_utc;
    use suntracker::scheduler::{ScheduleConfig, SetPoint};
    use suntracker::sources::{gps_time, GpsTime, TimeConfig};

    /// The stored site, used until GPS gives one: Kano, Nigeria.
    const SITE_LAT_DEG: f32 = 11.9683;
    const SITE_LON_DEG: f32 = 8.4261;
    const TABLE_STEP_S: u32 = 240;
    const TABLE_LEN: usize = 360;
    /// 200-step motor through a 50:1 worm gear.
    const STEPS_PER_DEG: f32 = 10_000.0 / 360.0;
    /// Full-step (two-phase-on) pattern of the four H-bridge inputs.
    const FULL_STEP: [u8; 4] = [0b0101, 0b0110, 0b1010, 0b1001];
    /// 1 ms per step at 96 MHz.
    const STEP_DELAY_CYCLES: u32 = 96_000;
    /// GPS time older than this many seconds of RTC drift resets the RTC.
    const MAX_RTC_DRIFT_S: u32 = 2;

    /// USART2 with its RS-485 direction pin as an embedded-io port for the
    /// Modbus master (which drives the direction pin itself).
    struct Rs485 {
        serial: Serial<pac::USART2>,
    }

    impl embedded_io::ErrorType for Rs485 {
        type Error = hal::serial::Error;
    }

    impl embedded_io::Read for Rs485 {
        fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
            let Some(first) = buf.first_mut() else {
                return Ok(0);
            };
            *first = hal::block!(hal::prelude::_embedded_hal_serial_nb_Read::read(
                &mut self.serial
            ))?;
            Ok(1)
        }
    }

    impl embedded_io::ReadReady for Rs485 {
        fn read_ready(&mut self) -> Result<bool, Self::Error> {
            Ok(self.serial.is_rx_not_empty())
        }
    }

    impl embedded_io::Write for Rs485 {
        fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
            embedded_io::Write::write(&mut self.serial, buf)
        }
        fn flush(&mut self) -> Result<(), Self::Error> {
            embedded_io::Write::flush(&mut self.serial)
        }
    }

    struct Log(Tx<pac::USART6>);

    impl Sink for Log {
        fn put(&mut self, bytes: &[u8]) {
            // Not `write_all`, which panics on a zero-length write.
            let mut rest = bytes;
            while !rest.is_empty() {
                match embedded_io::Write::write(&mut self.0, rest) {
                    Ok(n) if n > 0 => rest = rest.get(n..).unwrap_or(&[]),
                    _ => break,
                }
            }
        }
    }

    struct BlackPill {
        rtc: Ds3231<I2c<pac::I2C1>>,
        gps: Rx<pac::USART1>,
        decoder: GpsDecoder,
        tick: CounterHz<pac::TIM2>,
        /// Monotonic milliseconds: 1000 per 1 Hz tick.
        ms: u64,
        coils: [[ErasedPin<Output>; 4]; 2],
        steps: [i32; 2],
    }

    impl BlackPill {
        /// Feeds waiting GPS bytes to the decoder; only a fix whose time
        /// the tracker trusts (a valid fix with a plausible position, fresh,
        /// inside the firmware's date window: `sources::gps_time`)
        /// disciplines the RTC. An RMC with status V never sets it.
        fn poll_gps(&mut self) {
            let cfg = TimeConfig::default();
            while let Ok(b) = hal::prelude::_embedded_hal_serial_nb_Read::read(&mut self.gps) {
                if let Some(fix) = self.decoder.push(b, self.ms) {
                    if let GpsTime::Trusted(t) = gps_time(&fix, self.ms, &cfg) {
                        if let Ok(utc) = datetime_from_utc(&t) {
                            let _ = sync_from_gps(&mut self.rtc, &utc, MAX_RTC_DRIFT_S);
                        }
                    }
                }
            }
        }

        fn set_coils(&mut self) {
            for (axis, pins) in self.coils.iter_mut().enumerate() {
                let s = self.steps.get(axis).copied().unwrap_or(0);
                let pattern = FULL_STEP
                    .get(s.rem_euclid(4) as usize)
                    .copied()
                    .unwrap_or(0);
                for (bit, pin) in pins.iter_mut().enumerate() {
                    pin.set_state((pattern & (1 << bit) != 0).into());
                }
            }
        }
    }

    impl track::Board for BlackPill {
        fn rtc_now(&mut self) -> Result<UtcTime, &'static str> {
            let _ = hal::block!(self.tick.wait());
            self.ms = self.ms.saturating_add(1000);
            self.poll_gps();
            if self.rtc.lost_power().map_err(|_| "DS3231 read failed")? {
                return Err("RTC lost power");
            }
            let dt = self.rtc.datetime().map_err(|_| "DS3231 read failed")?;
            let t = UtcTime::from_unix_seconds(dt.unix_seconds())
                .map_err(|_| "RTC time out of range")?;
            if DateWindow::firmware().contains(&t) {
                Ok(t)
            } else {
                Err("RTC date outside the firmware's window")
            }
        }

        fn drive(&mut self, sp: &SetPoint<f32>, out: &mut dyn Sink) {
            let target = [
                (sp.slope_deg * STEPS_PER_DEG + 0.5) as i32,
                (sp.azimuth_deg * STEPS_PER_DEG + 0.5) as i32,
            ];
            while self.steps != target {
                for (s, t) in self.steps.iter_mut().zip(target) {
                    *s += (t - *s).signum();
                }
                self.set_coils();
                cortex_m::asm::delay(STEP_DELAY_CYCLES);
            }
            for pin in self.coils.iter_mut().flatten() {
                pin.set_low();
            }
            out.text(" steps=");
            out.i32(target[0]);
            out.text(",");
            out.i32(target[1]);
        }
    }

    #[entry]
    fn main() -> ! {
        let Some(dp) = pac::Peripherals::take() else {
            #[allow(clippy::empty_loop)]
            loop {}
        };
        // 25 MHz crystal of the Black Pill, 96 MHz system clock.
        let mut rcc = dp.RCC.freeze(Config::hse(25.MHz()).sysclk(96.MHz()));
        let gpioa = dp.GPIOA.split(&mut rcc);
        let gpiob = dp.GPIOB.split(&mut rcc);

        let mut log = match dp.USART6.tx(gpioa.pa11, 115_200.bps(), &mut rcc) {
            Ok(tx) => Log(tx),
            Err(_) => loop {
                cortex_m::asm::wfi();
            },
        };
        log.text(suntracker::BANNER);
        log.text(" on stm32f411 (black pill): boot ok\n");

        let i2c1 = I2c::new(
            dp.I2C1,
            (gpiob.pb6, gpiob.pb7),
            Mode::standard(100.kHz()),
            &mut rcc,
        );
        let i2c2 = I2c::new(
            dp.I2C2,
            (gpiob.pb10, gpiob.pb9),
            Mode::standard(100.kHz()),
            &mut rcc,
        );
        match Qmc5883l::new(i2c2, CompassConfig::default()) {
            Ok(mut compass) => match compass.read_raw() {
                Ok(_) => log.text("compass: QMC5883L ok\n"),
                Err(_) => log.text("compass: QMC5883L read failed\n"),
            },
            Err(_) => log.text("compass: QMC5883L not answering\n"),
        }

        let de = gpioa.pa1.into_push_pull_output();
        let delay = dp.TIM5.delay_us(&mut rcc);
        match dp
            .USART2
            .serial((gpioa.pa2, gpioa.pa3), 9_600.bps(), &mut rcc)
        {
            Ok(serial) => {
                let timeout = Timeout {
                    timeout_us: 100_000,
                    poll_us: 100,
                };
                let mut tilt = WitInclinometer::new(Rs485 { serial }, de, delay, 0x50, timeout);
                match tilt.read() {
                    Ok(i) => {
                        log.text("inclinometer: roll=");
                        log.fixed(i.roll_deg, 2);
                        log.text(" pitch=");
                        log.fixed(i.pitch_deg, 2);
                        log.text("\n");
                    }
                    Err(_) => log.text("inclinometer: no answer on RS-485\n"),
                }
            }
            Err(_) => log.text("inclinometer: USART2 configuration rejected\n"),
        }

        let gps = match dp.USART1.rx(gpioa.pa10, 9_600.bps(), &mut rcc) {
            Ok(rx) => rx,
            Err(_) => loop {
                cortex_m::asm::wfi();
            },
        };
        let mut tick = dp.TIM2.counter_hz(&mut rcc);
        if tick.start(1.Hz()).is_err() {
            log.text("error: timer\n");
        }
        let coils = [
            [
                gpiob.pb12.into_push_pull_output().erase(),
                gpiob.pb13.into_push_pull_output().erase(),
                gpiob.pb14.into_push_pull_output().erase(),
                gpiob.pb15.into_push_pull_output().erase(),
            ],
            [
                gpioa.pa4.into_push_pull_output().erase(),
                gpioa.pa5.into_push_pull_output().erase(),
                gpioa.pa6.into_push_pull_output().erase(),
                gpioa.pa7.into_push_pull_output().erase(),
            ],
        ];
        let mut board = BlackPill {
            rtc: Ds3231::new(i2c1),
            gps,
            decoder: GpsDecoder::new(10_000),
            tick,
            ms: 0,
            coils,
            steps: [0, 0],
        };
        if let Ok(site) = Site::new(SITE_LAT_DEG, SITE_LON_DEG) {
            let config = ScheduleConfig {
                table_step_s: TABLE_STEP_S,
                ..ScheduleConfig::default()
            };
            loop {
                track::run_table::<_, TABLE_LEN>(&mut board, &mut log, site, config);
            }
        }
        loop {
            cortex_m::asm::wfi();
        }
    }

    #[panic_handler]
    fn panic(_info: &core::panic::PanicInfo) -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    println!(
        "{}: blackpill_tracker runs on an STM32F411",
        suntracker::BANNER
    );
}
