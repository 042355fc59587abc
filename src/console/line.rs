//! The line buffer: bytes in, one command line (or why it was refused)
//! out.

use crate::text::FlashStr;

/// A line length for [`LineBuffer`] that holds every command of the
/// language with room to spare (`set site.postal_code GB:SW1A 1AA` is 32
/// characters, `set site.lat_deg -33.8688 site.lon_deg 151.2093` 48).
pub const LINE_LEN: usize = 64;

/// The byte a board's receive ring leaves where it had to drop input (its
/// ring was full): ASCII CAN, "cancel". The ring writes it over its newest
/// byte, so the gap stays where it was in the stream; the line it falls in
/// is discarded and answered `error input lost`, never run with a piece
/// missing (a `set wind.stow_hz 25` that lost its `2` would be a valid
/// `set` of 5 Hz).
pub const LOST_INPUT: u8 = 0x18;

/// The byte a board's receive ring leaves where the input it had to drop
/// included a line end (ASCII EM, "end of medium"): the line it ends is
/// answered `error input lost` at once ([`super::RxRing`]).
pub const LOST_LINE_END: u8 = 0x19;

/// Why a line was refused before parsing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineError {
    /// Bytes of it were lost on the way in ([`LOST_INPUT`]): `error input
    /// lost`.
    Lost,
    /// More bytes than the buffer holds: `error line too long`.
    TooLong,
    /// A byte above 0x7F: `error non-ASCII input`.
    NonAscii,
    /// A control byte other than tab, CR, LF, backspace and DEL:
    /// `error control character`.
    Control,
}

impl LineError {
    /// The reply text after `error `.
    pub fn text(self) -> FlashStr {
        match self {
            LineError::Lost => crate::flash_str!("input lost"),
            LineError::TooLong => crate::flash_str!("line too long"),
            LineError::NonAscii => crate::flash_str!("non-ASCII input"),
            LineError::Control => crate::flash_str!("control character"),
        }
    }
}

/// Collects bytes into lines of at most `N` characters, one byte at a time,
/// in constant time per byte.
///
/// CR, LF and CR LF end a line (the LF of a CR LF pair is skipped); an
/// empty line yields nothing. Backspace (0x08) and DEL (0x7F) remove the
/// last character. A line longer than `N`, or with a byte above 0x7F or a
/// control byte (other than tab), is discarded up to its end of line and
/// then reported once as a [`LineError`]; the first problem is the one
/// reported, except lost input ([`LOST_INPUT`]), which is always the one
/// reported. A flood of bytes without an end of line only keeps the
/// buffer in that state.
#[derive(Debug, Clone)]
pub struct LineBuffer<const N: usize> {
    buf: [u8; N],
    len: usize,
    error: Option<LineError>,
    after_cr: bool,
}

impl<const N: usize> Default for LineBuffer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> LineBuffer<N> {
    /// An empty buffer.
    pub const fn new() -> Self {
        LineBuffer {
            buf: [0; N],
            len: 0,
            error: None,
            after_cr: false,
        }
    }

    /// Forgets the line being collected.
    pub fn clear(&mut self) {
        self.len = 0;
        self.error = None;
        self.after_cr = false;
    }

    /// Takes one byte; at the end of a non-empty line, the line (ASCII,
    /// without its end of line) or why it was refused.
    pub fn push(&mut self, byte: u8) -> Option<Result<&str, LineError>> {
        let after_cr = core::mem::replace(&mut self.after_cr, false);
        match byte {
            b'\n' if after_cr => None,
            b'\r' | b'\n' => {
                self.after_cr = byte == b'\r';
                self.finish()
            }
            0x08 | 0x7F => {
                if self.error.is_none() {
                    self.len = self.len.saturating_sub(1);
                }
                None
            }
            b'\t' | 0x20..=0x7E => {
                if self.error.is_none() {
                    match self.buf.get_mut(self.len) {
                        Some(slot) => {
                            *slot = byte;
                            self.len = self.len.saturating_add(1);
                        }
                        None => self.error = Some(LineError::TooLong),
                    }
                }
                None
            }
            LOST_INPUT => {
                self.error = Some(LineError::Lost);
                None
            }
            LOST_LINE_END => {
                self.error = Some(LineError::Lost);
                self.finish()
            }
            0x80..=0xFF => {
                self.error.get_or_insert(LineError::NonAscii);
                None
            }
            _ => {
                self.error.get_or_insert(LineError::Control);
                None
            }
        }
    }

    fn finish(&mut self) -> Option<Result<&str, LineError>> {
        let len = core::mem::replace(&mut self.len, 0);
        if let Some(e) = self.error.take() {
            return Some(Err(e));
        }
        if len == 0 {
            return None;
        }
        let bytes = self.buf.get(..len)?;
        Some(crate::text::ascii_str(bytes).ok_or(LineError::NonAscii))
    }
}
