//! The Arduino Uno's settings image (ATmega328P): the configuration console
//! whose settings the tracker image (`avr_tracker`) reads from the EEPROM.
//! Everything about the board is in `suntracker_uno`
//! (`run_settings`); this file binds its interrupt vectors and starts it.
//! Use: see the book's firmware chapter (docs/src/firmware.md).
#![no_std]
#![no_main]
#![feature(abi_avr_interrupt)]

use suntracker_avr::chip;

// The Timer0 millisecond clock (the loop's wake-up) and the console's
// USART0 receiver.
suntracker_avr::avr_board_interrupts!(timer0, usart0);

#[avr_device::entry]
fn main() -> ! {
    match chip::Peripherals::take() {
        Some(dp) => suntracker_uno::run_settings(dp),
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
