//! Quadrature encoder decoding (YMT22 class optical encoder, up to 300 pulses
//! per revolution per channel, Chowdhury et al. 2019), ×4: one count per edge.
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
///
/// ```
/// use drivers::encoder::{QuadratureDecoder, Transition};
///
/// let mut d = QuadratureDecoder::new(false, false);
/// let seen: Vec<Transition> = [(true, false), (true, false), (false, true)]
///     .into_iter()
///     .map(|(a, b)| d.update(a, b))
///     .collect();
/// assert_eq!(seen, [Transition::Forward, Transition::None, Transition::Illegal]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

fn state(a: bool, b: bool) -> u8 {
    (u8::from(a) << 1) | u8::from(b)
}

/// The position of state `s` (`(A << 1) | B`) in the Gray-code cycle
/// 00 → 10 → 11 → 01 that A leading B runs: B, then A xor B.
fn cycle_position(s: u8) -> u8 {
    ((s & 1) << 1) | (((s >> 1) ^ s) & 1)
}

/// The transition from state `prev` to state `curr`.
///
/// ```
/// use drivers::encoder::{transition, Transition};
///
/// // States (A << 1) | B; A leading B runs 00 → 10 → 11 → 01 → 00.
/// assert_eq!(transition(0b00, 0b10), Transition::Forward);
/// assert_eq!(transition(0b10, 0b00), Transition::Backward);
/// assert_eq!(transition(0b11, 0b11), Transition::None);
/// assert_eq!(transition(0b01, 0b10), Transition::Illegal); // both changed
/// ```
// Inlined into the pin-change interrupt's decoders (as at opt-level "s"
// without the hint): a call there costs the handler cycles. Computed from
// the positions in the cycle, not looked up: a table is constant data the
// AVR copies into RAM at reset (16 B).
#[inline]
pub fn transition(prev: u8, curr: u8) -> Transition {
    match cycle_position(curr).wrapping_sub(cycle_position(prev)) & 3 {
        0 => Transition::None,
        1 => Transition::Forward,
        3 => Transition::Backward,
        _ => Transition::Illegal,
    }
}

/// A plain decoder (single owner, no interrupt sharing).
///
/// ```
/// use drivers::encoder::QuadratureDecoder;
///
/// // One full Gray-code cycle forward (A leads B), ×4: four counts.
/// let mut d = QuadratureDecoder::new(false, false);
/// for (a, b) in [(true, false), (true, true), (false, true), (false, false)] {
///     d.update(a, b);
/// }
/// assert_eq!(d.count(), 4);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct QuadratureDecoder {
    state: u8,
    count: i32,
    errors: u32,
}

impl QuadratureDecoder {
    /// Starts from the current levels of A and B, count 0.
    ///
    /// ```
    /// use drivers::encoder::{QuadratureDecoder, Transition};
    ///
    /// // Starting at 11: 11 → 01 is forward, 11 → 10 backward.
    /// let mut d = QuadratureDecoder::new(true, true);
    /// assert_eq!(d.update(false, true), Transition::Forward);
    /// assert_eq!(d.count(), 1);
    /// ```
    pub const fn new(a: bool, b: bool) -> Self {
        Self {
            state: ((a as u8) << 1) | (b as u8),
            count: 0,
            errors: 0,
        }
    }

    /// Feeds one sample of both channels.
    ///
    /// ```
    /// use drivers::encoder::{QuadratureDecoder, Transition};
    ///
    /// let mut d = QuadratureDecoder::new(false, false);
    /// assert_eq!(d.update(false, true), Transition::Backward); // 00 → 01
    /// assert_eq!(d.update(false, true), Transition::None);
    /// assert_eq!(d.update(true, false), Transition::Illegal); // 01 → 10: an edge missed
    /// assert_eq!((d.count(), d.errors()), (-1, 1));
    /// ```
    #[inline]
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
    ///
    /// ```
    /// use drivers::encoder::QuadratureDecoder;
    ///
    /// let mut d = QuadratureDecoder::new(false, false);
    /// d.update(true, false); // 00 → 10
    /// d.update(true, true); // 10 → 11
    /// assert_eq!(d.count(), 2);
    /// ```
    pub fn count(&self) -> i32 {
        self.count
    }

    /// Illegal transitions so far.
    ///
    /// ```
    /// use drivers::encoder::QuadratureDecoder;
    ///
    /// let mut d = QuadratureDecoder::new(false, false);
    /// d.update(true, true); // 00 → 11: both channels changed
    /// assert_eq!((d.count(), d.errors()), (0, 1));
    /// ```
    pub fn errors(&self) -> u32 {
        self.errors
    }

    /// Redefines the count (e.g. 0 at home).
    ///
    /// ```
    /// use drivers::encoder::QuadratureDecoder;
    ///
    /// let mut d = QuadratureDecoder::new(false, false);
    /// d.set_count(i32::MAX);
    /// d.update(true, false); // wraps
    /// assert_eq!(d.count(), i32::MIN);
    /// ```
    pub fn set_count(&mut self, count: i32) {
        self.count = count;
    }
}

