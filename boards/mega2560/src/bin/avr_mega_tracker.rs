//! The Arduino Mega 2560 tracker image (Li et al.'s (2022) build). Everything
//! about the board — pins, devices, configuration — is in
//! `suntracker_mega2560`; this file binds its interrupt vectors and
//! starts it. Build, flash and emulate: see the book's firmware chapter (docs/src/firmware.md).
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use suntracker_avr::chip;

// Timer0 millisecond clock, log and console USART0, GPS USART1, the
// RS-485 port's USART2, anemometer on INT4, the DC axes' Hall encoders on
// PCINT2 (enabled in every image: an axis is DC by its configuration; an
// unbound vector would reset the chip at the first Hall edge).
suntracker_avr::avr_board_interrupts!(timer0, usart0, usart1, usart2, int4, pcint2);

#[avr_device::entry]
fn main() -> ! {
    match chip::Peripherals::take() {
        Some(dp) => suntracker_mega2560::run(dp),
        // Taken twice: cannot happen at reset; sleep until the watchdog.
        None => loop {
            avr_device::asm::sleep();
        },
    }
}

/// No panic path is expected in this image (`.ci/panic_check.sh`); should
/// one be reached, the board stops driving and sleeps until the watchdog
/// resets it.
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    avr_device::interrupt::disable();
    loop {
        avr_device::asm::sleep();
    }
}
