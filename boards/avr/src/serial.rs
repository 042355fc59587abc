//! Interrupt-driven USARTs (ATmega2560 datasheet §22 / ATmega328P §20
//! "USART": "Clock Generation" (double speed, UBRR formula), "Receive
//! Complete Flag and Interrupt", "Data Reception", register description of
//! UDRn, UCSRnA/B/C, UBRRn).
//!
//! Reception: the RX-complete interrupt moves each byte into a ring buffer
//! (`suntracker::console::RxRing`: 128 bytes for the GPS port; 255 for the
//! log and console port on the ATmega2560, 64 on the ATmega328P); when it
//! is full the byte is dropped and counted ([`Usart0::rx_dropped`]) and the
//! gap is marked for the reader (the ring's documentation; every line typed
//! is still answered, [`Usart0::take_lost_lines`]), as are bytes the
//! hardware lost before the interrupt ran (data overrun, DORn) and bytes
//! with a framing error (FEn, dropped too). `Read` takes what is waiting without blocking; with
//! nothing waiting it sleeps (idle mode) until a byte arrives, as
//! `embedded_io::Read` asks — the `drivers` GPS reader's `poll_if_ready`
//! first asks `ReadReady` and only reads when a byte is there, so a main
//! loop never waits. With interrupts disabled an empty `Read` would never
//! end; it returns [`SerialError::WouldBlockForever`] instead.
//!
//! Transmission is blocking, byte by byte on UDREn (one byte is 87 µs at
//! 115200 baud, the log's rate; no transmit buffer, no TX interrupt).

use core::cell::RefCell;

use avr_device::interrupt::{self, CriticalSection, Mutex};
use embedded_io::{ErrorKind, ErrorType};

use suntracker::console::RxRing;

use super::{chip, CPU_HZ};

/// Receive ring of the GPS port (USART1): a whole NMEA sentence (at most
/// 82 bytes) with room to spare.
#[cfg(avr_atmega2560)]
const RX_LEN_GPS: usize = 128;
/// Receive ring of the log and console port (USART0) on the ATmega2560:
/// 255 bytes (the most a ring with 8-bit indices holds), 22 ms of input at
/// 115200 baud, longer than the loop's longest daytime tick, so that lines
/// typed or pasted back to back wait for the loop instead of overflowing
/// it (64 bytes lasted 5.6 ms: a tick of 15 ms lost the end of 30 `save`s
/// pasted at once, `emu/tests/mega_scenarios.rs` (l)).
#[cfg(avr_atmega2560)]
const RX_LEN_CONSOLE: usize = 255;
/// Receive ring of the log and console port (USART0) on the ATmega328P:
/// a whole console line (`suntracker::console::LINE_LEN`), in 2 KB of RAM.
#[cfg(not(avr_atmega2560))]
const RX_LEN_CONSOLE: usize = 64;

/// Bytes moved per critical section by `read` (bounds the time interrupts
/// are off to about 150 cycles).
const READ_BURST: usize = 8;

/// UBRR for `baud_hz` in double-speed mode (U2Xn = 1), rounded to nearest:
/// UBRR = CPU / (8 · baud) − 1 (115200 → 16, 2.1 % error as on every
/// Arduino; 9600 → 207, 0.2 %). Clamped to the 12-bit register.
pub(crate) fn ubrr_u2x(baud_hz: u32) -> u16 {
    let divisor = baud_hz.saturating_mul(8);
    let ratio = (CPU_HZ + divisor / 2)
        .checked_div(divisor)
        .unwrap_or(u32::MAX);
    ratio.saturating_sub(1).min(0x0FFF) as u16
}

/// Errors of the serial ports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SerialError {
    /// `read` found no byte while interrupts are disabled: waiting would
    /// never end.
    WouldBlockForever,
}

impl embedded_io::Error for SerialError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

