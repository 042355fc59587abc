//! Constant text that stays in flash on the 8-bit AVR.
//!
//! The AVR is a Harvard machine: an ordinary `&'static str` is copied from
//! flash into RAM by the start-up code (`.data`) because a normal load
//! instruction reads only the data space. The console's replies, the
//! configuration's key names and reasons and the log's words are some
//! 4 KB of text — half the RAM of an ATmega2560 and twice that of an
//! ATmega328P. [`FlashStr`] keeps such text in program memory
//! (`.progmem.data`, which avr-gcc's linker script places right after the
//! interrupt vectors, below 64 KB) and reads it with `LPM` (ATmega328P
//! datasheet §7.3 / ATmega2560 §8.3 "In-System Reprogrammable Flash
//! Program Memory"; AVR Instruction Set Manual, `LPM`). On every other
//! target it is a plain `&'static str`.
//!
//! Texts are made with [`flash_str!`] and written with
//! the tracker's log sink; they are ASCII (a serial
//! terminal shows them as typed), which [`flash_str!`]
//! checks when compiling.
#![no_std]
// `LPM` through inline assembly.
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]
// Every unsafe block here reads program memory with `LPM` (AVR) or turns
// checked ASCII into `str`; each carries its SAFETY argument.
#![deny(unsafe_op_in_unsafe_fn)]

/// A constant ASCII text: in program memory on AVR, a `&'static str`
/// elsewhere. Made by [`flash_str!`].
#[derive(Clone, Copy)]
pub struct FlashStr {
    #[cfg(target_arch = "avr")]
    ptr: *const u8,
    #[cfg(target_arch = "avr")]
    len: u16,
    #[cfg(not(target_arch = "avr"))]
    text: &'static str,
}

// SAFETY: a FlashStr only ever reads constant program memory.
unsafe impl Sync for FlashStr {}
unsafe impl Send for FlashStr {}

/// `bytes` as text when every byte is ASCII, else `None`. Not
/// `core::str::from_utf8`: its 256-byte UTF-8 width table is kept in RAM
/// by avr-gcc, a quarter of what an ATmega328P's tracker has.
pub fn ascii_str(bytes: &[u8]) -> Option<&str> {
    if bytes.is_ascii() {
        // SAFETY: ASCII (every byte below 0x80, just checked) is valid
        // UTF-8.
        Some(unsafe { core::str::from_utf8_unchecked(bytes) })
    } else {
        None
    }
}

/// `s` as a byte array of its length, for [`flash_str!`];
/// fails to compile for a text that is not ASCII.
pub const fn to_array<const N: usize>(s: &str) -> [u8; N] {
    let b = s.as_bytes();
    assert!(b.len() == N, "length");
    let mut a = [0u8; N];
    let mut i = 0;
    while i < N {
        assert!(b[i].is_ascii(), "flash_str! texts are ASCII");
        a[i] = b[i];
        i += 1;
    }
    a
}

impl FlashStr {
    /// The text of `bytes`, which must be a static placed in
    /// `.progmem.data` on AVR and hold `text`'s bytes; use
    /// [`flash_str!`].
    ///
    /// # Safety
    /// On AVR `bytes` must be in program memory below 64 KB.
    #[doc(hidden)]
    pub const unsafe fn from_static(bytes: &'static [u8], text: &'static str) -> FlashStr {
        #[cfg(target_arch = "avr")]
        {
            let _ = text;
            FlashStr {
                ptr: bytes.as_ptr(),
                len: bytes.len() as u16,
            }
        }
        #[cfg(not(target_arch = "avr"))]
        {
            let _ = bytes;
            FlashStr { text }
        }
    }

    /// Length in bytes.
    pub const fn len(self) -> usize {
        #[cfg(target_arch = "avr")]
        {
            self.len as usize
        }
        #[cfg(not(target_arch = "avr"))]
        {
            self.text.len()
        }
    }

    /// True for the empty text.
    pub const fn is_empty(self) -> bool {
        self.len() == 0
    }

