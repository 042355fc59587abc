//! ATmega328P (Arduino Uno class) tracker image: seed chowdhury-2019's
//! build — RTC (DS3231 on TWI) + a stored site + `psa-2020` in `f32` + two
//! positional servos — with the seed's real-time 4-minute set-point loop.
//!
//! Pins: servo A (tilt, the panel's slope) on OC1A = PB1 (Uno D9), servo B
//! (azimuth) on OC1B = PB2 (D10), Timer1 fast PWM at 50 Hz; DS3231 on
//! SDA/SCL (A4/A5); log on USART0 (D0/D1) at 115200 baud.
//!
//! Under simavr no RTC answers, so the image runs one compressed day on a
//! simulated clock (see `fw/track.rs`) and prints every set-point:
//! `cargo +nightly avr-run`. The seed's shaft encoders are not read yet.
#![cfg_attr(target_os = "none", no_std, no_main)]

#[cfg(target_arch = "avr")]
use avr_device::atmega328p as chip;
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
    use suntracker::scheduler::SetPoint;

    /// The stored site: Kano, Nigeria (seed jimoh-2019's site).
    const SITE_LAT_DEG: f32 = 11.9683;
    const SITE_LON_DEG: f32 = 8.4261;

    /// Set-point interval: the seed's 4 minutes. The Uno computes each
    /// set-point when it is due instead of storing the library scheduler's
    /// day table: that table holds a whole (polar) day, 360 entries of 17
    /// bytes = 6 KB at 4 minutes, three times the part's RAM, and the
    /// scheduler's planning code alone is larger than the part's flash.
    const STEP_S: u32 = 240;

    /// Servo pulse range: 500 µs at 0°, 2,500 µs at 180° (common hobby
    /// servos); Timer1 counts 0.5 µs (16 MHz / 8).
    const PULSE_MIN_US: f32 = 500.0;
    const PULSE_PER_DEG_US: f32 = 2000.0 / 180.0;
    /// 20 ms frame: TOP = 20,000 µs × 2 − 1.
    const FRAME_TOP: u16 = 39_999;

    struct Uno {
        twi: twi::Twi,
        tc1: chip::TC1,
    }

    /// Servo angle (0–180°) to Timer1 compare counts.
    fn pulse_counts(angle_deg: f32) -> (u16, u16) {
        let angle = angle_deg.clamp(0.0, 180.0);
        let us = PULSE_MIN_US + angle * PULSE_PER_DEG_US;
        (us as u16, (us * 2.0) as u16)
    }

    impl track::Board for Uno {
        fn rtc_now(&mut self) -> Result<UtcTime, &'static str> {
            twi::ds3231_now(&mut self.twi)
        }

        fn drive(&mut self, sp: &SetPoint<f32>, out: &mut dyn Sink) {
            // Servo A: the panel's slope (0° flat … 90° vertical).
            // Servo B: azimuth over the half circle 90°–270° (east–south–
            // west), servo 0° = east.
            let (us_a, counts_a) = pulse_counts(sp.slope_deg);
            let (us_b, counts_b) = pulse_counts(sp.azimuth_deg - 90.0);
            self.tc1.ocr1a().write(|w| w.set(counts_a));
            self.tc1.ocr1b().write(|w| w.set(counts_b));
            out.text(" servo_us=");
            out.u32(u32::from(us_a));
            out.text(",");
            out.u32(u32::from(us_b));
        }
    }

    #[no_mangle]
    pub extern "C" fn main() -> ! {
        // SAFETY: taken once, at the start of the only thread.
        let dp = unsafe { chip::Peripherals::steal() };
        let mut out = uart::Uart0::new(dp.USART0);
        out.text(suntracker::BANNER);
        out.text(" on atmega328p: boot ok\n");
        // OC1A/OC1B (PB1, PB2) as outputs; Timer1 mode 14 (fast PWM, TOP =
        // ICR1), clear on compare match, clk/8.
        // SAFETY: DDRB bits only select pin directions.
        dp.PORTB.ddrb().write(|w| unsafe { w.bits(0b0000_0110) });
        let tc1 = dp.TC1;
        tc1.icr1().write(|w| w.set(FRAME_TOP));
        tc1.tccr1a().write(|w| {
            w.wgm1()
                .set(0b10)
                .com1a()
                .match_clear()
                .com1b()
                .match_clear()
        });
        tc1.tccr1b()
            .write(|w| w.wgm1().set(0b11).cs1().prescale_8());
        let mut board = Uno {
            twi: twi::Twi::new(dp.TWI),
            tc1,
        };
        match Site::new(SITE_LAT_DEG, SITE_LON_DEG) {
            Ok(site) => track::run_realtime(&mut board, &mut out, site, STEP_S),
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
