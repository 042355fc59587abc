//! The 8-bit AVR board layer over the `avr-device` 0.9 PAC: the ATmega2560
//! when the build sets `--cfg avr_atmega2560` (see `.ci/firmware_env.sh`),
//! else the ATmega328P. The two chips share the register names of every
//! peripheral used here; where they differ (the second USART, INT2..INT7,
//! ports A and E..L) the 2560-only parts are behind the same cfg.
//!
//! | part | type | traits |
//! |---|---|---|
//! | TWI at 100 kHz | [`I2c`], shared by several drivers through [`SharedI2c`] | `embedded_hal::i2c::I2c` |
//! | port bits | [`OutputPin`], [`InputPin`], [`OpenDrainPin`] | `OutputPin`, `StatefulOutputPin`, `InputPin` |
//! | busy wait | [`Delay`] | `embedded_hal::delay::DelayNs` |
//! | USART0 (+ USART1 on the 2560) | [`Usart0`], [`Usart1`] | `embedded_io::{Read, ReadReady, Write}`, [`suntracker::log::Sink`] |
//! | Timer0 | [`Millis`] | 1 kHz tick, [`millis`] |
//! | INTn | [`Anemometer`] | falling-edge pulse count |
//! | WDT | [`Watchdog`] | ~2 s, [`Watchdog::feed`] |
//! | Timer1, fast PWM mode 14, 50 Hz (Timer3 on the 2560 too) | [`Timer1Pwm`]: [`Oc1a`], [`Oc1b`]; `Timer3Pwm`: `Oc3a`, `Oc3c` | `embedded_hal::pwm::SetDutyCycle` (max duty 40,000 = one 0.5 µs count per duty step) |
//! | PCINT23:16 (PD4–PD7; PK4–PK7 on the 2560) | [`PinChangeEncoders`] | two `drivers::encoder::SharedEncoder`s (`suntracker::hw::EncoderCount`) |
//! | ADC, AVcc reference, 125 kHz | [`Adc`] | [`Adc::start`] / [`Adc::poll`], no waiting |
//! | USART2 with a driver enable on PH3, Timer5 (2560 only) | [`Rs485`] | [`suntracker::sunspec::ModbusLine`]: bytes with µs stamps in, a reply sent by interrupts |
//!
//! Interrupts: the layer defines no interrupt vector itself (an image that
//! does not use a part keeps its vector and its flash); an image binds the
//! vectors of the parts it uses with [`avr_board_interrupts!`](crate::avr_board_interrupts)
//! and then enables interrupts (`unsafe { avr_device::interrupt::enable() }`,
//! in the image, after every part is set up).
//!
//! `unsafe` in this module: only raw register writes (`W::bits`) to
//! registers whose every bit pattern is valid, the receive interrupts'
//! access to the data register of a USART that the interrupt's owner
//! configured, the RS-485 interrupts' access to USART2, Timer5's count and
//! the driver-enable bit and their read of the reply where the Modbus port
//! built it ([`Rs485`]), and the pin-change handler's read of the encoder port's
//! input register; each block carries a SAFETY comment.
//!
//! The encoder handler ([`on_encoder_pin_change`], vector PCINT2), counted
//! by hand from the disassembly of the ATmega328P self-test
//! (`avr-objdump -d`, `__vector_5` and `SharedEncoder::update`; cycles per
//! instruction from the AVR Instruction Set Manual): 203 cycles from its
//! first instruction to RETI for one encoder's edge (202–204 by direction;
//! 314–315 when both encoders changed, 345 at worst with two illegal
//! transitions, 92 for a change that went away), plus 7 to enter it (4 for
//! the interrupt response, 3 for the vector's JMP; 4 more out of sleep):
//! 210 cycles, 13.1 µs, per edge. simavr, stepping the handler one
//! instruction at a time, agrees: 203 and 314 (`emu/tests/uno_board_smoke.rs`).
//! The pins are read 44 cycles (2.75 µs) after the interrupt is taken. So:
//!
//! * throughput: 16 MHz / 210 = 76,000 edges/s over both encoders with the
//!   CPU doing nothing else (38,000 edges/s at half the CPU);
//! * spacing: two edges of one encoder must be further apart than the time
//!   to that read — 44 cycles plus the longest stretch with interrupts off
//!   elsewhere (the Timer0 tick's handler: 105 cycles; 150 in all, 9.4 µs),
//!   or the decoder sees both channels changed (an error, no count);
//! * Chowdhury et al.'s (2019) servo at 95 rpm (FS5106R at 6 V) with a
//!   300-line encoder (YMT22, up to 300 pulses per turn) on its shaft gives
//!   4 · 300 · 95 / 60 = 1,900 edges/s per axis: 3,800 edges/s, 5 % of the
//!   CPU, edges 526 µs apart. `emu/tests/uno_board_smoke.rs` drives both
//!   encoders at that rate and at ten times it (19,000 edges/s each) and
//!   every edge is counted.
//!
//! RAM: the layer's statics are 162 B (USART0 ring 133 B, plus 133 B for
//! USART1's when used; millis 8 B; anemometer 2 B; the two encoders 18 B
//! and their last pin levels 1 B, plus `drivers::encoder`'s 16-byte
//! transition table when they are used; `avr-nm -S`). avr-gcc keeps constant
//! data in RAM (`.data`), so a driver's tables cost RAM, not only flash:
//! `drivers::compass::wmm`'s WMM2025 coefficients in `f64` take 3 KB, and
//! `drivers::gps` through the `nmea` crate brings core's float-parsing
//! tables (12 KB) — more than the 2560's 8 KiB.
#![no_std]

