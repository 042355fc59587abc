//! NMEA 0183 sentence framing: bytes in, checksum-verified sentences out.
//!
//! A sentence is `$` + up to 79 more printable ASCII characters ending in
//! `*hh` (two hexadecimal digits, the XOR of every byte between `$` and `*`),
//! then CR LF. The buffer holds [`MAX_SENTENCE_LEN`] = 82 characters from `$`
//! through the checksum digits; CR LF are not stored.
//!
//! Rejections and their counters:
//! - `Overflow`: more than 82 characters before the line ended;
//! - `MissingStart`: a line with content that did not begin with `$`;
//! - `NonAscii`: a byte >= 0x80 or a control character inside a sentence;
//! - `Partial`: a sentence cut off by a new `$`, or CR not followed by LF;
//! - `MissingChecksum` / `BadChecksum`: no well-formed `*hh`, or the wrong value.
//!
//! A bare LF (without CR) is accepted as the end of a line, since some
//! receivers and log files drop the CR.

use crate::counter::count_up;

/// Longest sentence kept, from `$` through the checksum digits.
///
/// ```
/// use drivers::gps::{Reject, SentenceAssembler, MAX_SENTENCE_LEN};
///
/// // NMEA 0183: at most 82 characters including `$` and CR LF; one more
/// // character and the line is refused.
/// let mut asm = SentenceAssembler::new();
/// let long = [b'A'; MAX_SENTENCE_LEN];
/// let verdict = core::iter::once(&b'$').chain(&long).find_map(|&b| asm.push(b).map(|r| r.err()));
/// assert_eq!(verdict, Some(Some(Reject::Overflow)));
/// ```
pub const MAX_SENTENCE_LEN: usize = 82;

const START: u8 = b'$';
const CHECKSUM_DELIMITER: u8 = b'*';
const CR: u8 = b'\r';
const LF: u8 = b'\n';

/// Why a line was not accepted as a sentence.
///
/// ```
/// use drivers::gps::{Reject, SentenceAssembler};
///
/// let mut asm = SentenceAssembler::new();
/// let mut verdicts = Vec::new();
/// // u-blox's GGA example with a wrong checksum (5B → 5C), then a sentence
/// // without `*hh`.
/// for &b in b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5C\r\n$GPTXT,hello\r\n" {
///     if let Some(Err(reason)) = asm.push(b) {
///         verdicts.push(reason);
///     }
/// }
/// assert_eq!(verdicts, [Reject::BadChecksum, Reject::MissingChecksum]);
/// assert_eq!(verdicts[0].to_string(), "checksum does not match the sentence");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Reject {
    /// Longer than [`MAX_SENTENCE_LEN`].
    Overflow,
    /// Content before the end of a line without a leading `$`.
    MissingStart,
    /// Non-ASCII byte or control character inside the sentence.
    NonAscii,
    /// Cut off by a new `$`, or CR not followed by LF.
    Partial,
    /// No `*hh` at the end of the sentence.
    MissingChecksum,
    /// The checksum digits do not match the XOR of the sentence body.
    BadChecksum,
}

impl core::fmt::Display for Reject {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Reject::Overflow => write!(f, "sentence longer than {MAX_SENTENCE_LEN} bytes"),
            Reject::MissingStart => f.write_str("line without a leading $"),
            Reject::NonAscii => f.write_str("non-ASCII byte or control character in the sentence"),
            Reject::Partial => f.write_str("sentence cut off"),
            Reject::MissingChecksum => f.write_str("no *hh checksum at the end of the sentence"),
            Reject::BadChecksum => f.write_str("checksum does not match the sentence"),
        }
    }
}

impl core::error::Error for Reject {}

