//! The tracker image for QEMU's `mps2-an386` (Cortex-M4F): the
//! board-independent firmware loop (`suntracker::firmware`) on the board module
//! `suntracker_mps2_an386` (GPS on UART0, log over semihosting,
//! simulated axes). Built only for `thumbv7em-none-eabihf`; `cargo run
//! --release` in boards/mps2_an386 runs it under `.ci/qemu_gps.py` (the
//! book's emulators chapter, docs/src/emulators.md).
#![no_std]
#![no_main]

use cortex_m_rt::{entry, exception, ExceptionFrame};
use suntracker_mps2_an386 as board;

#[entry]
fn main() -> ! {
    board::run()
}

#[exception]
fn SysTick() {
    board::on_systick();
}

#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    board::on_interrupt(irqn);
}

#[exception]
unsafe fn HardFault(_frame: &ExceptionFrame) -> ! {
    board::on_panic()
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    board::on_panic()
}