/// A decoder shared between an interrupt and the main loop through a
/// critical section (every target).
///
/// ```
/// use drivers::encoder::SharedEncoder;
///
/// static ENCODER: SharedEncoder = SharedEncoder::new();
///
/// // In the pin-change interrupt: the levels of A and B.
/// fn on_pin_change(a: bool, b: bool) {
///     ENCODER.update(a, b);
/// }
///
/// ENCODER.set_levels(false, false);
/// for (a, b) in [(true, false), (true, true), (false, true)] {
///     on_pin_change(a, b);
/// }
/// assert_eq!(ENCODER.count(), 3); // read from the main loop
/// ```
#[derive(Debug)]
pub struct SharedEncoder {
    inner: critical_section::Mutex<Cell<QuadratureDecoder>>,
}

impl SharedEncoder {
    /// For a `static`; starts in state 00 (call [`SharedEncoder::set_levels`] once at start-up).
    ///
    /// ```
    /// use drivers::encoder::SharedEncoder;
    ///
    /// static ENCODER: SharedEncoder = SharedEncoder::new();
    /// assert_eq!((ENCODER.count(), ENCODER.errors()), (0, 0));
    /// ```
    pub const fn new() -> Self {
        Self {
            inner: critical_section::Mutex::new(Cell::new(QuadratureDecoder::new(false, false))),
        }
    }

    /// Sets the current channel levels without counting (start-up).
    ///
    /// ```
    /// use drivers::encoder::{SharedEncoder, Transition};
    ///
    /// let enc = SharedEncoder::new();
    /// enc.set_levels(true, true); // both channels high at power-on
    /// assert_eq!(enc.update(false, true), Transition::Forward); // 11 → 01
    /// assert_eq!(enc.count(), 1);
    /// ```
    pub fn set_levels(&self, a: bool, b: bool) {
        critical_section::with(|cs| {
            let cell = self.inner.borrow(cs);
            let mut d = cell.get();
            d.state = state(a, b);
            cell.set(d);
        });
    }

    /// From the pin-change interrupt: feed the levels of A and B.
    ///
    /// ```
    /// use drivers::encoder::{SharedEncoder, Transition};
    ///
    /// let enc = SharedEncoder::new();
    /// assert_eq!(enc.update(false, true), Transition::Backward); // 00 → 01
    /// assert_eq!(enc.update(true, false), Transition::Illegal); // 01 → 10
    /// assert_eq!((enc.count(), enc.errors()), (-1, 1));
    /// ```
    #[inline]
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
    ///
    /// ```
    /// use drivers::encoder::SharedEncoder;
    ///
    /// let enc = SharedEncoder::new();
    /// enc.update(true, false);
    /// assert_eq!(enc.count(), 1);
    /// ```
    pub fn count(&self) -> i32 {
        critical_section::with(|cs| self.inner.borrow(cs).get().count)
    }

    /// Illegal transitions so far.
    ///
    /// ```
    /// use drivers::encoder::SharedEncoder;
    ///
    /// let enc = SharedEncoder::new();
    /// enc.update(true, true); // 00 → 11
    /// assert_eq!(enc.errors(), 1);
    /// ```
    pub fn errors(&self) -> u32 {
        critical_section::with(|cs| self.inner.borrow(cs).get().errors)
    }

    /// Redefines the count.
    ///
    /// ```
    /// use drivers::encoder::SharedEncoder;
    ///
    /// let enc = SharedEncoder::new();
    /// enc.set_count(-300); // e.g. the home position
    /// enc.update(true, false);
    /// assert_eq!(enc.count(), -299);
    /// ```
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
    ///
    /// ```
    /// use drivers::encoder::AtomicEncoder;
    ///
    /// static ENCODER: AtomicEncoder = AtomicEncoder::new();
    /// // The main loop zeroes by keeping an offset.
    /// let home = ENCODER.count();
    /// for (a, b) in [(false, true), (true, true), (true, false)] {
    ///     ENCODER.update(a, b); // from the one interrupt that owns it
    /// }
    /// assert_eq!(ENCODER.count() - home, -3); // B leads A: backward
    /// ```
    #[derive(Debug)]
    pub struct AtomicEncoder {
        state: AtomicU8,
        count: AtomicI32,
        errors: AtomicU32,
    }

    impl AtomicEncoder {
        /// For a `static`; state 00, count 0.
        ///
        /// ```
        /// use drivers::encoder::AtomicEncoder;
        ///
        /// static ENCODER: AtomicEncoder = AtomicEncoder::new();
        /// assert_eq!((ENCODER.count(), ENCODER.errors()), (0, 0));
        /// ```
        pub const fn new() -> Self {
            Self {
                state: AtomicU8::new(0),
                count: AtomicI32::new(0),
                errors: AtomicU32::new(0),
            }
        }