/// Counters of everything the assembler has seen.
///
/// ```
/// use drivers::gps::SentenceAssembler;
///
/// let mut asm = SentenceAssembler::new();
/// // A GSV (checksum 0x79 computed in Python), then a byte above 0x7F.
/// for &b in b"$GPGSV,1,1,00*79\r\n$GP\xB0\r\n" {
///     asm.push(b);
/// }
/// let stats = asm.stats();
/// assert_eq!((stats.accepted, stats.non_ascii), (1, 1));
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AssemblerStats {
    /// Sentences with a correct checksum.
    pub accepted: u32,
    /// Rejected for [`Reject::BadChecksum`].
    pub bad_checksum: u32,
    /// Rejected for [`Reject::MissingChecksum`].
    pub missing_checksum: u32,
    /// Rejected for [`Reject::Overflow`].
    pub overflow: u32,
    /// Rejected for [`Reject::MissingStart`].
    pub missing_start: u32,
    /// Rejected for [`Reject::NonAscii`].
    pub non_ascii: u32,
    /// Rejected for [`Reject::Partial`].
    pub partial: u32,
}

impl AssemblerStats {
    /// Every rejection except a bad checksum.
    ///
    /// ```
    /// use drivers::gps::AssemblerStats;
    ///
    /// let stats = AssemblerStats { bad_checksum: 4, overflow: 1, partial: 2, ..Default::default() };
    /// assert_eq!(stats.rejected_other(), 3);
    /// ```
    pub fn rejected_other(&self) -> u32 {
        self.missing_checksum
            .saturating_add(self.overflow)
            .saturating_add(self.missing_start)
            .saturating_add(self.non_ascii)
            .saturating_add(self.partial)
    }

    /// Lines seen: accepted plus every rejection.
    ///
    /// ```
    /// use drivers::gps::AssemblerStats;
    ///
    /// let stats = AssemblerStats { accepted: 10, bad_checksum: 4, partial: 2, ..Default::default() };
    /// assert_eq!(stats.sentences(), 16);
    /// ```
    pub fn sentences(&self) -> u32 {
        self.accepted
            .saturating_add(self.bad_checksum)
            .saturating_add(self.rejected_other())
    }