    /// Byte `i`, `None` past the end.
    pub fn byte(self, i: usize) -> Option<u8> {
        #[cfg(target_arch = "avr")]
        {
            if i >= self.len() {
                return None;
            }
            // SAFETY: in bounds of a program-memory static (`from_static`).
            Some(unsafe { lpm(self.ptr.add(i)) })
        }
        #[cfg(not(target_arch = "avr"))]
        {
            self.text.as_bytes().get(i).copied()
        }
    }

    /// The bytes in order.
    pub fn bytes(self) -> impl Iterator<Item = u8> {
        (0..self.len()).filter_map(move |i| self.byte(i))
    }

    /// Whether the text equals `other`, ASCII case ignored.
    pub fn eq_ignore_ascii_case(self, other: &str) -> bool {
        self.eq_ignore_ascii_case_bytes(other.as_bytes())
    }

    /// Whether the text's bytes equal `other`, ASCII case ignored.
    pub fn eq_ignore_ascii_case_bytes(self, other: &[u8]) -> bool {
        self.len() == other.len()
            && self
                .bytes()
                .zip(other.iter())
                .all(|(a, b)| a.eq_ignore_ascii_case(b))
    }

    /// Copies the text into `buf` `CHUNK` bytes at a time and hands each
    /// piece to `f` (every piece is ASCII, so valid UTF-8; a byte that is
    /// not, which `flash_str!`'s texts never have, becomes `?`).
    pub fn for_each_chunk(self, mut f: impl FnMut(&str)) {
        #[cfg(target_arch = "avr")]
        {
            const CHUNK: usize = 16;
            let mut buf = [0u8; CHUNK];
            let mut at = 0;
            while at < self.len() {
                let n = (self.len() - at).min(CHUNK);
                for (k, slot) in buf.iter_mut().take(n).enumerate() {
                    *slot = match self.byte(at + k) {
                        Some(b) if b.is_ascii() => b,
                        _ => b'?',
                    };
                }
                let piece = buf.get(..n).unwrap_or(&[]);
                // SAFETY: every byte is ASCII (below 0x80, just checked),
                // and ASCII is valid UTF-8. (`core::str::from_utf8` would
                // check it again and bring its 256-byte UTF-8 width table,
                // which avr-gcc keeps in RAM.)
                f(unsafe { core::str::from_utf8_unchecked(piece) });
                at += n;
            }
        }
        #[cfg(not(target_arch = "avr"))]
        {
            f(self.text);
        }
    }

    /// The text (hosts and Cortex-M, where it is an ordinary string).
    #[cfg(not(target_arch = "avr"))]
    pub const fn as_str(self) -> &'static str {
        self.text
    }
}

/// A table of constant ASCII texts read by number, as [`flash_strs!`]
/// makes it: the texts joined in one static and the end of each as a `u16`
/// in another (both in program memory on AVR). An entry costs its text and
/// two bytes, where a table of [`FlashStr`]s, or a `match` returning one,
/// costs a pointer and a length (four bytes on AVR, eight on a 32-bit
/// core) and the code to load them.
#[derive(Clone, Copy)]
pub struct FlashStrs {
    bytes: &'static [u8],
    ends: &'static [u16],
}

impl FlashStrs {
    /// The table of `bytes` (the texts joined) and `ends` (the end of
    /// each); use [`flash_strs!`].
    ///
    /// # Safety
    /// On AVR both must be statics in program memory below 64 KB; the
    /// ends must rise and every text between two of them be ASCII (as
    /// [`join`] and [`ends`] make them).
    #[doc(hidden)]
    pub const unsafe fn from_static(bytes: &'static [u8], ends: &'static [u16]) -> FlashStrs {
        FlashStrs { bytes, ends }
    }

    /// Number of texts.
    pub const fn len(self) -> usize {
        self.ends.len()
    }

    /// True for an empty table.
    pub const fn is_empty(self) -> bool {
        self.ends.is_empty()
    }

