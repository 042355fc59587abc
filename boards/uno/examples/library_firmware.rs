//! The library's firmware loop ([`suntracker::firmware::Firmware`]) on the
//! Uno's parts: both FS5106R servo axes closed on their YMT22 encoders,
//! the home switches, the DS3231, the configuration console on USART0 and
//! the configuration stored in the EEPROM; no GPS receiver (`NoGps`), no
//! attitude sensors (`Infallible`), no weather inputs (`NoWeather`: the
//! anemometer's wind stow stays), no postal-code table (the site is typed
//! as `site.lat_deg` and `site.lon_deg`), the real-time scheduler (no day
//! table: the part has 2 KB of RAM).
//!
//! This is the single image the Uno is to run in place of `avr_tracker`
//! and `avr_settings`. It does not fit the ATmega328P's 32 KB yet: it is
//! built to measure how far it is (`.ci/budgets.sh` holds it to a budget
//! so that the distance only shrinks; the book's size chapter tracks it).
//! The linker's avr5 script allows 128 KB of program memory, so it links;
//! do not flash it.
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use core::convert::Infallible;

use drivers::rtc::Ds3231;
use suntracker::config::{Config, DriveKind, DriveSet};
use suntracker::firmware::{AppConfig, ConfigPersist, Firmware, Platform, StartError};
use suntracker::hw::NoGps;
use suntracker::mechanics;
use suntracker::persist::{ConfigStore, EepromStorage};
use suntracker::safety::NoWeather;
use suntracker::servo_tracker::axis_configs;
use suntracker_avr::eeprom::Eeprom;
use suntracker_avr::{
    chip, millis, sleep_until_interrupt, I2c, InputPin, Millis, PinChangeEncoders, PortInputPin,
    PulseWidth, Timer1Pwm, Usart0, Watchdog,
};
use suntracker_uno::UnoServoAxis;

suntracker_avr::avr_board_interrupts!(timer0, pcint2, usart0);

/// The real-time scheduler: a sun position at each slot, no day table.
const TABLE_LEN: usize = 0;

/// What the loop needs of the board besides its devices.
struct UnoPlatform<'c> {
    cpu: &'c chip::CPU,
    watchdog: Watchdog,
    store: ConfigStore<EepromStorage<Eeprom>>,
}

impl Platform for UnoPlatform<'_> {
    // Latitude and longitude are typed as keys: the table and its search
    // took 2,332 B of this image.
    const POSTAL_CODES: bool = false;
    fn now_ms(&mut self) -> u64 {
        millis()
    }
    fn take_wind_pulses(&mut self) -> u32 {
        0
    }
    fn feed_watchdog(&mut self) {
        self.watchdog.feed();
    }
    fn wait_for_interrupt(&mut self) {
        sleep_until_interrupt(self.cpu);
    }
    fn console_read(&mut self, buf: &mut [u8]) -> usize {
        Usart0::take_received(buf)
    }
    fn console_lost_lines(&mut self) -> u8 {
        Usart0::take_lost_lines()
    }
    fn config_store(&mut self) -> Option<&mut dyn ConfigPersist> {
        Some(&mut self.store)
    }
}

/// The Uno's configuration: its servo axes, the rest the library's
/// defaults (written in place, not by the struct update syntax clippy
/// suggests, which built the defaults aside and copied them).
#[allow(clippy::field_reassign_with_default)]
fn uno_config() -> Config {
    let mut config = Config::default();
    config.axes = axis_configs();
    config
}

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = chip::Peripherals::take() else {
        // Taken twice: cannot happen at reset; sleep until the watchdog.
        loop {
            avr_device::asm::sleep();
        }
    };
    let chip::Peripherals {
        USART0,
        TC0,
        TC1,
        WDT,
        CPU,
        PORTB,
        PORTD,
        EXINT,
        TWI,
        EEPROM,
        ..
    } = dp;
    let log = Usart0::new(USART0, suntracker_uno::LOG_BAUD_HZ);
    let _millis = Millis::start(TC0);
    let watchdog = Watchdog::enable(WDT, &CPU);
    let neutral = PulseWidth::NEUTRAL_1500_US;
    let pwm = Timer1Pwm::start(TC1, &PORTB, neutral, neutral);
    let encoders = PinChangeEncoders::start(&EXINT, &PORTD, true);
    let home_c = InputPin::<_, 0>::new(&PORTB, true).erase();
    let home_a = InputPin::<_, 4>::new(&PORTB, true).erase();
    // SAFETY: the Timer0 tick, the encoders' pin-change vector and the
    // USART0 receiver, the only three, are set up above.
    unsafe { avr_device::interrupt::enable() };

    let mut platform = UnoPlatform {
        cpu: &CPU,
        watchdog,
        store: ConfigStore::new(Eeprom::storage(EEPROM)),
    };
    let homes = [home_c, home_a];
    let mut firmware = build_firmware(&pwm, &encoders, homes, &mut platform.store, TWI, log);
    // Run it where it is, inside the result: moving it out would copy its
    // 1,832 B on the stack.
    match &mut firmware {
        Ok(fw) => fw.run(&mut platform),
        Err(_) => halt(),
    }
}

/// The loop on the Uno's parts.
type UnoFirmware<'p> =
    Firmware<f32, Ds3231<I2c>, NoGps, UnoServoAxis<'p>, Infallible, Usart0, TABLE_LEN, NoWeather>;

/// The firmware on the Uno's axes and devices, with the stored
/// configuration (the board's own when none is good); halts when the
/// axes refuse it. Not inlined: the configuration and the axes it is built
/// from are on the stack only while it runs, not under the loop's passes.
#[inline(never)]
fn build_firmware<'p>(
    pwm: &'p Timer1Pwm,
    encoders: &PinChangeEncoders,
    homes: [PortInputPin<'p, chip::PORTB>; 2],
    store: &mut ConfigStore<EepromStorage<Eeprom>>,
    twi: chip::TWI,
    log: Usart0,
) -> Result<UnoFirmware<'p>, StartError> {
    let mut config = uno_config();
    if store.load_into(&mut config).defaults {
        config = uno_config();
    }
    let Some(axes) = suntracker_uno::servo_axes(pwm, encoders, homes, &config.axes) else {
        halt()
    };
    let app = AppConfig {
        defaults: uno_config,
        drives: DriveSet::NONE.with(DriveKind::ServoEncoder),
        wmm_declination: false,
        ..AppConfig::new(suntracker_uno::BOARD)
    };
    let options = mechanics::options_for_drives(mechanics::controller_options(), &config.axes);
    let rtc = Ds3231::new(I2c::new(twi));
    Firmware::new(app, config, options, rtc, NoGps, axes, None, log)
}

/// Stops: the watchdog, no longer fed, resets the board.
fn halt() -> ! {
    loop {
        avr_device::asm::sleep();
    }
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    avr_device::interrupt::disable();
    loop {
        avr_device::asm::sleep();
    }
}
