//! A board's receive ring for a serial port: one producer (the receive
//! interrupt) and one consumer (the main loop), `N` bytes, no allocation.
//!
//! When the ring is full a byte is dropped, and the gap is marked so that
//! the console never runs a line with a piece missing and answers every
//! line typed:
//!
//! - the newest byte stored becomes [`LOST_INPUT`] (bytes lost inside a
//!   line), or [`LOST_LINE_END`] when the byte dropped ended a line: the
//!   line buffer answers that line `error input lost` at once;
//! - when the newest byte stored itself ends a line (it must stay, or two
//!   lines would become one), a line end dropped is counted
//!   ([`RxRing::take_lost_lines`]: the firmware answers each such line
//!   `error input lost` too), and the start of a line dropped is marked
//!   with [`LOST_INPUT`] in front of the next byte stored (the rest of
//!   that line).
//!
//! CR, LF and CR LF each end one line, as for the line buffer; an LF right
//! after a CR ends nothing, and dropping it loses nothing. A byte lost
//! before it was read at all (a receive error: overrun, framing) is marked
//! the same way, as a byte inside a line. For a GPS port the marker makes
//! the sentence's checksum fail.

use super::line::{LOST_INPUT, LOST_LINE_END};

/// The receive ring; see the module documentation. Its logic is one
/// copy for every size (its state over the bytes as a slice): an 8-bit
/// board has two rings, and each copy of the logic is inlined into a
/// receive interrupt.
#[derive(Debug, Clone)]
pub struct RxRing<const N: usize> {
    bytes: [u8; N],
    state: RingState,
}

/// The ring's indices and counts, apart from its bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct RingState {
    /// The oldest byte's slot.
    tail: usize,
    /// The slot the next byte goes to.
    head: usize,
    /// Bytes stored.
    len: usize,
    /// Bytes dropped or lost, saturating.
    dropped: u16,
    /// A gap to mark in front of the next byte stored.
    gap_pending: bool,
    /// The last byte received was a CR.
    after_cr: bool,
    /// Line ends dropped that no marker in the ring stands for.
    lost_lines: u8,
}

impl<const N: usize> Default for RxRing<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> RxRing<N> {
    /// An empty ring.
    pub const fn new() -> Self {
        RxRing {
            bytes: [0; N],
            state: RingState::EMPTY,
        }
    }

    /// Bytes waiting.
    pub fn len(&self) -> usize {
        self.state.len
    }

    /// Nothing waiting.
    pub fn is_empty(&self) -> bool {
        self.state.len == 0
    }

    /// Bytes dropped (ring full) or lost (receive errors) so far, at most
    /// 65,535.
    pub fn dropped(&self) -> u16 {
        self.state.dropped
    }

    /// Line ends dropped since the last call that no marker in the ring
    /// stands for (at most 255): each is a line to answer `error input
    /// lost`.
    pub fn take_lost_lines(&mut self) -> u8 {
        core::mem::take(&mut self.state.lost_lines)
    }

    /// Empties the ring and forgets its counts.
    pub fn clear(&mut self) {
        self.state = RingState::EMPTY;
    }

    /// A byte received: stored, or dropped with its gap marked when the
    /// ring is full. Constant time.
    pub fn push(&mut self, byte: u8) {
        self.state.push(&mut self.bytes, byte);
    }

    /// A byte lost before it could be read (a receive error): marked as a
    /// byte inside a line.
    pub fn lose(&mut self) {
        self.state.lose(&mut self.bytes);
    }

    /// The oldest byte.
    pub fn pop(&mut self) -> Option<u8> {
        self.state.pop(&self.bytes)
    }

    /// Moves the oldest bytes into `out`; how many.
    pub fn pop_into(&mut self, out: &mut [u8]) -> usize {
        let mut n = 0;
        for slot in out.iter_mut() {
            match self.state.pop(&self.bytes) {
                Some(b) => *slot = b,
                None => break,
            }
            n += 1;
        }
        n
    }
}

impl RingState {
    const EMPTY: RingState = RingState {
        tail: 0,
        head: 0,
        len: 0,
        dropped: 0,
        gap_pending: false,
        after_cr: false,
        lost_lines: 0,
    };

    #[inline(never)]
    fn push(&mut self, bytes: &mut [u8], byte: u8) {
        let after_cr = core::mem::replace(&mut self.after_cr, byte == b'\r');
        let line_end = byte == b'\r' || (byte == b'\n' && !after_cr);
        // The LF of a CR LF ends nothing (the line buffer skips it, or ends
        // an empty line with it when its CR was dropped): stored as it is,
        // a gap to mark stays for the next byte; dropped, nothing is lost.
        let lf_of_crlf = byte == b'\n' && after_cr;
        // Otherwise a gap pending is marked first when there is room for
        // the marker, and the byte is stored when room is left after it.
        // One store of each and one count of a drop (written out per case,
        // 100 B more on the ATmega2560).
        let mut room = bytes.len().saturating_sub(self.len);
        if room >= 1 && self.gap_pending && !lf_of_crlf {
            self.store(bytes, LOST_INPUT);
            self.gap_pending = false;
            room -= 1;
        }
        if room >= 1 {
            self.store(bytes, byte);
            return;
        }
        self.dropped = self.dropped.saturating_add(1);
        if !lf_of_crlf {
            self.mark_gap(bytes, line_end);
        }
    }

    #[inline(never)]
    fn lose(&mut self, bytes: &mut [u8]) {
        self.dropped = self.dropped.saturating_add(1);
        self.after_cr = false;
        if self.len < bytes.len() {
            self.store(bytes, LOST_INPUT);
            self.gap_pending = false;
        } else {
            self.mark_gap(bytes, false);
        }
    }

    fn pop(&mut self, bytes: &[u8]) -> Option<u8> {
        if self.len == 0 {
            return None;
        }
        let byte = bytes.get(self.tail).copied();
        self.tail = next(self.tail, bytes.len());
        self.len -= 1;
        byte
    }

    /// Stores `byte`; the caller checked that there is room.
    fn store(&mut self, bytes: &mut [u8], byte: u8) {
        if let Some(slot) = bytes.get_mut(self.head) {
            *slot = byte;
            self.head = next(self.head, bytes.len());
            self.len += 1;
        }
    }

    /// The ring is full and a byte was dropped (`line_end`: it ended a
    /// line): the gap is marked on the newest byte, or in front of the next
    /// one when the newest ends a line.
    fn mark_gap(&mut self, bytes: &mut [u8], line_end: bool) {
        let newest = self
            .head
            .checked_sub(1)
            .unwrap_or(bytes.len().saturating_sub(1));
        match bytes.get_mut(newest).filter(|_| self.len > 0) {
            Some(slot) if !matches!(*slot, b'\r' | b'\n' | LOST_LINE_END) => {
                *slot = if line_end { LOST_LINE_END } else { LOST_INPUT };
            }
            // The newest byte ends a line and stays. A line end dropped
            // ends a line lost whole (counted); other bytes start one whose
            // rest may be stored later: marked in front of it.
            _ if line_end => {
                self.lost_lines = self.lost_lines.saturating_add(1);
                self.gap_pending = false;
            }
            _ => self.gap_pending = true,
        }
    }
}

/// The slot after `i` in a ring of `n` (no division: an 8-bit MCU has
/// none).
fn next(i: usize, n: usize) -> usize {
    if i + 1 >= n {
        0
    } else {
        i + 1
    }
}
