//! GPS over NMEA 0183: sentence framing of our own, GGA/RMC parsing by the
//! `nmea` crate (0.8, `default-features = false`, features `GGA` and `RMC`,
//! which keeps it `no_std`), and a fusion of the two into a [`GpsFix`].
//!
//! ```text
//! serial bytes ─> SentenceAssembler ─> parse_sentence (nmea) ─> FixFusion ─> GpsFix
//!                 (82-char buffer,      (GGA, RMC, any talker)   (per epoch,
//!                  checksum, counters)                            stale after N ms)
//! ```
//! [`GpsReader`] pulls the bytes from an `embedded_io::Read` port;
//! [`GpsDecoder`] takes them one at a time from anywhere else.

mod assembler;
mod fix;
mod parse;
mod reader;

pub use assembler::{nmea_checksum, AssemblerStats, Reject, SentenceAssembler, MAX_SENTENCE_LEN};
pub use fix::{FixFusion, GpsFix};
pub use parse::{parse_sentence, FixQuality, Gga, ParseError, Rmc, Sentence, TimeOfDayMs};
pub use reader::{Error, GpsDecoder, GpsReader, GpsStats};
