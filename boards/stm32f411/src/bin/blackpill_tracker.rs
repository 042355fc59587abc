//! STM32F411CEU6 "Black Pill" tracker image: the board module
//! (`suntracker_stm32f411`: pins, wiring, clocks, devices) on the
//! board-independent firmware loop. Build and flash: the book's firmware chapter (docs/src/firmware.md).
//! With the feature `defmt` the log goes out over RTT (defmt-rtt) and a
//! panic's message too (panic-probe), for `probe-rs run` to print.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
#[cfg(feature = "defmt")]
use defmt_rtt as _;
#[cfg(feature = "defmt")]
use panic_probe as _;
use stm32f4xx_hal::pac;

#[entry]
fn main() -> ! {
    match (pac::Peripherals::take(), cortex_m::Peripherals::take()) {
        (Some(dp), Some(cp)) => suntracker_stm32f411::run(dp, cp),
        // Taken once at reset: never reached.
        _ => loop {
            cortex_m::asm::wfi();
        },
    }
}

/// A panic stops here; the independent watchdog, no longer fed, resets the
/// board. (With `defmt`, panic-probe's handler says why over RTT and stops
/// the core for the probe: a debugger halts the watchdog with it.)
#[cfg(not(feature = "defmt"))]
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    loop {
        cortex_m::asm::wfi();
    }
}
