//! GPS over NMEA 0183: sentence framing, GGA/RMC field reading (integer
//! arithmetic, no text-to-float parsing) and a fusion of the two into a
//! [`GpsFix`], all of our own.
//!
//! ```text
//! serial bytes ─> SentenceAssembler ─> parse_sentence ───────> FixFusion ─> GpsFix
//!                 (82-char buffer,      (GGA, RMC, any talker,   (per epoch,
//!                  checksum, counters)   impossible content       stale after N ms)
//!                                        rejected)
//! ```
//!
//! A sentence with a right checksum but impossible content (latitude beyond
//! ±90°, minutes ≥ 60, `nan`, 30 February, hour 24, a leap second, ...) is a
//! parse error, counted in [`GpsStats::rejected_other`]; see `parse_sentence`.
//! [`GpsReader`] pulls the bytes from an `embedded_io::Read` port;
//! [`GpsDecoder`] takes them one at a time from anywhere else.

mod assembler;
mod coordinate;
#[cfg(test)]
mod fields;
mod fix;
mod parse;
mod plausible;
mod reader;

pub use assembler::{nmea_checksum, AssemblerStats, Reject, SentenceAssembler, MAX_SENTENCE_LEN};
pub use coordinate::Coordinate;
pub use fix::{FixFusion, GpsFix};
pub use parse::{parse_sentence, FixQuality, Gga, ParseError, Rmc, Sentence, TimeOfDayMs};
pub use reader::{Error, GpsDecoder, GpsReader, GpsStats};