    fn count(&mut self, reject: Reject) {
        let counter = match reject {
            Reject::Overflow => &mut self.overflow,
            Reject::MissingStart => &mut self.missing_start,
            Reject::NonAscii => &mut self.non_ascii,
            Reject::Partial => &mut self.partial,
            Reject::MissingChecksum => &mut self.missing_checksum,
            Reject::BadChecksum => &mut self.bad_checksum,
        };
        count_up(counter);
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum State {
    /// Between sentences; `content` is true once a non-blank byte was seen.
    Idle { content: bool },
    /// Inside a sentence, storing bytes.
    InSentence,
    /// Got CR, waiting for LF.
    AfterCr,
    /// The current line was already rejected; skip to the next LF or `$`.
    Discard,
}

/// Assembles NMEA sentences from a byte stream in a fixed buffer.
///
/// ```
/// use drivers::gps::SentenceAssembler;
///
/// let mut asm = SentenceAssembler::new();
/// let mut sentences = Vec::new();
/// // u-blox's GGA example; a bare LF also ends a line.
/// for &b in b"$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B\n" {
///     if let Some(Ok(s)) = asm.push(b) {
///         sentences.push(s.to_owned());
///     }
/// }
/// assert_eq!(sentences, ["$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B"]);
/// ```
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SentenceAssembler {
    buf: [u8; MAX_SENTENCE_LEN],
    len: usize,
    state: State,
    stats: AssemblerStats,
}

impl Default for SentenceAssembler {
    fn default() -> Self {
        Self::new()
    }
}

/// XOR of all bytes, the NMEA 0183 checksum of a sentence body.
///
/// ```
/// use drivers::gps::nmea_checksum;
///
/// // u-blox NEO-6 protocol specification, GGA example: checksum 5B.
/// let body = b"GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,";
/// assert_eq!(nmea_checksum(body), 0x5B);
/// assert_eq!(nmea_checksum(b""), 0);
/// ```
pub fn nmea_checksum(body: &[u8]) -> u8 {
    body.iter().fold(0, |acc, b| acc ^ b)
}

fn hex_value(digit: u8) -> Option<u8> {
    match digit {
        b'0'..=b'9' => Some(digit - b'0'),
        b'A'..=b'F' => Some(digit - b'A' + 10),
        b'a'..=b'f' => Some(digit - b'a' + 10),
        _ => None,
    }
}

impl SentenceAssembler {
    /// An empty assembler with zeroed counters.
    ///
    /// ```
    /// use drivers::gps::{AssemblerStats, SentenceAssembler};
    ///
    /// let asm = SentenceAssembler::new();
    /// assert_eq!(asm.stats(), AssemblerStats::default());
    /// ```
    pub const fn new() -> Self {
        Self {
            buf: [0; MAX_SENTENCE_LEN],
            len: 0,
            state: State::Idle { content: false },
            stats: AssemblerStats {
                accepted: 0,
                bad_checksum: 0,
                missing_checksum: 0,
                overflow: 0,
                missing_start: 0,
                non_ascii: 0,
                partial: 0,
            },
        }
    }

    /// Counters so far.
    ///
    /// ```
    /// use drivers::gps::SentenceAssembler;
    ///
    /// // A GSV (checksum 0x79 computed in Python), cut off by the next `$`.
    /// let mut asm = SentenceAssembler::new();
    /// for &b in b"$GPGSV,1,1$GPGSV,1,1,00*79\r\n" {
    ///     asm.push(b);
    /// }
    /// assert_eq!((asm.stats().partial, asm.stats().accepted), (1, 1));
    /// ```
    pub fn stats(&self) -> AssemblerStats {
        self.stats
    }

    /// Feed one byte. Returns `Some(Ok(sentence))` when a sentence with a
    /// correct checksum has just ended (without CR LF, e.g.
    /// `$GPGGA,...*47`), `Some(Err(reason))` when a line was rejected, and
    /// `None` otherwise.
    ///
    /// ```
    /// use drivers::gps::{Reject, SentenceAssembler};
    ///
    /// let mut asm = SentenceAssembler::new();
    /// // u-blox's RMC example: nothing until the line ends.
    /// let rmc = b"$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57\r";
    /// assert!(rmc.iter().all(|&b| asm.push(b).is_none()));
    /// assert_eq!(
    ///     asm.push(b'\n'),
    ///     Some(Ok("$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57"))
    /// );
    /// // A control character inside a sentence rejects the line.
    /// asm.push(b'$');
    /// assert_eq!(asm.push(0x07), Some(Err(Reject::NonAscii)));
    /// ```
    pub fn push(&mut self, byte: u8) -> Option<Result<&str, Reject>> {
        match self.state {
            State::Idle { content } => match byte {
                START => self.start(),
                LF => {
                    self.state = State::Idle { content: false };
                    if content {
                        return Some(Err(self.reject(Reject::MissingStart)));
                    }
                }
                CR | b' ' | b'\t' | 0 => {}
                _ => self.state = State::Idle { content: true },
            },
            State::Discard => match byte {
                START => self.start(),
                LF => self.state = State::Idle { content: false },
                _ => {}
            },
            State::InSentence => match byte {
                START => {
                    self.start();
                    return Some(Err(self.reject(Reject::Partial)));
                }
                CR => self.state = State::AfterCr,
                LF => return Some(self.finish()),
                0x20..=0x7e => {
                    if let Some(slot) = self.buf.get_mut(self.len) {
                        *slot = byte;
                        self.len += 1;
                    } else {
                        self.state = State::Discard;
                        return Some(Err(self.reject(Reject::Overflow)));
                    }
                }
                _ => {
                    self.state = State::Discard;
                    return Some(Err(self.reject(Reject::NonAscii)));
                }
            },
            State::AfterCr => match byte {
                LF => return Some(self.finish()),
                START => {
                    self.start();
                    return Some(Err(self.reject(Reject::Partial)));
                }
                _ => {
                    self.state = State::Discard;
                    return Some(Err(self.reject(Reject::Partial)));
                }
            },
        }
        None
    }

    /// Call at the end of the stream: an unterminated sentence is counted as
    /// [`Reject::Partial`] and an unterminated line without `$` as
    /// [`Reject::MissingStart`].
    ///
    /// ```
    /// use drivers::gps::{Reject, SentenceAssembler};
    ///
    /// let mut asm = SentenceAssembler::new();
    /// b"$GPGGA,0927".iter().for_each(|&b| drop(asm.push(b)));
    /// assert_eq!(asm.finish_stream(), Some(Reject::Partial));
    /// assert_eq!(asm.finish_stream(), None); // nothing left
    /// assert_eq!(asm.stats().partial, 1);
    /// ```
    pub fn finish_stream(&mut self) -> Option<Reject> {
        let reason = match self.state {
            State::InSentence | State::AfterCr => Some(Reject::Partial),
            State::Idle { content: true } => Some(Reject::MissingStart),
            State::Idle { content: false } | State::Discard => None,
        };
        self.len = 0;
        self.state = State::Idle { content: false };
        reason.map(|r| self.reject(r))
    }

    fn start(&mut self) {
        self.len = 0;
        if let Some(slot) = self.buf.first_mut() {
            *slot = START;
            self.len = 1;
        }
        self.state = State::InSentence;
    }

    // Out of line on the AVR: inlined at its constant call sites, each kept
    // a copy of the saturating 32-bit increment.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn reject(&mut self, reason: Reject) -> Reject {
        self.stats.count(reason);
        reason
    }

    fn finish(&mut self) -> Result<&str, Reject> {
        self.state = State::Idle { content: false };
        let len = self.len;
        self.len = 0;
        let sentence = self.buf.get(..len).unwrap_or(&[]);
        let verdict = check(sentence);
        match verdict {
            Ok(()) => {
                count_up(&mut self.stats.accepted);
                // Only 0x20..=0x7e bytes are ever stored, so this is ASCII.
                ascii_text(self.buf.get(..len).unwrap_or(&[])).ok_or(Reject::NonAscii)
            }
            Err(reason) => Err(self.reject(reason)),
        }
    }
}

/// `bytes` as text when every byte is ASCII. Not `core::str::from_utf8`:
/// for the one case the assembler has (printable ASCII) it would bring its
/// general UTF-8 validation and 256-byte width table (530 bytes of a
/// Cortex-M4F image, the table in RAM on an AVR).
#[allow(unsafe_code)]
fn ascii_text(bytes: &[u8]) -> Option<&str> {
    // A byte loop, not `<[u8]>::is_ascii` (word-at-a-time code, larger on
    // the AVR, for at most 82 bytes).
    if bytes.iter().all(|b| *b < 0x80) {
        // SAFETY: every byte is below 0x80 (just checked): ASCII, which is
        // valid UTF-8 byte for byte.
        Some(unsafe { core::str::from_utf8_unchecked(bytes) })
    } else {
        None
    }
}

/// Checks `$<body>*hh`.
// One pass over the body for the stray `*` and the checksum (as
// `contains` and then `nmea_checksum`, 532 B on the AVR, the generic
// search among them).
pub(super) fn check(sentence: &[u8]) -> Result<(), Reject> {
    let (&first, rest) = sentence.split_first().ok_or(Reject::MissingStart)?;
    if first != START {
        return Err(Reject::MissingStart);
    }
    let [body @ .., star, hi, lo] = rest else {
        return Err(Reject::MissingChecksum);
    };
    if *star != CHECKSUM_DELIMITER {
        return Err(Reject::MissingChecksum);
    }
    let (Some(hi), Some(lo)) = (hex_value(*hi), hex_value(*lo)) else {
        return Err(Reject::MissingChecksum);
    };
    let mut sum = 0;
    for &b in body {
        if b == CHECKSUM_DELIMITER {
            return Err(Reject::MissingChecksum);
        }
        sum ^= b;
    }
    if sum == (hi << 4) | lo {
        Ok(())
    } else {
        Err(Reject::BadChecksum)
    }
}
