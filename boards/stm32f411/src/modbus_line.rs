//! The RS-485 port of the Modbus RTU server (the `modbus` feature): USART2
//! (A2 TX to the transceiver's DI, A3 RX from its RO) with the driver enable
//! on A1 (DE and /RE tied), and TIM5 free-running at 1 MHz as the line's µs
//! clock (RM0383 §19 "Universal synchronous asynchronous receiver
//! transmitter (USART)": §19.3.2 "Transmitter" (TXE, TC), §19.3.3
//! "Receiver" (RXNE, ORE, NF, FE), §19.3.7 "Parity control"; §13
//! "General-purpose timers (TIM2 to TIM5)", TIM5's 32-bit counter).
//!
//! **Half duplex, nothing waits** ([`suntracker_modbus::HalfDuplexLine`],
//! tested there against a model of this USART's data and shift
//! registers). While receiving, the USART2 interrupt queues each byte with
//! TIM5's count at that moment (a ring of [`RX_RING_LEN`]); the Modbus port
//! takes them each pass and frames them by the silences between them. A
//! reply is copied into the line's own buffer, the driver enable raised,
//! and the bytes moved to the transmitter by the transmit-register-empty
//! interrupt, without a gap between them whatever the main loop does (a
//! 255-byte reply is 133 ms at 19,200 baud: sent by the loop it would hold
//! up ticks); the transmission-complete interrupt, once the last stop bit
//! has left, releases the driver enable. Until then [`ModbusLine::busy`]
//! holds the port. What the receiver gets while sending is dropped.
//!
//! **Frame format** from the configuration: `modbus.baud`, and
//! `modbus.parity` even or odd with one stop bit (the USART's 9-bit word:
//! 8 data bits and the parity bit), or none with two stop bits (Modbus over
//! Serial Line §2.5.1). A byte with a parity, framing or noise error, or
//! one the USART overran, is dropped and counted: its frame then misses a
//! byte and the frame layer drops it (the gap, or the CRC), as the
//! specification asks of a frame with a parity error.
//!
//! **Times.** TIM5 counts µs from 0 to 2³² − 2 and wraps (the HAL's counter
//! sets the auto-reload to its ticks less one): at the wrap, once every 71
//! minutes, one silence reads 1 µs short, against the 859 µs and 2,005 µs
//! (at 19,200 baud) the frame layer tells apart.

use core::cell::RefCell;

use cortex_m::interrupt::{free, Mutex};
use stm32f4xx_hal as hal;

use hal::gpio::{Output, PA1};
use hal::pac::{self, interrupt};
use hal::prelude::*;
use hal::serial::{Event, Flag, RxISR, Serial, TxISR};
use hal::timer::CounterUs;
use suntracker::sunspec::ModbusLine;
use suntracker_modbus::{HalfDuplexLine, UartIo};

/// Received bytes waiting with their stamps: a whole frame (256 bytes).
pub const RX_RING_LEN: usize = 256;

/// USART2 and the transceiver's driver enable.
struct Usart2 {
    serial: Serial<pac::USART2>,
    de: PA1<Output>,
}

impl UartIo for Usart2 {
    fn take_received(&mut self) -> Option<Result<u8, ()>> {
        if !self.serial.is_rx_not_empty() {
            return None;
        }
        // Reading the data register clears the error flags; a byte with
        // an error is lost.
        Some(hal::prelude::_embedded_hal_serial_nb_Read::read(&mut self.serial).map_err(|_| ()))
    }
    fn tx_empty(&mut self) -> bool {
        self.serial.is_tx_empty()
    }
    fn write(&mut self, byte: u8) {
        // Called when TXE is set: the write does not block.
        let _ = hal::prelude::_embedded_hal_serial_nb_Write::write(&mut self.serial, byte);
    }
    fn tx_complete(&mut self) -> bool {
        self.serial.flags().contains(Flag::TransmissionComplete)
    }
    fn set_tx_interrupts(&mut self, empty: bool, complete: bool) {
        let events = [
            (Event::TxEmpty, empty),
            (Event::TransmissionComplete, complete),
        ];
        for (event, on) in events {
            if on {
                self.serial.listen(event);
            } else {
                self.serial.unlisten(event);
            }
        }
    }
    fn set_driver(&mut self, on: bool) {
        self.de.set_state(on.into());
    }
}

/// The UART, the µs clock and the line's state, owned by the USART2
/// interrupt once set up.
struct Line {
    uart: Usart2,
    clock: CounterUs<pac::TIM5>,
    state: HalfDuplexLine<RX_RING_LEN>,
}

static LINE: Mutex<RefCell<Option<Line>>> = Mutex::new(RefCell::new(None));

/// Runs `f` on the line, inside a critical section (`None` before it is
/// set up).
fn with_line<R>(f: impl FnOnce(&mut Line) -> R) -> Option<R> {
    free(|cs| {
        // Never borrowed elsewhere inside a critical section: the `try_`
        // form only keeps the panicking path out.
        let mut line = LINE.borrow(cs).try_borrow_mut().ok()?;
        line.as_mut().map(f)
    })
}

/// The line's bytes in and out.
// The vector binding of `#[interrupt]` is an `#[export_name]` item, which
// the `unsafe_code` lint counts; the handler itself has no unsafe code.
#[allow(unsafe_code)]
#[interrupt]
fn USART2() {
    with_line(|line| {
        let t_us = line.clock.now().ticks();
        line.state.on_interrupt(&mut line.uart, t_us);
    });
}

/// The Modbus server's line ([`ModbusLine`]) on USART2.
pub struct Rs485Server {
    _private: (),
}

impl Rs485Server {
    /// Takes USART2 (configured by the caller at the configuration's rate
    /// and frame format), the driver-enable pin and TIM5's µs counter,
    /// starts the counter free-running and the receive interrupt, the
    /// driver released (receiving). The caller unmasks USART2 in the NVIC.
    pub fn start(
        mut serial: Serial<pac::USART2>,
        mut de: PA1<Output>,
        mut clock: CounterUs<pac::TIM5>,
    ) -> Self {
        de.set_low();
        // u32::MAX µs fits TIM5's 32-bit auto-reload: cannot fail.
        let _ = clock.start(u32::MAX.micros());
        serial.listen(Event::RxNotEmpty);
        free(|cs| {
            if let Ok(mut slot) = LINE.borrow(cs).try_borrow_mut() {
                *slot = Some(Line {
                    uart: Usart2 { serial, de },
                    clock,
                    state: HalfDuplexLine::new(),
                });
            }
        });
        Rs485Server { _private: () }
    }
}

impl ModbusLine for Rs485Server {
    fn receive(&mut self) -> Option<(u8, u32)> {
        with_line(|l| l.state.receive()).flatten()
    }
    fn now_us(&mut self) -> u32 {
        with_line(|l| l.clock.now().ticks()).unwrap_or(0)
    }
    fn send(&mut self, frame: &[u8]) {
        with_line(|l| l.state.start_send(&mut l.uart, frame));
    }
    fn busy(&mut self) -> bool {
        with_line(|l| l.state.busy()).unwrap_or(false)
    }
}