mod adc;
mod anemometer;
mod delay;
pub mod eeprom;
mod gpio;
mod millis;
#[cfg(avr_atmega2560)]
mod motor_pwm;
mod pcint;
mod pwm;
#[cfg(avr_atmega2560)]
mod rs485;
mod serial;
mod twi;
mod watchdog;

#[cfg(avr_atmega2560)]
pub use avr_device::atmega2560 as chip;
#[cfg(not(avr_atmega2560))]
pub use avr_device::atmega328p as chip;

#[cfg(avr_atmega2560)]
pub use adc::SharedAdcChannel;
pub use adc::{Adc, AdcError, ADC_CHANNELS, ADC_MAX_CODE};
pub use anemometer::{on_anemometer_edge, Anemometer, ExtInt};
pub use delay::Delay;
pub use gpio::{InputPin, OpenDrainPin, OutputPin, Port, PortInputPin, PortOutputPin};
pub use millis::{millis, on_timer0_compare, sleep_until_interrupt, Millis, MS_PER_TICK};
#[cfg(avr_atmega2560)]
pub use motor_pwm::{
    MotorDutyOutOfRange, MotorPwm, Timer1MotorPwm, Timer4MotorPwm, MOTOR_MAX_DUTY, MOTOR_PWM_TOP,
};
pub use pcint::{on_encoder_pin_change, EncoderPort, PinChangeEncoders};
pub use pwm::{
    Oc1a, Oc1b, PulseWidth, PwmError, Timer1Channel, Timer1Pwm, COUNTS_PER_US, FRAME_TOP, FRAME_US,
    MAX_DUTY,
};
#[cfg(avr_atmega2560)]
pub use pwm::{Oc3a, Oc3c, Timer3Channel, Timer3Pwm};
#[cfg(avr_atmega2560)]
pub use rs485::{
    on_usart2_rx, on_usart2_tx, on_usart2_udre, Parity, Rs485, RX_ENTRIES, US_PER_COUNT,
};
pub use serial::{on_usart0_rx, SerialError, Usart0};
#[cfg(avr_atmega2560)]
pub use serial::{on_usart1_rx, Usart1};
pub use twi::{I2c, SharedI2c, TwiError};
pub use watchdog::Watchdog;

/// CPU clock of every supported board (Arduino Uno and Mega: 16 MHz crystal).
pub const CPU_HZ: u32 = 16_000_000;