    fn end(self, i: usize) -> Option<usize> {
        let slot = self.ends.get(i)?;
        #[cfg(target_arch = "avr")]
        {
            // Two LPMs, low byte first (AVR is little-endian).
            let p = (slot as *const u16).cast::<u8>();
            // SAFETY: `ends` is a static in program memory on AVR
            // (`from_static`), and both bytes are in `slot`.
            let (lo, hi) = unsafe { (lpm(p), lpm(p.add(1))) };
            Some(usize::from(u16::from_le_bytes([lo, hi])))
        }
        #[cfg(not(target_arch = "avr"))]
        {
            Some(usize::from(*slot))
        }
    }

    /// Text `i`, `None` past the end.
    pub fn get(self, i: usize) -> Option<FlashStr> {
        let start = match i.checked_sub(1) {
            Some(before) => self.end(before)?,
            None => 0,
        };
        // Only the slice's address and length are taken here: on AVR its
        // bytes are read with LPM, by FlashStr.
        let piece = self.bytes.get(start..self.end(i)?)?;
        #[cfg(target_arch = "avr")]
        {
            // A piece of a static below 64 KB: its length fits.
            Some(FlashStr {
                ptr: piece.as_ptr(),
                len: piece.len() as u16,
            })
        }
        #[cfg(not(target_arch = "avr"))]
        {
            // SAFETY: `join` checked every byte ASCII when compiling, and
            // ASCII is valid UTF-8.
            Some(FlashStr {
                text: unsafe { core::str::from_utf8_unchecked(piece) },
            })
        }
    }
}

/// Total length of `texts`, for [`flash_strs!`].
#[doc(hidden)]
pub const fn joined_len(texts: &[&str]) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < texts.len() {
        n += texts[i].len();
        i += 1;
    }
    n
}

/// `texts` joined, for [`flash_strs!`]; fails to compile for a text that is
/// not ASCII or a table longer than a `u16` can index.
#[doc(hidden)]
pub const fn join<const N: usize>(texts: &[&str]) -> [u8; N] {
    assert!(N <= u16::MAX as usize, "flash_strs! tables end below 64 KB");
    let mut out = [0u8; N];
    let (mut at, mut i) = (0, 0);
    while i < texts.len() {
        let b = texts[i].as_bytes();
        let mut k = 0;
        while k < b.len() {
            assert!(b[k].is_ascii(), "flash_strs! texts are ASCII");
            out[at] = b[k];
            at += 1;
            k += 1;
        }
        i += 1;
    }
    assert!(at == N, "length");
    out
}

/// The end of each of `texts` in their join, for [`flash_strs!`].
#[doc(hidden)]
pub const fn ends<const N: usize>(texts: &[&str]) -> [u16; N] {
    assert!(texts.len() == N, "count");
    let mut out = [0u16; N];
    let (mut at, mut i) = (0, 0);
    while i < N {
        at += texts[i].len();
        // `join` fails to compile past u16::MAX.
        out[i] = at as u16;
        i += 1;
    }
    out
}

/// Reads one byte of program memory (`LPM Rd, Z`).
///
/// # Safety
/// `p` must point into program memory below 64 KB.
#[cfg(target_arch = "avr")]
#[inline(always)]
unsafe fn lpm(p: *const u8) -> u8 {
    let byte: u8;
    // SAFETY: LPM only reads program memory at Z; the caller vouches for
    // the address.
    unsafe {
        core::arch::asm!("lpm {0}, Z", out(reg) byte, in("Z") p, options(pure, readonly, nostack));
    }
    byte
}

