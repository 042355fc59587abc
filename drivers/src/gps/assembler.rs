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

/// Longest sentence kept, from `$` through the checksum digits.
pub const MAX_SENTENCE_LEN: usize = 82;

const START: u8 = b'$';
const CHECKSUM_DELIMITER: u8 = b'*';
const CR: u8 = b'\r';
const LF: u8 = b'\n';

/// Why a line was not accepted as a sentence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
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
    pub fn rejected_other(&self) -> u32 {
        self.missing_checksum
            .saturating_add(self.overflow)
            .saturating_add(self.missing_start)
            .saturating_add(self.non_ascii)
            .saturating_add(self.partial)
    }

    /// Lines seen: accepted plus every rejection.
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
        *counter = counter.saturating_add(1);
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
#[derive(Debug, Clone)]
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
    pub fn stats(&self) -> AssemblerStats {
        self.stats
    }

    /// Feed one byte. Returns `Some(Ok(sentence))` when a sentence with a
    /// correct checksum has just ended (without CR LF, e.g.
    /// `$GPGGA,...*47`), `Some(Err(reason))` when a line was rejected, and
    /// `None` otherwise.
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
                self.stats.accepted = self.stats.accepted.saturating_add(1);
                // Only 0x20..=0x7e bytes are ever stored, so this is ASCII.
                core::str::from_utf8(self.buf.get(..len).unwrap_or(&[]))
                    .map_err(|_| Reject::NonAscii)
            }
            Err(reason) => Err(self.reject(reason)),
        }
    }
}

/// Checks `$<body>*hh`.
pub(super) fn check(sentence: &[u8]) -> Result<(), Reject> {
    let (&first, rest) = sentence.split_first().ok_or(Reject::MissingStart)?;
    if first != START {
        return Err(Reject::MissingStart);
    }
    let n = rest.len();
    if n < 3 {
        return Err(Reject::MissingChecksum);
    }
    let (body, tail) = rest.split_at(n - 3);
    let (star, hi, lo) = match tail {
        [s, h, l] => (*s, *h, *l),
        _ => return Err(Reject::MissingChecksum),
    };
    if star != CHECKSUM_DELIMITER {
        return Err(Reject::MissingChecksum);
    }
    let (Some(hi), Some(lo)) = (hex_value(hi), hex_value(lo)) else {
        return Err(Reject::MissingChecksum);
    };
    if body.contains(&CHECKSUM_DELIMITER) {
        return Err(Reject::MissingChecksum);
    }
    if nmea_checksum(body) == (hi << 4) | lo {
        Ok(())
    } else {
        Err(Reject::BadChecksum)
    }
}
