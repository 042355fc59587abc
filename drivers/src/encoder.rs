//! Quadrature encoder decoding (YMT22 class optical encoder, up to 300 pulses
//! per revolution per channel, seed *chowdhury-2019*), ×4: one count per edge.
//!
//! The two channels form a 2-bit Gray code `s = (A << 1) | B`. Forward (A leads
//! B) runs `00 → 10 → 11 → 01 → 00`, backward the reverse. A transition table
//! indexed by `(previous << 2) | current` gives +1, −1, 0 (no change) or
//! *illegal* (both bits changed at once: an edge was missed), which is counted
//! as an error and does not move the count.
//!
//! Interrupt use:
//! * [`SharedEncoder`]: state in a `critical_section::Mutex`, works on every
//!   target (AVR and Cortex-M0 have no 32-bit compare-and-swap). Put it in a
//!   `static`, call [`SharedEncoder::update`] from the pin-change interrupt and
//!   [`SharedEncoder::count`] from the main loop.
//! * [`AtomicEncoder`] (targets with 32-bit atomics, e.g. thumbv7em): lock-free,
//!   the interrupt is the only writer and uses plain atomic loads and stores (no
//!   read-modify-write); the main loop only loads. Do not call `update` from two
//!   interrupts of different priority.

use core::cell::Cell;

use embedded_hal::digital::InputPin;

/// What one sample of the two channels meant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transition {
    /// No change.
    None,
    /// One count forward.
    Forward,
    /// One count backward.
    Backward,
    /// Both channels changed: an edge was missed.
    Illegal,
}

const N: Transition = Transition::None;
const F: Transition = Transition::Forward;
const B: Transition = Transition::Backward;
const X: Transition = Transition::Illegal;

/// Transition table, index `(prev << 2) | curr`, states `(A << 1) | B`.
const TABLE: [Transition; 16] = [
    // prev 00: to 00, 01, 10, 11
    N, B, F, X, //
    // prev 01
    F, N, X, B, //
    // prev 10
    B, X, N, F, //
    // prev 11
    X, F, B, N,
];

fn state(a: bool, b: bool) -> u8 {
    (u8::from(a) << 1) | u8::from(b)
}

/// Looks up one transition.
pub fn transition(prev: u8, curr: u8) -> Transition {
    TABLE
        .get(usize::from(((prev & 3) << 2) | (curr & 3)))
        .copied()
        .unwrap_or(Transition::Illegal)
}

/// A plain decoder (single owner, no interrupt sharing).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct QuadratureDecoder {
    state: u8,
    count: i32,
    errors: u32,
}

impl QuadratureDecoder {
    /// Starts from the current levels of A and B, count 0.
    pub const fn new(a: bool, b: bool) -> Self {
        Self {
            state: ((a as u8) << 1) | (b as u8),
            count: 0,
            errors: 0,
        }
    }

    /// Feeds one sample of both channels.
    pub fn update(&mut self, a: bool, b: bool) -> Transition {
        let s = state(a, b);
        let t = transition(self.state, s);
        match t {
            Transition::Forward => self.count = self.count.wrapping_add(1),
            Transition::Backward => self.count = self.count.wrapping_sub(1),
            Transition::Illegal => self.errors = self.errors.saturating_add(1),
            Transition::None => {}
        }
        self.state = s;
        t
    }

    /// Counts so far.
    pub fn count(&self) -> i32 {
        self.count
    }

    /// Illegal transitions so far.
    pub fn errors(&self) -> u32 {
        self.errors
    }

    /// Redefines the count (e.g. 0 at home).
    pub fn set_count(&mut self, count: i32) {
        self.count = count;
    }
}

/// A decoder shared between an interrupt and the main loop through a
/// critical section (every target).
#[derive(Debug)]
pub struct SharedEncoder {
    inner: critical_section::Mutex<Cell<QuadratureDecoder>>,
}

impl SharedEncoder {
    /// For a `static`; starts in state 00 (call [`SharedEncoder::set_levels`] once at start-up).
    pub const fn new() -> Self {
        Self {
            inner: critical_section::Mutex::new(Cell::new(QuadratureDecoder::new(false, false))),
        }
    }

    /// Sets the current channel levels without counting (start-up).
    pub fn set_levels(&self, a: bool, b: bool) {
        critical_section::with(|cs| {
            let cell = self.inner.borrow(cs);
            let mut d = cell.get();
            d.state = state(a, b);
            cell.set(d);
        });
    }

