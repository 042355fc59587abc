//! ATmega2560 (Arduino Mega class) tracker image: seed li-2022's build —
//! GPS (NMEA on USART1) + compass and inclinometer (TWI) + two steppers on
//! H-bridges — with the library's set-point scheduler (seed jimoh-2019: a
//! 4-minute day table between sunrise and sunset, stored; home at sunset).
//!
//! Pins: GPS on RX1/TX1 (Mega D19/D18) at 9600 baud; QMC5883L compass
//! (0x0D) and ADXL345 inclinometer (0x53) on SDA/SCL (D20/D21); H-bridge
//! inputs of axis A (tilt) on PA0–PA3 (D22–D25) and of axis B (azimuth) on
//! PA4–PA7 (D26–D29), full-step sequence; log on USART0 at 115200 baud.
//!
//! Without a GPS fix (simavr feeds no NMEA) the image uses the stored site;
//! without an RTC it runs one compressed day on a simulated clock. Without
//! compass and inclinometer answers it assumes a level mount facing north
//! (identity attitude) and says so. Build and run: see `.ci/firmware_env.sh`
//! (`build_avr_mega`) and `simavr -m atmega2560 -f 16000000 <elf>`.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_arch = "avr")]
use avr_device::atmega2560 as chip;
#[cfg(target_arch = "avr")]
#[path = "fw/fmt.rs"]
mod fmt;
#[cfg(target_arch = "avr")]
#[path = "fw/track.rs"]
mod track;
#[cfg(target_arch = "avr")]
#[path = "fw/avr_twi.rs"]
mod twi;
#[cfg(target_arch = "avr")]
#[path = "fw/avr_uart.rs"]
mod uart;

#[cfg(target_arch = "avr")]
mod firmware {
    use crate::fmt::Sink;
    use crate::{chip, track, twi, uart};
    use sun_algos::{Site, UtcTime};
    use suntracker::scheduler::{ScheduleConfig, SetPoint};

    /// The stored site, used without a GPS fix: Kano, Nigeria.
    const SITE_LAT_DEG: f32 = 11.9683;
    const SITE_LON_DEG: f32 = 8.4261;
    /// The seed's 4-minute table; a polar day needs 360 entries.
    const TABLE_STEP_S: u32 = 240;
    const TABLE_LEN: usize = 360;
    /// Steps per degree of each axis: 200-step motor through a 50:1 worm
    /// gear = 10,000 steps per turn.
    const STEPS_PER_DEG: f32 = 10_000.0 / 360.0;
    /// Pause between two full steps (1 ms: 1,000 steps/s).
    const STEP_DELAY_CYCLES: u32 = 16_000;
    /// Full-step (two-phase-on) coil pattern for the four H-bridge inputs.
    const FULL_STEP: [u8; 4] = [0b0101, 0b0110, 0b1010, 0b1001];
    /// Polls of USART1 while waiting for GPS (about 2 s at ~20 cycles).
    const GPS_WAIT_POLLS: u32 = 1_600_000;

    struct Mega {
        twi: twi::Twi,
        porta: chip::PORTA,
        /// Step counts of axes A and B.
        steps: [i32; 2],
    }

    impl Mega {
        fn coils(&self) -> u8 {
            let phase = |s: i32| {
                FULL_STEP
                    .get(s.rem_euclid(4) as usize)
                    .copied()
                    .unwrap_or(0)
            };
            phase(self.steps[0]) | phase(self.steps[1]) << 4
        }

        /// Steps both axes to their targets, one step of each per period.
        fn step_to(&mut self, target: [i32; 2]) -> [u32; 2] {
            let mut moved = [0u32; 2];
            while self.steps != target {
                for (axis, (s, t)) in self.steps.iter_mut().zip(target).enumerate() {
                    if *s != t {
                        *s += (t - *s).signum();
                        if let Some(m) = moved.get_mut(axis) {
                            *m += 1;
                        }
                    }
                }
                let pattern = self.coils();
                // SAFETY: PORTA only drives the H-bridge inputs.
                self.porta.porta().write(|w| unsafe { w.bits(pattern) });
                avr_device::asm::delay_cycles(STEP_DELAY_CYCLES);
            }
            // Coils off between moves (holding torque of the worm gear).
            // SAFETY: as above.
            self.porta.porta().write(|w| unsafe { w.bits(0) });
            moved
        }
    }

