//! The Arduino Uno tracker (ATmega328P; Chowdhury et al.'s (2019) build):
//! everything about this board in one place — pins, devices, the loop —
//! over the AVR board layer ([`suntracker_avr`]). The loop is
//! [`suntracker::servo_tracker::ServoTracker`]; an image binds the vectors
//! (`avr_board_interrupts!(timer0, pcint2)`) and calls [`run`], as
//! `avr_tracker` does.
//!
//! | function | pin | Uno header |
//! |---|---|---|
//! | log, 115200 8N1 (the settings image: its console) | USART0 TXD/RXD (PD1/PD0) | D1/D0 (USB) |
//! | I²C 100 kHz: DS3231 0x68 | SDA/SCL (PC4/PC5) | A4/A5 |
//! | servo A (tilt) FS5106R, 50 Hz PWM | OC1A (PB1) | D9 |
//! | servo C (azimuth) FS5106R, 50 Hz PWM | OC1B (PB2) | D10 |
//! | encoder C (YMT22) A/B, pin-change interrupt | PD4/PD5 | D4/D5 |
//! | encoder A (YMT22) A/B, pin-change interrupt | PD6/PD7 | D6/D7 |
//! | C home switch (closed at −180°, to GND, pull-up) | PB0 | D8 |
//! | A home switch (closed at −90°, to GND, pull-up) | PB4 | D12 |
//! | panel voltage through a 10 kΩ/10 kΩ divider | ADC0 (PC0) | A0 |
//! | feature `ds1302`: DS1302 CE / I/O (10 kΩ pull-up) / SCLK, instead of the DS3231 | PC1 / PC2 / PC3 | A1 / A2 / A3 |
//!
//! Wiring sketch:
//!
//! ```text
//!  Uno D9  ─ signal ┐ FS5106R tilt servo    (+6 V from its own supply, common GND)
//!  Uno D10 ─ signal ┘ FS5106R azimuth servo
//!  Uno D4/D5 ─ A/B ─ YMT22 on the azimuth shaft (+5 V)
//!  Uno D6/D7 ─ A/B ─ YMT22 on the tilt shaft (+5 V)
//!  Uno D8  ─ azimuth home switch ─ GND      Uno D12 ─ tilt home switch ─ GND
//!  Uno A0 ─┬─ 10 kΩ ─ panel +               Uno A4/A5 ─ SDA/SCL ─ DS3231 (CR2032)
//!          └─ 10 kΩ ─ GND                   Uno D0/D1 ─ USB serial: the log
//! ```
//!
//! Each pass of the loop (every Timer0 millisecond) closes both servo loops on
//! their encoder counts; once a second a tick reads the DS3231, runs Chowdhury
//! et al.'s way of tracking (a sun position at each 4-minute slot, no day
//! table: the part has 2 KB of RAM), commands the axes, takes the ADC
//! conversion started at the previous tick and starts the next; then the
//! watchdog is fed and the CPU sleeps until the next interrupt. There is no
//! simulated clock: an RTC that lost power or does not answer leaves the panel
//! flat, `mode wait_for_time`.
//!
//! The site and the gears come from the EEPROM at power-on
//! ([`suntracker::servo_tracker::settings`]), where the settings image
//! ([`run_settings`], bin `avr_settings`) saved them from its console:
//! there is no room for a console beside the tracker.
#![no_std]

use drivers::encoder::SharedEncoder;
use drivers::servo::ContinuousServo;
use suntracker::config::AxisConfig;
use suntracker::console;
use suntracker::hw::ServoAxis;
use suntracker::log::{self, Sink, SiteSource};
use suntracker::panel::{Divider, PanelAdc};
use suntracker::servo_tracker::settings::{self as settings, SettingsConsole};
use suntracker::servo_tracker::{self, ServoTracker, POSITION_LOOP, SERVO};
use suntracker::text::FlashStr;
use suntracker::time::monotonic;
use suntracker_avr::eeprom::Eeprom;
use suntracker_avr::{
    chip, millis, sleep_until_interrupt, Adc, InputPin, Millis, PinChangeEncoders, PortInputPin,
    PulseWidth, Timer1Channel, Timer1Pwm, Usart0, Watchdog, MS_PER_TICK,
};

/// Board name in the boot line.
pub const BOARD: &str = "uno";
/// Board name in the settings image's boot line.
pub const SETTINGS_BOARD: &str = "uno-settings";
/// Log serial.
pub const LOG_BAUD_HZ: u32 = 115_200;
/// The panel's ADC input: AVcc (5 V) reference, 10 bits, a 10 kΩ/10 kΩ
/// divider (the paper's 6 V panel, open circuit up to about 7.5 V, stays
/// under the 5 V reference at the pin).
pub const PANEL: PanelAdc = PanelAdc {
    vref_mv: 5_000,
    bits: 10,
    divider: Divider {
        r_top_ohm: 10_000,
        r_bottom_ohm: 10_000,
    },
};
/// ADC channel of the panel voltage (A0).
const PANEL_CHANNEL: u8 = 0;

