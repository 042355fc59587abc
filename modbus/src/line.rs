//! A half-duplex RS-485 line driven by a UART's interrupts: the received
//! bytes queued with their arrival times, a reply sent from the line's own
//! buffer byte by byte by the transmit-register-empty interrupt, and the
//! transceiver's driver released by the transmission-complete interrupt
//! once the last stop bit has left. A board implements [`UartIo`] over its
//! UART's flags and its driver-enable pin and calls
//! [`HalfDuplexLine::on_interrupt`] from the UART's interrupt.
//!
//! The line either receives or sends, as the bus does (Modbus over Serial
//! Line §2.5.1: a master waits for the reply before it speaks again). What
//! the receiver gets while the line sends is dropped: with /RE tied to DE
//! the transceiver gives no echo, and a byte then is not for us.

use crate::ring::StampedRing;
use crate::rtu::MAX_FRAME_BYTES;

/// What the line needs of a UART and its transceiver.
pub trait UartIo {
    /// The byte the receiver holds (reading it clears the receiver's flags):
    /// `Some(Ok(byte))`, `Some(Err(()))` for a byte with a parity, framing
    /// or noise error or after an overrun, `None` when nothing came.
    fn take_received(&mut self) -> Option<Result<u8, ()>>;
    /// The transmit data register is empty (the next byte may go in).
    fn tx_empty(&mut self) -> bool;
    /// Puts `byte` into the transmit data register.
    fn write(&mut self, byte: u8);
    /// The last byte's stop bit has left the shift register.
    fn tx_complete(&mut self) -> bool;
    /// Enables or disables the transmit-register-empty and the
    /// transmission-complete interrupts.
    fn set_tx_interrupts(&mut self, empty: bool, complete: bool);
    /// Drives (`true`) or releases the bus: the transceiver's DE (and /RE).
    fn set_driver(&mut self, on: bool);
}

/// The line's state between the UART's interrupt and the loop; see the
/// module documentation. `N` bytes of receive ring.
#[derive(Debug, Clone)]
pub struct HalfDuplexLine<const N: usize> {
    rx: StampedRing<N>,
    tx: [u8; MAX_FRAME_BYTES],
    tx_len: usize,
    /// The next byte of `tx` to hand the transmitter.
    tx_at: usize,
    /// A reply is going out (until its last stop bit has left).
    sending: bool,
}

impl<const N: usize> Default for HalfDuplexLine<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> HalfDuplexLine<N> {
    /// A line receiving, nothing queued.
    pub const fn new() -> Self {
        HalfDuplexLine {
            rx: StampedRing::new(),
            tx: [0; MAX_FRAME_BYTES],
            tx_len: 0,
            tx_at: 0,
            sending: false,
        }
    }

    /// The UART's interrupt: takes the byte received at `t_us`, hands the
    /// transmitter the next byte, releases the bus once the last has left.
    pub fn on_interrupt(&mut self, uart: &mut impl UartIo, t_us: u32) {
        match uart.take_received() {
            Some(Ok(byte)) if !self.sending => self.rx.push(byte, t_us),
            Some(Ok(_)) | None => {}
            Some(Err(())) => self.rx.lose(),
        }
        if !self.sending {
            return;
        }
        if self.tx_at < self.tx_len {
            if uart.tx_empty() {
                if let Some(&byte) = self.tx.get(self.tx_at) {
                    uart.write(byte);
                }
                self.tx_at += 1;
                if self.tx_at >= self.tx_len {
                    // The last byte is in: wait for it to leave.
                    uart.set_tx_interrupts(false, true);
                }
            }
        } else if uart.tx_complete() {
            uart.set_tx_interrupts(false, false);
            uart.set_driver(false);
            self.sending = false;
        }
    }

    /// Starts sending `frame` (at most [`MAX_FRAME_BYTES`]; the rest is
    /// cut): copies it, forgets what was received, drives the bus and
    /// enables the transmit-register-empty interrupt, which comes at once.
    /// Call it with the UART's interrupt masked (in a critical section).
    pub fn start_send(&mut self, uart: &mut impl UartIo, frame: &[u8]) {
        let len = frame.len().min(MAX_FRAME_BYTES);
        let (Some(to), Some(from)) = (self.tx.get_mut(..len), frame.get(..len)) else {
            return;
        };
        for (to, &from) in to.iter_mut().zip(from) {
            *to = from;
        }
        self.tx_len = len;
        self.tx_at = 0;
        self.sending = len > 0;
        if self.sending {
            self.rx.clear();
            uart.set_driver(true);
            uart.set_tx_interrupts(true, false);
        }
    }

    /// A reply is still going out.
    pub fn busy(&self) -> bool {
        self.sending
    }

    /// The oldest received byte with its stamp.
    pub fn receive(&mut self) -> Option<(u8, u32)> {
        self.rx.pop()
    }

    /// The receive ring (its counts).
    pub fn received(&self) -> &StampedRing<N> {
        &self.rx
    }
}
