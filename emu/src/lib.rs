//! Emulator harness for the suntracker AVR images: simavr (the build that
//! the `avr-tester` crate runs on, through `simavr-ffi`) with models of the
//! board's peripherals — DS3231 RTC, QMC5883L compass and ADXL345
//! accelerometer on the TWI, two H-bridge steppers on PORTA with their home
//! and max-end switches on PORTC, a GPS on USART1, a cup anemometer on
//! INT4 — and a reader of the log on USART0; and the ATmega328P (Uno)
//! image with a DS3231 (or, for its `ds1302` build, a DS1302 on three port
//! C pins), two FS5106R servos turning YMT22 encoders on its pins, home
//! switches and the panel voltage on ADC0 ([`uno`]). On both,
//! lines typed on the console (USART0) and power cuts at given emulated
//! minutes ([`script`]). See `emu/README.md`.

pub mod ihex;
pub mod log;
pub mod mega;
pub mod models;
pub mod pty;
pub mod script;
pub mod sim;
pub mod twi;
pub mod uno;

pub use mega::{Contact, LogLine, MegaBench, Rtc, Run};
pub use models::mount::{Field, Mount};
pub use models::nmea::{GpsFeed, GpsSite};
pub use models::wind::WindProfile;