/// The clock chip: the DS3231 on the I²C bus, or with the `ds1302` feature
/// the DS1302 the paper also names, on three port C pins (its I/O
/// line open-drain with an external 10 kΩ pull-up: see
/// `drivers::rtc::ds1302`).
#[cfg(not(feature = "ds1302"))]
fn rtc(portc: &chip::PORTC, twi: chip::TWI) -> drivers::rtc::Ds3231<suntracker_avr::I2c> {
    let _ = portc;
    drivers::rtc::Ds3231::new(suntracker_avr::I2c::new(twi))
}

/// The DS1302 variant of [`rtc`].
#[cfg(feature = "ds1302")]
fn rtc(
    portc: &chip::PORTC,
    twi: chip::TWI,
) -> drivers::rtc::Ds1302<
    suntracker_avr::OutputPin<'_, chip::PORTC, 1>,
    suntracker_avr::OutputPin<'_, chip::PORTC, 3>,
    suntracker_avr::OpenDrainPin<'_, chip::PORTC, 2>,
    suntracker_avr::Delay,
> {
    let _ = twi;
    drivers::rtc::Ds1302::new(
        suntracker_avr::OutputPin::new(portc, false),
        suntracker_avr::OutputPin::new(portc, false),
        suntracker_avr::OpenDrainPin::new(portc, false),
        suntracker_avr::Delay::new(),
    )
}

/// Starts the tracker on the board's peripherals; never returns.
pub fn run(dp: chip::Peripherals) -> ! {
    let chip::Peripherals {
        USART0,
        TC0,
        TC1,
        WDT,
        CPU,
        PORTB,
        PORTC,
        PORTD,
        EXINT,
        ADC,
        TWI,
        EEPROM,
        ..
    } = dp;
    let mut out = Usart0::new_tx_only(USART0, LOG_BAUD_HZ);
    let _millis = Millis::start(TC0);
    let mut watchdog = Watchdog::enable(WDT, &CPU);
    let neutral = PulseWidth::NEUTRAL_1500_US;
    let pwm = Timer1Pwm::start(TC1, &PORTB, neutral, neutral);
    let encoders = PinChangeEncoders::start(&EXINT, &PORTD, true);
    let home_c = InputPin::<_, 0>::new(&PORTB, true).erase();
    let home_a = InputPin::<_, 4>::new(&PORTB, true).erase();
    let mut adc = Adc::new(ADC);
    // SAFETY: the Timer0 tick and the encoders' pin-change vector, the
    // only two, are set up above.
    unsafe { avr_device::interrupt::enable() };

    log::boot(&mut out, BOARD);
    if MS_PER_TICK != 1 {
        // Emulator builds only: the harness reads the time scale here.
        out.flash(suntracker::flash_str!("timescale "));
        out.u32(MS_PER_TICK as u32);
        out.flash(suntracker::flash_str!("\n"));
    }
    let settings = settings::load(Eeprom::storage(EEPROM), &mut out);
    let Ok(site) = settings.site() else {
        // Loaded settings are validated: cannot happen. The watchdog, no
        // longer fed, resets the chip.
        halt(&mut out, suntracker::flash_str!("site refused"))
    };
    log::site(
        &mut out,
        SiteSource::Config,
        settings.lat_deg,
        settings.lon_deg,
    );
    let configs = settings.axis_configs();
    let [config_c, config_a] = &configs;
    out.flash(suntracker::flash_str!("config step_s="));
    out.u32(servo_tracker::STEP_S);
    out.flash(suntracker::flash_str!(" tick_ms="));
    out.u32(servo_tracker::TICK_MS);
    // One encoder count of axis, the pose's resolution: the coarser axis's
    // (0.3° through a direct drive).
    let (c, a) = (config_c.counts_per_deg(), config_a.counts_per_deg());
    let counts_per_deg = if c < a { c } else { a };
    out.flash(suntracker::flash_str!(" axis_step_deg="));
    out.fixed(1.0 / counts_per_deg, 3);
    out.flash(suntracker::flash_str!(" algorithm="));
    out.flash(servo_tracker::ALGORITHM_NAME);
    out.flash(suntracker::flash_str!("\n"));

    let Some(axes) = servo_axes(&pwm, &encoders, [home_c, home_a], &configs) else {
        halt(
            &mut out,
            suntracker::flash_str!("servo configuration refused"),
        )
    };
    let rtc = rtc(&PORTC, TWI);
    let mut tracker = ServoTracker::new(rtc, site, axes, &configs);
    let tick_ms = u64::from(servo_tracker::TICK_MS);
    let mut next_tick_ms = 0u64;
    loop {
        let now_ms = millis();
        tracker.service(now_ms);
        if now_ms >= next_tick_ms {
            // The conversion started at the previous tick (104 µs) is done.
            let panel_mv = adc.poll().and_then(|code| PANEL.panel_mv(code).ok());
            tracker.tick(&mut out, monotonic::from_board_ms(now_ms), panel_mv);
            let _ = adc.start(PANEL_CHANNEL);
            next_tick_ms = now_ms.saturating_add(tick_ms);
        }
        watchdog.feed();
        sleep_until_interrupt(&CPU);
    }
}