macro_rules! usart {
    (
        $(#[$doc:meta])* $name:ident, $periph:ident, $ring:ident, $len:ident, $isr:ident,
        $ucsra:ident, $ucsrb:ident, $ucsrc:ident, $ubrr:ident, $udr:ident,
        $u2x:ident, $txc:ident, $rxen:ident, $txen:ident, $rxcie:ident, $ucsz:ident,
        $rxc:ident, $udre:ident, $fe:ident, $dor:ident
    ) => {
        static $ring: Mutex<RefCell<RxRing<$len>>> = Mutex::new(RefCell::new(RxRing::new()));

        $(#[$doc])*
        pub struct $name {
            usart: chip::$periph,
            /// A byte was written since the last flush (TXC is meaningful).
            sent: bool,
        }

        impl $name {
            /// Takes the USART: 8 data bits, no parity, 1 stop bit at
            /// `baud_hz` (double speed), receiver with its interrupt and
            /// transmitter on, ring emptied.
            pub fn new(usart: chip::$periph, baud_hz: u32) -> Self {
                interrupt::free(|cs| {
                    if let Ok(mut ring) = $ring.borrow(cs).try_borrow_mut() {
                        ring.clear();
                    }
                });
                usart.$ubrr().write(|w| w.set(ubrr_u2x(baud_hz)));
                usart.$ucsra().write(|w| w.$u2x().set_bit());
                usart.$ucsrc().write(|w| w.$ucsz().chr8());
                usart.$ucsrb().write(|w| {
                    w.$txen().set_bit().$rxen().set_bit().$rxcie().set_bit()
                });
                $name { usart, sent: false }
            }

            /// Takes the USART for sending only (a log): 8N1 at `baud_hz`,
            /// transmitter on, receiver and its interrupt off. Its receive
            /// ring is then not linked (when nothing else uses it) and its
            /// RX vector need not be bound: 134 B of RAM on an 8-bit board.
            /// Reading such a port finds nothing.
            pub fn new_tx_only(usart: chip::$periph, baud_hz: u32) -> Self {
                usart.$ubrr().write(|w| w.set(ubrr_u2x(baud_hz)));
                usart.$ucsra().write(|w| w.$u2x().set_bit());
                usart.$ucsrc().write(|w| w.$ucsz().chr8());
                usart.$ucsrb().write(|w| w.$txen().set_bit());
                $name { usart, sent: false }
            }

            /// Bytes received and lost so far (ring full, hardware overrun,
            /// framing error); saturates at 65,535.
            pub fn rx_dropped(&self) -> u16 {
                interrupt::free(|cs| $ring.borrow(cs).try_borrow().map_or(0, |r| r.dropped()))
            }

            /// Bytes waiting in the ring.
            pub fn rx_waiting(&self) -> usize {
                interrupt::free(|cs| $ring.borrow(cs).try_borrow().map_or(0, |r| r.len()))
            }

            /// Lines the ring lost whole since the last call
            /// (`RxRing::take_lost_lines`).
            pub fn take_lost_lines() -> u8 {
                interrupt::free(|cs| {
                    $ring
                        .borrow(cs)
                        .try_borrow_mut()
                        .map_or(0, |mut r| r.take_lost_lines())
                })
            }

            /// Moves up to `buf.len()` received bytes out of the ring
            /// without waiting; 0 when none. For a port whose value is
            /// busy elsewhere (the log writes through it while the main
            /// loop reads the console typed on it): only the main loop
            /// takes from the ring, through this or through `Read`.
            pub fn take_received(buf: &mut [u8]) -> usize {
                let mut n = 0;
                while n < buf.len() {
                    let Some(rest) = buf.get_mut(n..) else { break };
                    let got = interrupt::free(|cs| Self::take(rest, cs));
                    if got == 0 {
                        break;
                    }
                    n += got;
                }
                n
            }

            /// Waits until every written byte has left the shift register
            /// (then the pins may change or the CPU may stop).
            pub fn flush_all(&mut self) {
                while self.usart.$ucsra().read().$udre().bit_is_clear() {}
                if self.sent {
                    while self.usart.$ucsra().read().$txc().bit_is_clear() {}
                    self.sent = false;
                }
            }

            /// Gives the USART back, receiver interrupt off.
            pub fn release(mut self) -> chip::$periph {
                self.flush_all();
                self.usart.$ucsrb().write(|w| w.$txen().set_bit().$rxen().set_bit());
                self.usart
            }

            fn put_byte(&mut self, byte: u8) {
                while self.usart.$ucsra().read().$udre().bit_is_clear() {}
                // Clear TXC (write 1) with the data, keeping double speed.
                self.usart
                    .$ucsra()
                    .write(|w| w.$u2x().set_bit().$txc().set_bit());
                self.usart.$udr().write(|w| w.set(byte));
                self.sent = true;
            }

            fn take(buf: &mut [u8], cs: CriticalSection<'_>) -> usize {
                let Ok(mut ring) = $ring.borrow(cs).try_borrow_mut() else {
                    return 0;
                };
                let n = buf.len().min(READ_BURST);
                buf.get_mut(..n).map_or(0, |b| ring.pop_into(b))
            }
        }

        /// The RX-complete handler's work; bound by `avr_board_interrupts!`.
        #[inline(always)]
        pub fn $isr() {
            // SAFETY: only status and data registers are read here (UCSRnA,
            // UDRn); reading UDRn is what acknowledges the interrupt. The
            // interrupt is enabled only by the constructor, whose value
            // owns the USART and never reads UDRn itself.
            let usart = unsafe { chip::$periph::steal() };
            let status = usart.$ucsra().read();
            let byte = usart.$udr().read().bits();
            interrupt::free(|cs| {
                let Ok(mut ring) = $ring.borrow(cs).try_borrow_mut() else {
                    return;
                };
                if status.$dor().bit_is_set() {
                    ring.lose();
                }
                if status.$rxc().bit_is_set() && status.$fe().bit_is_clear() {
                    ring.push(byte);
                } else {
                    ring.lose();
                }
            });
        }

        impl ErrorType for $name {
            type Error = SerialError;
        }

        impl embedded_io::ReadReady for $name {
            fn read_ready(&mut self) -> Result<bool, SerialError> {
                Ok(self.rx_waiting() > 0)
            }
        }

        impl embedded_io::Read for $name {
            /// Up to `buf.len()` waiting bytes; sleeps until the first one
            /// if none is waiting (see the module text).
            fn read(&mut self, buf: &mut [u8]) -> Result<usize, SerialError> {
                if buf.is_empty() {
                    return Ok(0);
                }
                loop {
                    let n = Self::take_received(buf);
                    if n > 0 {
                        return Ok(n);
                    }
                    if !interrupt::is_enabled() {
                        return Err(SerialError::WouldBlockForever);
                    }
                    // SAFETY: SMCR only selects the sleep mode; CPU is
                    // touched here and in `sleep_until_interrupt` only, to
                    // set idle mode and the sleep enable bit around SLEEP.
                    let cpu = unsafe { chip::CPU::steal() };
                    super::sleep_until_interrupt(&cpu);
                }
            }
        }

        impl embedded_io::Write for $name {
            /// Writes all of `buf`, blocking on UDREn for each byte.
            fn write(&mut self, buf: &[u8]) -> Result<usize, SerialError> {
                for &byte in buf {
                    self.put_byte(byte);
                }
                Ok(buf.len())
            }

            fn flush(&mut self) -> Result<(), SerialError> {
                self.flush_all();
                Ok(())
            }
        }

        impl suntracker::log::Sink for $name {
            // Not inlined: the log and the console call it at some twenty
            // places.
            #[inline(never)]
            fn put(&mut self, bytes: &[u8]) {
                for &byte in bytes {
                    self.put_byte(byte);
                }
            }

            #[inline(never)]
            fn byte(&mut self, byte: u8) {
                self.put_byte(byte);
            }
        }
    };
}

usart!(
    /// USART0 (TXD0/RXD0: Uno D1/D0, Mega D1/D0, the USB bridge).
    Usart0, USART0, RX0, RX_LEN_CONSOLE, on_usart0_rx,
    ucsr0a, ucsr0b, ucsr0c, ubrr0, udr0,
    u2x0, txc0, rxen0, txen0, rxcie0, ucsz0,
    rxc0, udre0, fe0, dor0
);

#[cfg(avr_atmega2560)]
usart!(
    /// USART1 of the ATmega2560 (TXD1/RXD1: Mega D18/D19, the GPS).
    Usart1, USART1, RX1, RX_LEN_GPS, on_usart1_rx,
    ucsr1a, ucsr1b, ucsr1c, ubrr1, udr1,
    u2x1, txc1, rxen1, txen1, rxcie1, ucsz1,
    rxc1, udre1, fe1, dor1
);
