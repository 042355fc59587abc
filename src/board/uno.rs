//! The Arduino Uno tracker (ATmega328P; seed chowdhury-2019's build):
//! everything about this board in one place — pins, devices, the loop —
//! over the AVR board layer ([`super::avr`]). An image binds the Timer0
//! vector (`avr_board_interrupts!(timer0)`) and calls [`run`], as
//! `avr_tracker` does.
//!
//! | function | pin | Uno header |
//! |---|---|---|
//! | log, 115200 8N1 | USART0 TXD (PD1) | D1 (USB) |
//! | I²C 100 kHz: DS3231 0x68 | SDA/SCL (PC4/PC5) | A4/A5 |
//! | servo A (tilt: the panel's slope), 50 Hz PWM | OC1A (PB1) | D9 |
//! | servo C (azimuth), 50 Hz PWM | OC1B (PB2) | D10 |
//!
//! Wiring sketch:
//!
//! ```text
//!  Uno D9  ─ signal ┐ tilt servo (+5 V from its own supply, common GND)
//!  Uno D10 ─ signal ┘ azimuth servo
//!  Uno A4/A5 ─ SDA/SCL ─ DS3231 (CR2032 backup)
//!  Uno D0/D1 ─ USB serial: the log
//! ```
//!
//! The loop is the seed's: every [`STEP_S`] seconds (on whole multiples
//! from UTC midnight) it computes the sun's position (`psa-2020` in `f32`)
//! and, with the sun up, drives both servos to face it; no day table is
//! stored (the part has 2 KB of RAM). The time comes from the DS3231
//! through [`drivers::rtc`] and the trust rules of
//! [`crate::sources::TimeKeeper`]: an RTC that lost power, reads a date
//! outside the firmware's window or does not answer gives no time, and the
//! tracker then waits with the panel stowed flat (`mode wait_for_time`,
//! `fault rtc_invalid raised`); there is no simulated clock. At night the
//! panel also lies flat.
//!
//! The servos are positional here (500–2,500 µs for 0–180°), so the
//! azimuth covers the half circle east–south–west (azimuth 90°–270°) and
//! poses beyond it are clamped. The pose in the log uses the convention of
//! every board (the attitude module's level mount facing north): `c` =
//! 180° − azimuth (−90…+90° here), `a` = −slope (−90…0°). Servo C's 0° is
//! east (c = 90°), servo A's 0° is flat.
//!
//! The loop never blocks: one pass serves the tick when it is due (an RTC
//! read over I²C, at most one sun position, about 3 ms), feeds the
//! watchdog, and sleeps until the next Timer0 interrupt.

use drivers::gps::GpsFix;
use drivers::rtc::Ds3231;
use sun_algos::{Algorithm, Options, Site};

use super::avr::{chip, millis, sleep_until_interrupt, I2c, Millis, Usart0, Watchdog, MS_PER_TICK};
use crate::log::{self, Sink, SiteSource, TimeSource};
use crate::safety::{Fault, Mode, Sensor};
use crate::sources::{TimeConfig, TimeKeeper};

/// Board name in the boot line.
pub const BOARD: &str = "uno";
/// Log serial.
pub const LOG_BAUD_HZ: u32 = 115_200;
/// The stored site: Kano, Nigeria (seed jimoh-2019's site), degrees.
pub const SITE_LAT_DEG: f32 = 11.9683;
/// The stored site's longitude, degrees east.
pub const SITE_LON_DEG: f32 = 8.4261;
/// ΔT (TT − UT1) for the sun algorithm, seconds (2026, IERS Bulletin A
/// order of magnitude).
pub const DELTA_T_S: f32 = 69.0;
/// Set-point interval: the seed's 4 minutes.
pub const STEP_S: u32 = 240;
/// Monotonic milliseconds between two ticks (an RTC read each).
pub const TICK_MS: u64 = 1_000;

