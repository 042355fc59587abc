//! Busy-wait delays at 16 MHz as `embedded_hal::delay::DelayNs`.
//!
//! Accuracy: a delay is never shorter than asked (it is rounded up to whole
//! CPU cycles of 62.5 ns, and `avr_device::asm::delay_cycles` loops in
//! 6-cycle steps). It is longer by the call overhead (a few cycles, plus
//! under 1 µs of loop per millisecond of `delay_ms`) and by every interrupt
//! taken meanwhile: with the [`Millis`](super::Millis) tick on, its handler
//! (about 70 cycles, ~4.4 µs) runs once per millisecond, so a long delay is
//! about 0.5 % long (the selftest's 100 ms measure 100 ms of Timer0 time).
//! Use [`millis`](super::millis) to measure real time.

use embedded_hal::delay::DelayNs;

/// Cycles per microsecond at [`CPU_HZ`](super::CPU_HZ).
const CYCLES_PER_US: u32 = super::CPU_HZ / 1_000_000;

/// The busy-wait delay (no peripheral).
#[derive(Debug, Clone, Copy, Default)]
pub struct Delay;

impl Delay {
    /// A delay.
    pub const fn new() -> Self {
        Delay
    }
}

impl DelayNs for Delay {
    fn delay_ns(&mut self, ns: u32) {
        // ceil(ns · 16 / 1000) without overflow: whole µs, then the rest.
        let cycles = (ns / 1_000) * CYCLES_PER_US + ((ns % 1_000) * CYCLES_PER_US).div_ceil(1_000);
        avr_device::asm::delay_cycles(cycles);
    }

    fn delay_us(&mut self, us: u32) {
        // In chunks of 1 s so that cycles never overflow a u32.
        const CHUNK_US: u32 = 1_000_000;
        let mut left_us = us;
        while left_us > CHUNK_US {
            avr_device::asm::delay_cycles(CHUNK_US * CYCLES_PER_US);
            left_us -= CHUNK_US;
        }
        avr_device::asm::delay_cycles(left_us * CYCLES_PER_US);
    }

    fn delay_ms(&mut self, ms: u32) {
        for _ in 0..ms {
            avr_device::asm::delay_cycles(1_000 * CYCLES_PER_US);
        }
    }
}