    impl track::Board for Mega {
        fn rtc_now(&mut self) -> Result<UtcTime, &'static str> {
            twi::ds3231_now(&mut self.twi)
        }

        fn drive(&mut self, sp: &SetPoint<f32>, out: &mut dyn Sink) {
            // Axis A: the slope; axis B: azimuth from north (a level mount
            // facing north, as no attitude sensor answered).
            let target = [
                (sp.slope_deg * STEPS_PER_DEG + 0.5) as i32,
                (sp.azimuth_deg * STEPS_PER_DEG + 0.5) as i32,
            ];
            let moved = self.step_to(target);
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

    /// Waits for NMEA bytes on USART1; reports whether any arrived.
    fn gps_heard(usart1: &chip::USART1) -> bool {
        // 9600 baud at 16 MHz, U2X1 = 0: UBRR = 16e6 / (16 · 9600) − 1 = 103.
        usart1.ubrr1().write(|w| w.set(103));
        usart1.ucsr1c().write(|w| w.ucsz1().chr8());
        usart1.ucsr1b().write(|w| w.rxen1().set_bit());
        for _ in 0..GPS_WAIT_POLLS {
            if usart1.ucsr1a().read().rxc1().bit_is_set() {
                return usart1.udr1().read().bits() == b'$';
            }
        }
        false
    }

    fn probe(twi: &mut twi::Twi, address: u8, register: u8) -> Result<u8, twi::TwiError> {
        let mut b = [0u8; 1];
        twi.write_read(address, register, &mut b).map(|()| b[0])
    }

    #[no_mangle]
    pub extern "C" fn main() -> ! {
        // SAFETY: taken once, at the start of the only thread.
        let dp = unsafe { chip::Peripherals::steal() };
        let mut out = uart::Uart0::new(dp.USART0);
        out.text(suntracker::BANNER);
        out.text(" on atmega2560: boot ok\n");
        // SAFETY: DDRA bits only select pin directions (all outputs).
        dp.PORTA.ddra().write(|w| unsafe { w.bits(0xFF) });
        let mut twi = twi::Twi::new(dp.TWI);
        if gps_heard(&dp.USART1) {
            out.text("gps: NMEA heard on USART1 (position fix not parsed on this part yet)\n");
        } else {
            out.text("gps: no NMEA on USART1 within 2 s -> stored site\n");
        }
        // QMC5883L chip-id register 0x0D reads 0xFF; ADXL345 DEVID (0x00)
        // reads 0xE5 (datasheets).
        let compass = probe(&mut twi, 0x0D, 0x0D);
        let tilt = probe(&mut twi, 0x53, 0x00);
        match (compass, tilt) {
            (Ok(0xFF), Ok(0xE5)) => out.text("attitude: QMC5883L and ADXL345 present\n"),
            _ => out
                .text("attitude: compass/inclinometer not answering -> level mount facing north\n"),
        }
        let mut board = Mega {
            twi,
            porta: dp.PORTA,
            steps: [0, 0],
        };
        match Site::new(SITE_LAT_DEG, SITE_LON_DEG) {
            Ok(site) => {
                let config = ScheduleConfig {
                    table_step_s: TABLE_STEP_S,
                    ..ScheduleConfig::default()
                };
                track::run_table::<_, TABLE_LEN>(&mut board, &mut out, site, config);
            }
            Err(_) => out.text("error: stored site invalid\n"),
        }
        uart::halt(&mut out)
    }

    #[panic_handler]
    fn panic(_info: &core::panic::PanicInfo) -> ! {
        // SAFETY: the program is over; nothing else uses USART0 any more.
        let dp = unsafe { chip::Peripherals::steal() };
        let mut out = uart::Uart0::new(dp.USART0);
        out.text("panic\n");
        uart::halt(&mut out)
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    println!("{} on host: boot ok", suntracker::BANNER);
}