    /// From the pin-change interrupt: feed the levels of A and B.
    pub fn update(&self, a: bool, b: bool) -> Transition {
        critical_section::with(|cs| {
            let cell = self.inner.borrow(cs);
            let mut d = cell.get();
            let t = d.update(a, b);
            cell.set(d);
            t
        })
    }

    /// Counts so far.
    pub fn count(&self) -> i32 {
        critical_section::with(|cs| self.inner.borrow(cs).get().count)
    }

    /// Illegal transitions so far.
    pub fn errors(&self) -> u32 {
        critical_section::with(|cs| self.inner.borrow(cs).get().errors)
    }

    /// Redefines the count.
    pub fn set_count(&self, count: i32) {
        critical_section::with(|cs| {
            let cell = self.inner.borrow(cs);
            let mut d = cell.get();
            d.count = count;
            cell.set(d);
        });
    }
}

impl Default for SharedEncoder {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(target_has_atomic = "32")]
pub use atomic::AtomicEncoder;

#[cfg(target_has_atomic = "32")]
mod atomic {
    use core::sync::atomic::{AtomicI32, AtomicU32, AtomicU8, Ordering};

    use super::{state, transition, Transition};

    /// Lock-free decoder: one interrupt writes (loads and stores only), the
    /// main loop reads. Zeroing is done by the reader keeping an offset.
    #[derive(Debug)]
    pub struct AtomicEncoder {
        state: AtomicU8,
        count: AtomicI32,
        errors: AtomicU32,
    }

    impl AtomicEncoder {
        /// For a `static`; state 00, count 0.
        pub const fn new() -> Self {
            Self {
                state: AtomicU8::new(0),
                count: AtomicI32::new(0),
                errors: AtomicU32::new(0),
            }
        }

        /// From the (single) interrupt that owns the encoder.
        pub fn update(&self, a: bool, b: bool) -> Transition {
            let s = state(a, b);
            let t = transition(self.state.load(Ordering::Relaxed), s);
            match t {
                Transition::Forward => {
                    let c = self.count.load(Ordering::Relaxed);
                    self.count.store(c.wrapping_add(1), Ordering::Release);
                }
                Transition::Backward => {
                    let c = self.count.load(Ordering::Relaxed);
                    self.count.store(c.wrapping_sub(1), Ordering::Release);
                }
                Transition::Illegal => {
                    let e = self.errors.load(Ordering::Relaxed);
                    self.errors.store(e.saturating_add(1), Ordering::Release);
                }
                Transition::None => {}
            }
            self.state.store(s, Ordering::Relaxed);
            t
        }

        /// Counts so far.
        pub fn count(&self) -> i32 {
            self.count.load(Ordering::Acquire)
        }

        /// Illegal transitions so far.
        pub fn errors(&self) -> u32 {
            self.errors.load(Ordering::Acquire)
        }
    }

    impl Default for AtomicEncoder {
        fn default() -> Self {
            Self::new()
        }
    }
}

/// Driver errors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error<E> {
    /// Reading a channel failed.
    Comm(E),
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::Comm(e) => write!(f, "encoder channel read error: {e:?}"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

/// An encoder read by polling its two `InputPin`s (or from an interrupt
/// handler that owns the pins).
#[derive(Debug)]
pub struct PolledEncoder<P> {
    a: P,
    b: P,
    decoder: QuadratureDecoder,
}

impl<P: InputPin> PolledEncoder<P> {
    /// Reads A then B once to learn the starting state.
    pub fn new(mut a: P, mut b: P) -> Result<Self, Error<P::Error>> {
        let la = a.is_high().map_err(Error::Comm)?;
        let lb = b.is_high().map_err(Error::Comm)?;
        Ok(Self {
            a,
            b,
            decoder: QuadratureDecoder::new(la, lb),
        })
    }

    /// Reads A then B and decodes.
    pub fn poll(&mut self) -> Result<Transition, Error<P::Error>> {
        let la = self.a.is_high().map_err(Error::Comm)?;
        let lb = self.b.is_high().map_err(Error::Comm)?;
        Ok(self.decoder.update(la, lb))
    }

    /// The decoder state.
    pub fn decoder(&self) -> &QuadratureDecoder {
        &self.decoder
    }

    /// Gives the pins back.
    pub fn destroy(self) -> (P, P) {
        (self.a, self.b)
    }
}
