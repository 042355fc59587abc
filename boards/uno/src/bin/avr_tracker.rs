//! The Arduino Uno tracker image (ATmega328P, Chowdhury et al.'s (2019) build).
//! Everything about the board — pins, devices, the loop — is in
//! `suntracker_uno`; this file binds its interrupt vector and
//! starts it. Build, flash and emulate: see the book's firmware chapter (docs/src/firmware.md).
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use suntracker_avr::chip;

// The Timer0 millisecond clock and the encoders' pin changes; the log
// USART0 only sends.
suntracker_avr::avr_board_interrupts!(timer0, pcint2);

#[avr_device::entry]
fn main() -> ! {
    match chip::Peripherals::take() {
        Some(dp) => suntracker_uno::run(dp),
        // Taken twice: cannot happen at reset; sleep until the watchdog.
        None => loop {
            avr_device::asm::sleep();
        },
    }
}

/// No panic path is expected in this image (`.ci/panic_check.sh`); should
/// one be reached, the board stops and sleeps until the watchdog resets it.
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    avr_device::interrupt::disable();
    loop {
        avr_device::asm::sleep();
    }
}