        /// From the (single) interrupt that owns the encoder.
        ///
        /// ```
        /// use drivers::encoder::{AtomicEncoder, Transition};
        ///
        /// let enc = AtomicEncoder::new();
        /// assert_eq!(enc.update(true, false), Transition::Forward); // 00 → 10
        /// assert_eq!(enc.update(false, true), Transition::Illegal); // 10 → 01
        /// ```
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
        ///
        /// ```
        /// use drivers::encoder::AtomicEncoder;
        ///
        /// let enc = AtomicEncoder::new();
        /// enc.update(true, false);
        /// enc.update(true, true);
        /// assert_eq!(enc.count(), 2);
        /// ```
        pub fn count(&self) -> i32 {
            self.count.load(Ordering::Acquire)
        }

        /// Illegal transitions so far.
        ///
        /// ```
        /// use drivers::encoder::AtomicEncoder;
        ///
        /// let enc = AtomicEncoder::new();
        /// enc.update(true, true); // 00 → 11
        /// assert_eq!((enc.count(), enc.errors()), (0, 1));
        /// ```
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
///
/// ```
/// use drivers::encoder::{Error, PolledEncoder};
/// use embedded_hal::digital::ErrorKind;
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
/// use embedded_hal_mock::eh1::MockError;
///
/// // Channel A cannot be read.
/// let err = MockError::Io(std::io::ErrorKind::NotConnected);
/// let mut a = Pin::new(&[T::get(State::Low).with_error(err.clone())]);
/// let mut b = Pin::new(&[]);
/// let e = PolledEncoder::new(a.clone(), b.clone()).err();
/// assert_eq!(e, Some(Error::Comm(err)));
/// a.done();
/// b.done();
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
///
/// ```
/// use drivers::encoder::PolledEncoder;
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
///
/// // A, B read at start (00), then 10, 11: A leads B, two counts forward.
/// let (h, l) = (T::get(State::High), T::get(State::Low));
/// let a = Pin::new(&[l.clone(), h.clone(), h.clone()]);
/// let b = Pin::new(&[l.clone(), l.clone(), h.clone()]);
/// let mut enc = PolledEncoder::new(a, b)?;
/// enc.poll()?;
/// enc.poll()?;
/// assert_eq!(enc.decoder().count(), 2);
/// let (mut a, mut b) = enc.destroy();
/// a.done();
/// b.done();
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct PolledEncoder<P> {
    a: P,
    b: P,
    decoder: QuadratureDecoder,
}

impl<P: InputPin> PolledEncoder<P> {
    /// Reads A then B once to learn the starting state.
    ///
    /// ```
    /// use drivers::encoder::{PolledEncoder, Transition};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // Both channels high at start (state 11): 11 → 01 is forward.
    /// let (h, l) = (T::get(State::High), T::get(State::Low));
    /// let a = Pin::new(&[h.clone(), l.clone()]);
    /// let b = Pin::new(&[h.clone(), h.clone()]);
    /// let mut enc = PolledEncoder::new(a, b)?;
    /// assert_eq!(enc.poll()?, Transition::Forward);
    /// let (mut a, mut b) = enc.destroy();
    /// a.done();
    /// b.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
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
    ///
    /// ```
    /// use drivers::encoder::{PolledEncoder, Transition};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // 00 at start, then 01 (B leads: backward), 01 again (no change).
    /// let (h, l) = (T::get(State::High), T::get(State::Low));
    /// let a = Pin::new(&[l.clone(), l.clone(), l.clone()]);
    /// let b = Pin::new(&[l.clone(), h.clone(), h.clone()]);
    /// let mut enc = PolledEncoder::new(a, b)?;
    /// assert_eq!(enc.poll()?, Transition::Backward);
    /// assert_eq!(enc.poll()?, Transition::None);
    /// let (mut a, mut b) = enc.destroy();
    /// a.done();
    /// b.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn poll(&mut self) -> Result<Transition, Error<P::Error>> {
        let la = self.a.is_high().map_err(Error::Comm)?;
        let lb = self.b.is_high().map_err(Error::Comm)?;
        Ok(self.decoder.update(la, lb))
    }

    /// The decoder state.
    ///
    /// ```
    /// use drivers::encoder::{PolledEncoder, Transition};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// // 00 at start, then 11: both channels changed, an edge was missed.
    /// let (h, l) = (T::get(State::High), T::get(State::Low));
    /// let a = Pin::new(&[l.clone(), h.clone()]);
    /// let b = Pin::new(&[l.clone(), h.clone()]);
    /// let mut enc = PolledEncoder::new(a, b)?;
    /// assert_eq!(enc.poll()?, Transition::Illegal);
    /// assert_eq!((enc.decoder().count(), enc.decoder().errors()), (0, 1));
    /// let (mut a, mut b) = enc.destroy();
    /// a.done();
    /// b.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn decoder(&self) -> &QuadratureDecoder {
        &self.decoder
    }

    /// Gives the pins back.
    ///
    /// ```
    /// use drivers::encoder::PolledEncoder;
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    ///
    /// let enc = PolledEncoder::new(Pin::new(&[T::get(State::Low)]), Pin::new(&[T::get(State::High)]))?;
    /// let (mut a, mut b) = enc.destroy();
    /// a.done();
    /// b.done();
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    pub fn destroy(self) -> (P, P) {
        (self.a, self.b)
    }
}