/// Reads a value from a static in program memory on AVR (`.progmem.data`,
/// below 64 KB), an ordinary read elsewhere.
///
/// # Safety
/// On AVR, `value` must be (in) a static placed in `.progmem.data`.
unsafe fn read_flash<T: Copy>(value: &'static T) -> T {
    #[cfg(target_arch = "avr")]
    {
        let mut out = core::mem::MaybeUninit::<T>::uninit();
        let src = (value as *const T).cast::<u8>();
        let dst = out.as_mut_ptr().cast::<u8>();
        for i in 0..core::mem::size_of::<T>() {
            // SAFETY: in bounds of both; `src` is program memory (caller).
            unsafe { dst.add(i).write(lpm(src.add(i))) };
        }
        // SAFETY: every byte was copied from a valid `T` (`T: Copy`).
        unsafe { out.assume_init() }
    }
    #[cfg(not(target_arch = "avr"))]
    {
        *value
    }
}

/// On hosts and Cortex-M the text is an ordinary `str`.
#[cfg(not(target_arch = "avr"))]
impl core::ops::Deref for FlashStr {
    type Target = str;
    fn deref(&self) -> &str {
        self.text
    }
}

impl PartialEq for FlashStr {
    fn eq(&self, other: &FlashStr) -> bool {
        self.len() == other.len() && self.bytes().eq(other.bytes())
    }
}

impl Eq for FlashStr {}

impl PartialEq<&str> for FlashStr {
    fn eq(&self, other: &&str) -> bool {
        self.len() == other.len() && self.bytes().eq(other.bytes())
    }
}

impl PartialEq<str> for FlashStr {
    fn eq(&self, other: &str) -> bool {
        self.len() == other.len() && self.bytes().eq(other.bytes())
    }
}

impl core::fmt::Display for FlashStr {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let mut r = Ok(());
        self.for_each_chunk(|s| {
            if r.is_ok() {
                r = f.write_str(s);
            }
        });
        r
    }
}

impl core::fmt::Debug for FlashStr {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("\"")?;
        core::fmt::Display::fmt(self, f)?;
        f.write_str("\"")
    }
}

/// A [`FlashStr`] of a string literal (or constant): kept in program
/// memory on AVR, an ordinary string elsewhere. The text must be ASCII.
///
/// ```
/// let ok = progmem::flash_str!("ok save");
/// assert_eq!(ok, "ok save");
/// assert_eq!(ok.len(), 7);
/// ```
#[macro_export]
macro_rules! flash_str {
    ($text:expr) => {{
        const TEXT: &str = $text;
        #[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
        static BYTES: [u8; TEXT.len()] = $crate::to_array::<{ TEXT.len() }>(TEXT);
        // SAFETY: on AVR, BYTES is in `.progmem.data` (attribute above),
        // which the linker places after the vectors, below 64 KB.
        unsafe { $crate::FlashStr::from_static(&BYTES, TEXT) }
    }};
}

/// A [`FlashStrs`] table of the texts given, in program memory on AVR; the
/// texts must be ASCII (checked when compiling).
///
/// ```
/// let words = progmem::flash_strs!("north", "east", "", "south");
/// assert_eq!(words.len(), 4);
/// assert_eq!(words.get(0).unwrap(), "north");
/// assert_eq!(words.get(1).unwrap(), "east");
/// assert_eq!(words.get(2).unwrap(), "");
/// assert_eq!(words.get(3).unwrap(), "south");
/// assert!(words.get(4).is_none());
/// ```
#[macro_export]
macro_rules! flash_strs {
    // The texts as one constant slice expression (a caller that leaves
    // some out by `cfg` builds it itself).
    (@texts $texts:expr) => {{
        const TEXTS: &[&str] = $texts;
        #[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
        static BYTES: [u8; $crate::joined_len(TEXTS)] =
            $crate::join::<{ $crate::joined_len(TEXTS) }>(TEXTS);
        #[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
        static ENDS: [u16; TEXTS.len()] = $crate::ends::<{ TEXTS.len() }>(TEXTS);
        // SAFETY: on AVR both statics are in `.progmem.data` (attributes
        // above), below 64 KB; `join` and `ends` made them from ASCII texts.
        unsafe { $crate::FlashStrs::from_static(&BYTES, &ENDS) }
    }};
    ($($text:expr),* $(,)?) => {
        $crate::flash_strs!(@texts &[$($text),*])
    };
}