/// A servo axis of this board: its signal on a Timer1 output, its encoder
/// counted by the pin-change interrupt, its home switch on port B.
pub type UnoServoAxis<'p> =
    ServoAxis<'static, Timer1Channel<'p>, SharedEncoder, PortInputPin<'p, chip::PORTB>>;

/// Both servo axes, C then A (C on OC1B (D10), its encoder on D4/D5; A on
/// OC1A (D9), D6/D7), with their home switches `homes` (closed low) and
/// the FS5106R's pulses and the encoder's position loop; `None` when a
/// servo refuses its settings (it takes these).
pub fn servo_axes<'p>(
    pwm: &'p Timer1Pwm,
    encoders: &PinChangeEncoders,
    homes: [PortInputPin<'p, chip::PORTB>; 2],
    configs: &[AxisConfig; 2],
) -> Option<[UnoServoAxis<'p>; 2]> {
    let (oc1a, oc1b) = pwm.channels();
    let (Ok(servo_c), Ok(servo_a)) = (
        ContinuousServo::new(Timer1Channel::Oc1b(oc1b), SERVO),
        ContinuousServo::new(Timer1Channel::Oc1a(oc1a), SERVO),
    ) else {
        return None;
    };
    let [home_c, home_a] = homes;
    let [config_c, config_a] = configs;
    Some([
        ServoAxis::new(
            servo_c,
            encoders.encoder_c(),
            home_c,
            true,
            POSITION_LOOP,
            config_c,
        ),
        ServoAxis::new(
            servo_a,
            encoders.encoder_a(),
            home_a,
            true,
            POSITION_LOOP,
            config_a,
        ),
    ])
}

/// Console bytes taken from the receive ring per pass of the settings
/// image's loop (115200 baud brings 11.5 bytes a millisecond; a pass ends
/// at each Timer0 millisecond or byte received).
const CONSOLE_BURST: usize = 16;

/// The settings image: the console of
/// [`suntracker::servo_tracker::settings`] on the log port (115200 8N1), the
/// EEPROM and the RTC (for `time set`); nothing else is driven (the servo
/// pins stay inputs, so the servos get no pulse and stay still). Flash it,
/// type the settings, `save`, then flash the tracker image back: the
/// bootloader leaves the EEPROM as it is. Never returns.
pub fn run_settings(dp: chip::Peripherals) -> ! {
    let chip::Peripherals {
        USART0,
        TC0,
        WDT,
        CPU,
        PORTC,
        TWI,
        EEPROM,
        ..
    } = dp;
    let mut out = Usart0::new(USART0, LOG_BAUD_HZ);
    let _millis = Millis::start(TC0);
    let mut watchdog = Watchdog::enable(WDT, &CPU);
    // SAFETY: the Timer0 tick and the USART0 receiver, the only two, are
    // set up above.
    unsafe { avr_device::interrupt::enable() };
    log::boot(&mut out, SETTINGS_BOARD);
    let mut console = SettingsConsole::boot(Eeprom::storage(EEPROM), &mut out);
    let mut rtc = rtc(&PORTC, TWI);
    loop {
        let mut rx = [0u8; CONSOLE_BURST];
        let n = Usart0::take_received(&mut rx);
        console.input(rx.get(..n).unwrap_or_default(), &mut rtc, &mut out);
        // Lines the receive ring lost whole: answered too.
        for _ in 0..Usart0::take_lost_lines() {
            console::write_line_error(&mut out, console::LineError::Lost);
        }
        console.poll(&mut out);
        watchdog.feed();
        sleep_until_interrupt(&CPU);
    }
}

/// Says why and stops: the watchdog, no longer fed, resets the board.
fn halt(out: &mut Usart0, why: FlashStr) -> ! {
    out.flash(suntracker::flash_str!("halt: "));
    out.flash(why);
    out.flash(suntracker::flash_str!("\n"));
    out.flush_all();
    loop {
        avr_device::asm::sleep();
    }
}