/// Servo pulse at 0°, µs (common hobby servos: 500–2,500 µs for 0–180°).
const PULSE_MIN_US: f32 = 500.0;
/// Pulse per degree of servo angle, µs.
const PULSE_PER_DEG_US: f32 = 2_000.0 / 180.0;
/// Timer1 counts per µs (16 MHz / 8).
const COUNTS_PER_US: f32 = 2.0;
/// 20 ms frame (50 Hz): TOP = 20,000 µs × 2 − 1 (ATmega328P §15.9.3 "Fast
/// PWM Mode", mode 14 with TOP = ICR1).
const FRAME_TOP: u16 = 39_999;
/// The pose's resolution: one Timer1 count of a pulse, in servo degrees
/// (0.5 µs / (2,000 µs / 180°) = 0.045°).
pub const AXIS_STEP_DEG: f32 = 1.0 / (COUNTS_PER_US * PULSE_PER_DEG_US);
/// Pose range of the servos' half circle: c −90…+90°, a −90…0°.
const C_RANGE_DEG: (f32, f32) = (-90.0, 90.0);
/// Pose range of the tilt servo.
const A_RANGE_DEG: (f32, f32) = (-90.0, 0.0);
/// The stow pose: flat (a = 0°), servo C at south (c = 0°).
const STOW_POSE_DEG: (f32, f32) = (0.0, 0.0);

/// The two servos on Timer1's compare outputs.
struct Servos {
    tc1: chip::TC1,
}

impl Servos {
    /// Timer1 in fast PWM mode 14 (TOP = ICR1) at clk/8, OC1A/OC1B cleared
    /// on compare match, both pins outputs; the first pulses are the stow
    /// pose's.
    fn start(tc1: chip::TC1, portb: &chip::PORTB) -> Self {
        // SAFETY: DDRB bits only select pin directions (PB1, PB2 out).
        portb
            .ddrb()
            .modify(|r, w| unsafe { w.bits(r.bits() | 0b0000_0110) });
        tc1.icr1().write(|w| w.set(FRAME_TOP));
        let mut servos = Servos { tc1 };
        servos.set(STOW_POSE_DEG.0, STOW_POSE_DEG.1);
        servos.tc1.tccr1a().write(|w| {
            w.wgm1()
                .set(0b10)
                .com1a()
                .match_clear()
                .com1b()
                .match_clear()
        });
        servos
            .tc1
            .tccr1b()
            .write(|w| w.wgm1().set(0b11).cs1().prescale_8());
        servos
    }

    /// Commands pose (`c_deg`, `a_deg`), clamped to the servos' range;
    /// returns the pose commanded.
    fn set(&mut self, c_deg: f32, a_deg: f32) -> (f32, f32) {
        let c = c_deg.clamp(C_RANGE_DEG.0, C_RANGE_DEG.1);
        let a = a_deg.clamp(A_RANGE_DEG.0, A_RANGE_DEG.1);
        // Servo C: 0° east (c = 90°) … 180° west (c = −90°); servo A: the
        // slope, 0° flat.
        self.tc1.ocr1b().write(|w| w.set(counts(90.0 - c)));
        self.tc1.ocr1a().write(|w| w.set(counts(-a)));
        (c, a)
    }
}

/// Timer1 compare value of a servo angle (0–180°, in range by the callers'
/// clamps; `as` saturates anyway): the pulse to the nearest count, less
/// one, since fast PWM holds the pin high for OCR1x + 1 counts
/// (ATmega328P §15.9.3: the output is set at BOTTOM and cleared at the
/// match that follows count OCR1x).
fn counts(servo_deg: f32) -> u16 {
    let pulse = (PULSE_MIN_US + servo_deg * PULSE_PER_DEG_US) * COUNTS_PER_US + 0.5;
    (pulse as u16).saturating_sub(1)
}

/// What the loop remembers between ticks.
struct Tracker {
    mode: Option<Mode>,
    fault: Option<Fault>,
    time_logged: bool,
    /// The last 4-minute slot served (days since 2000 × slots per day +
    /// slot of the day).
    last_slot: Option<i64>,
}

impl Tracker {
    fn set_mode(&mut self, out: &mut Usart0, mode: Mode) {
        if self.mode != Some(mode) {
            log::mode(out, mode);
            self.mode = Some(mode);
        }
    }

    fn set_fault(&mut self, out: &mut Usart0, fault: Option<Fault>) {
        if self.fault != fault {
            if let Some(old) = self.fault {
                log::fault(out, old, false);
            }
            if let Some(new) = fault {
                log::fault(out, new, true);
            }
            self.fault = fault;
        }
    }