/// A constant (a table, a value) in program memory on AVR, an ordinary
/// static elsewhere; read by copy. Made by [`progmem!`], which places the
/// static in `.progmem.data`.
#[repr(transparent)]
pub struct ProgMem<T: ?Sized>(T);

// SAFETY: a ProgMem is never written; its reads copy constant memory.
unsafe impl<T: ?Sized> Sync for ProgMem<T> {}

impl<T: Copy> ProgMem<T> {
    /// Wraps `value`; use [`progmem!`].
    ///
    /// # Safety
    /// On AVR the static that holds the result must be in `.progmem.data`
    /// (below 64 KB), as [`progmem!`] places it.
    #[doc(hidden)]
    pub const unsafe fn new(value: T) -> ProgMem<T> {
        ProgMem(value)
    }

    /// A copy of the value.
    pub fn load(&'static self) -> T {
        // SAFETY: `self` is a static in program memory on AVR (`new`).
        unsafe { read_flash(&self.0) }
    }
}

impl<T: Copy, const N: usize> ProgMem<[T; N]> {
    /// Number of elements.
    pub const fn len(&self) -> usize {
        N
    }

    /// True for an empty table.
    pub const fn is_empty(&self) -> bool {
        N == 0
    }

    /// A copy of element `i`, `None` past the end (one element is read,
    /// not the table).
    pub fn get(&'static self, i: usize) -> Option<T> {
        self.as_slice().get(i)
    }

    /// Copies of the elements in order.
    pub fn iter(&'static self) -> impl Iterator<Item = T> {
        self.as_slice().iter()
    }

    /// The table as a slice of any length in program memory (what a
    /// caller that takes tables of several lengths stores).
    pub const fn as_slice(&'static self) -> &'static ProgMem<[T]> {
        self
    }
}

/// A table of a length known at run time in program memory on AVR
/// ([`ProgMem::as_slice`]).
///
/// ```
/// progmem::progmem! {
///     static ODD: [u8; 3] = [1, 3, 5];
/// }
/// let odd: &'static progmem::ProgMem<[u8]> = ODD.as_slice();
/// assert_eq!(odd.len(), 3);
/// assert_eq!(odd.get(1), Some(3));
/// assert_eq!(odd.get(3), None);
/// assert_eq!(odd.iter().sum::<u8>(), 9);
/// ```
impl<T: Copy> ProgMem<[T]> {
    /// Number of elements.
    pub const fn len(&self) -> usize {
        self.0.len()
    }

    /// True for an empty table.
    pub const fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// A copy of element `i`, `None` past the end (one element is read,
    /// not the table).
    pub fn get(&'static self, i: usize) -> Option<T> {
        // SAFETY: `self` is a static in program memory on AVR (`new`, then
        // `as_slice`), and so is each of its elements.
        self.0.get(i).map(|slot| unsafe { read_flash(slot) })
    }

    /// Copies of the elements in order.
    pub fn iter(&'static self) -> impl Iterator<Item = T> {
        // SAFETY: as in `get`.
        self.0.iter().map(|slot| unsafe { read_flash(slot) })
    }
}

/// A static in program memory on AVR (an ordinary static elsewhere), read
/// through [`ProgMem`]:
///
/// ```
/// progmem::progmem! {
///     /// Powers of ten.
///     static TENS: [u16; 3] = [1, 10, 100];
/// }
/// assert_eq!(TENS.get(2), Some(100));
/// assert_eq!(TENS.get(3), None);
/// ```
#[macro_export]
macro_rules! progmem {
    ($(#[$meta:meta])* $vis:vis static $name:ident : $ty:ty = $init:expr;) => {
        $(#[$meta])*
        #[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
        // SAFETY: on AVR the static is in `.progmem.data` (attribute
        // above), which the linker places after the vectors, below 64 KB.
        $vis static $name: $crate::ProgMem<$ty> = unsafe { $crate::ProgMem::new($init) };
    };
}
