//! USART0 of the ATmega328P and the ATmega2560 (the same registers on both
//! chips: datasheet "USART0" register description), 8N1 at 115200 baud.
//!
//! The image's crate root names its chip as `chip`
//! (`use avr_device::atmega328p as chip;`).

use crate::chip;
use crate::fmt::Sink;

/// 115200 baud at 16 MHz in double-speed mode (U2X0 = 1):
/// UBRR = 16e6 / (8 · 115200) − 1 = 16.4 → 16, a 2.1 % rate error that every
/// Arduino bootloader also uses (datasheet table "UBRR settings").
const UBRR_115200_U2X: u16 = 16;

/// USART0, transmitter and receiver on.
pub struct Uart0 {
    usart: chip::USART0,
}

impl Uart0 {
    /// Configures USART0: 8 data bits, no parity, 1 stop bit, 115200 baud.
    pub fn new(usart: chip::USART0) -> Self {
        usart.ubrr0().write(|w| w.set(UBRR_115200_U2X));
        usart.ucsr0a().write(|w| w.u2x0().set_bit());
        usart.ucsr0c().write(|w| w.ucsz0().chr8());
        usart
            .ucsr0b()
            .write(|w| w.txen0().set_bit().rxen0().set_bit());
        Uart0 { usart }
    }

    /// A received byte, if one is waiting.
    #[allow(dead_code)]
    pub fn try_read(&mut self) -> Option<u8> {
        if self.usart.ucsr0a().read().rxc0().bit_is_set() {
            Some(self.usart.udr0().read().bits())
        } else {
            None
        }
    }
}

impl Sink for Uart0 {
    fn put(&mut self, bytes: &[u8]) {
        for &b in bytes {
            while self.usart.ucsr0a().read().udre0().bit_is_clear() {}
            self.usart.udr0().write(|w| w.set(b));
        }
    }
}

/// Waits until the last byte has left the shift register, then stops the
/// CPU (interrupts off, sleep): simavr ends the simulation there.
pub fn halt(uart: &mut Uart0) -> ! {
    while uart.usart.ucsr0a().read().udre0().bit_is_clear() {}
    loop {
        avr_device::interrupt::disable();
        avr_device::asm::sleep();
    }
}
