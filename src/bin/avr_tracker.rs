//! ATmega328P firmware (Arduino Uno class) that prints over USART0.
//!
//! Runs under simavr at 16 MHz: `cargo +nightly avr-run`. The C runtime of
//! avr-libc (linked by avr-gcc) sets up the stack and calls `main`.
#![cfg_attr(target_os = "none", no_std, no_main)]
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]

#[cfg(target_arch = "avr")]
mod firmware {
    use core::ptr::{read_volatile, write_volatile};

    // USART0 registers of the ATmega328P (datasheet, register summary).
    const UCSR0A: *mut u8 = 0xC0 as *mut u8;
    const UCSR0B: *mut u8 = 0xC1 as *mut u8;
    const UCSR0C: *mut u8 = 0xC2 as *mut u8;
    const UBRR0L: *mut u8 = 0xC4 as *mut u8;
    const UBRR0H: *mut u8 = 0xC5 as *mut u8;
    const UDR0: *mut u8 = 0xC6 as *mut u8;
    const UDRE0: u8 = 1 << 5;
    const TXEN0: u8 = 1 << 3;
    const UCSZ_8BIT: u8 = 0b11 << 1;
    /// 115200 baud at 16 MHz with U2X0 = 0: UBRR = 16e6 / (16 * 115200) - 1 ≈ 8.
    const UBRR_115200: u8 = 8;

    fn uart_init() {
        // SAFETY: fixed, documented I/O register addresses of the ATmega328P;
        // nothing else touches USART0.
        unsafe {
            write_volatile(UBRR0H, 0);
            write_volatile(UBRR0L, UBRR_115200);
            write_volatile(UCSR0C, UCSZ_8BIT);
            write_volatile(UCSR0B, TXEN0);
        }
    }

    fn uart_write(bytes: &[u8]) {
        for &b in bytes {
            // SAFETY: as in `uart_init`.
            unsafe {
                while read_volatile(UCSR0A) & UDRE0 == 0 {}
                write_volatile(UDR0, b);
            }
        }
    }

    /// Stops the CPU: interrupts off, then sleep. simavr ends the run there.
    fn halt() -> ! {
        loop {
            // SAFETY: `cli; sleep` only stops the core.
            unsafe { core::arch::asm!("cli", "sleep") };
        }
    }

    #[no_mangle]
    pub extern "C" fn main() -> ! {
        uart_init();
        uart_write(suntracker::BANNER.as_bytes());
        uart_write(b" on atmega328p: boot ok\n");
        halt()
    }

    #[panic_handler]
    fn panic(_info: &core::panic::PanicInfo) -> ! {
        uart_write(b"panic\n");
        halt()
    }
}

#[cfg(not(target_os = "none"))]
fn main() {
    println!("{} on host: boot ok", suntracker::BANNER);
}