/// Binds interrupt vectors to the board layer's handlers. Name the parts the
/// image uses, in any order:
///
/// * `timer0` — TIMER0_COMPA → [`Millis`] tick;
/// * `usart0` — USART0 RX complete (vector `USART_RX` on the 328P) → [`Usart0`];
/// * `usart1` — USART1 RX complete (2560 only) → [`Usart1`];
/// * `usart2` — USART2 RX complete, data register empty and TX complete
///   (2560 only) → [`Rs485`];
/// * `int0` … `int7` — the external interrupt the [`Anemometer`] listens on
///   (`int0`, `int1` on the 328P);
/// * `pcint2` — PCINT2 (pins PCINT23:16) → [`PinChangeEncoders`].
///
/// ```ignore
/// suntracker_avr::avr_board_interrupts!(timer0, usart0);
/// ```
///
/// Expands in the image's crate, which needs `avr-device` with its `rt`
/// feature (as every AVR image has) and, for the handlers' unstable
/// `avr-interrupt` ABI, `#![cfg_attr(target_arch = "avr", feature(abi_avr_interrupt))]`
/// at its root.
#[macro_export]
macro_rules! avr_board_interrupts {
    ($($part:ident),* $(,)?) => {
        $( $crate::__avr_board_isr!($part); )*
    };
}

/// One vector of [`avr_board_interrupts!`]; not for direct use.
#[doc(hidden)]
#[macro_export]
macro_rules! __avr_board_isr {
    (timer0) => {
        #[cfg_attr(avr_atmega2560, avr_device::interrupt(atmega2560))]
        #[cfg_attr(not(avr_atmega2560), avr_device::interrupt(atmega328p))]
        #[allow(non_snake_case)]
        fn TIMER0_COMPA() {
            $crate::on_timer0_compare();
        }
    };
    (usart0) => {
        #[cfg(avr_atmega2560)]
        #[avr_device::interrupt(atmega2560)]
        #[allow(non_snake_case)]
        fn USART0_RX() {
            $crate::on_usart0_rx();
        }
        #[cfg(not(avr_atmega2560))]
        #[avr_device::interrupt(atmega328p)]
        #[allow(non_snake_case)]
        fn USART_RX() {
            $crate::on_usart0_rx();
        }
    };
    (usart1) => {
        #[avr_device::interrupt(atmega2560)]
        #[allow(non_snake_case)]
        fn USART1_RX() {
            $crate::on_usart1_rx();
        }
    };
    (usart2) => {
        #[avr_device::interrupt(atmega2560)]
        #[allow(non_snake_case)]
        fn USART2_RX() {
            $crate::on_usart2_rx();
        }
        #[avr_device::interrupt(atmega2560)]
        #[allow(non_snake_case)]
        fn USART2_UDRE() {
            $crate::on_usart2_udre();
        }
        #[avr_device::interrupt(atmega2560)]
        #[allow(non_snake_case)]
        fn USART2_TX() {
            $crate::on_usart2_tx();
        }
    };
    (pcint2) => {
        #[cfg_attr(avr_atmega2560, avr_device::interrupt(atmega2560))]
        #[cfg_attr(not(avr_atmega2560), avr_device::interrupt(atmega328p))]
        #[allow(non_snake_case)]
        fn PCINT2() {
            $crate::on_encoder_pin_change();
        }
    };
    (int0) => { $crate::__avr_board_isr!(@ext INT0); };
    (int1) => { $crate::__avr_board_isr!(@ext INT1); };
    (int2) => { $crate::__avr_board_isr!(@ext2560 INT2); };
    (int3) => { $crate::__avr_board_isr!(@ext2560 INT3); };
    (int4) => { $crate::__avr_board_isr!(@ext2560 INT4); };
    (int5) => { $crate::__avr_board_isr!(@ext2560 INT5); };
    (int6) => { $crate::__avr_board_isr!(@ext2560 INT6); };
    (int7) => { $crate::__avr_board_isr!(@ext2560 INT7); };
    (@ext $vector:ident) => {
        #[cfg_attr(avr_atmega2560, avr_device::interrupt(atmega2560))]
        #[cfg_attr(not(avr_atmega2560), avr_device::interrupt(atmega328p))]
        #[allow(non_snake_case)]
        fn $vector() {
            $crate::on_anemometer_edge();
        }
    };
    (@ext2560 $vector:ident) => {
        #[avr_device::interrupt(atmega2560)]
        #[allow(non_snake_case)]
        fn $vector() {
            $crate::on_anemometer_edge();
        }
    };
}