    /// One tick: the time, then the set-point of a new slot.
    fn tick(
        &mut self,
        out: &mut Usart0,
        time: &mut TimeKeeper<Ds3231<I2c>>,
        servos: &mut Servos,
        site: &Site<f32>,
        now_ms: u64,
    ) {
        let status = time.update(&GpsFix::NONE, now_ms);
        let Some(now) = status.now else {
            // No trusted time: stowed, waiting; say why.
            let why = if status.rtc_error {
                Fault::I2cError(Sensor::Rtc)
            } else {
                Fault::RtcInvalid
            };
            self.set_fault(out, Some(why));
            servos.set(STOW_POSE_DEG.0, STOW_POSE_DEG.1);
            self.set_mode(out, Mode::WaitForTime);
            self.time_logged = false;
            self.last_slot = None;
            return;
        };
        if !self.time_logged {
            log::time(out, TimeSource::Rtc, &now);
            self.time_logged = true;
        }
        let slot = i64::from(now.days_since_2000()) * i64::from(86_400 / STEP_S)
            + i64::from(now.ms_of_day() / 1_000 / STEP_S);
        if self.last_slot == Some(slot) {
            return;
        }
        self.last_slot = Some(slot);
        let options = Options {
            delta_t_s: Some(DELTA_T_S),
            ..Options::default()
        };
        match Algorithm::Psa2020.position(&now, site, &options) {
            Ok(sun) if sun.zenith_deg < 90.0 => {
                self.set_fault(out, None);
                let (c, a) = servos.set(180.0 - sun.azimuth_deg, -sun.zenith_deg);
                self.set_mode(out, Mode::Tracking);
                log::setpoint(out, &now, sun.zenith_deg, sun.azimuth_deg, c, a);
            }
            Ok(_) => {
                self.set_fault(out, None);
                servos.set(STOW_POSE_DEG.0, STOW_POSE_DEG.1);
                self.set_mode(out, Mode::Night);
            }
            Err(_) => {
                // A trusted time the algorithm does not cover: stowed.
                self.set_fault(out, Some(Fault::TimeOutOfRange));
                servos.set(STOW_POSE_DEG.0, STOW_POSE_DEG.1);
                self.set_mode(out, Mode::WaitForTime);
            }
        }
    }
}

/// Starts the tracker on the board's peripherals; never returns.
pub fn run(dp: chip::Peripherals) -> ! {
    let mut out = Usart0::new_tx_only(dp.USART0, LOG_BAUD_HZ);
    let _millis = Millis::start(dp.TC0);
    let mut watchdog = Watchdog::enable(dp.WDT, &dp.CPU);
    let mut servos = Servos::start(dp.TC1, &dp.PORTB);
    // SAFETY: the Timer0 tick, the only vector, is set up above.
    unsafe { avr_device::interrupt::enable() };

    log::boot(&mut out, BOARD);
    if MS_PER_TICK != 1 {
        // Emulator builds only: the harness reads the time scale here.
        out.flash(crate::flash_str!("timescale "));
        out.u32(MS_PER_TICK as u32);
        out.flash(crate::flash_str!("\n"));
    }
    let site = match Site::new(SITE_LAT_DEG, SITE_LON_DEG) {
        Ok(site) => site,
        // The board's own constants: cannot happen. Nothing is driven
        // but the stow pose; the watchdog, no longer fed, resets the chip.
        Err(_) => halt(&mut out, "site refused"),
    };
    log::site(&mut out, SiteSource::Config, SITE_LAT_DEG, SITE_LON_DEG);
    out.flash(crate::flash_str!("config step_s="));
    out.u32(STEP_S);
    out.flash(crate::flash_str!(" tick_ms="));
    out.u32(TICK_MS as u32);
    out.flash(crate::flash_str!(" axis_step_deg="));
    out.fixed(AXIS_STEP_DEG, 3);
    out.flash(crate::flash_str!("\n"));
    let mut time = TimeKeeper::new(Ds3231::new(I2c::new(dp.TWI)), TimeConfig::default());
    let mut tracker = Tracker {
        mode: None,
        fault: None,
        time_logged: false,
        last_slot: None,
    };
    let mut next_tick_ms = 0u64;
    loop {
        let now_ms = millis();
        if now_ms >= next_tick_ms {
            tracker.tick(&mut out, &mut time, &mut servos, &site, now_ms);
            next_tick_ms = now_ms.saturating_add(TICK_MS);
        }
        watchdog.feed();
        sleep_until_interrupt(&dp.CPU);
    }
}

/// Says why and stops: the watchdog, no longer fed, resets the board.
fn halt(out: &mut Usart0, why: &str) -> ! {
    out.flash(crate::flash_str!("halt: "));
    out.text(why);
    out.flash(crate::flash_str!("\n"));
    out.flush_all();
    loop {
        avr_device::asm::sleep();
    }
}
