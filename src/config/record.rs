//! The [`Config`] as a record of the two-slot CRC-32 store
//! ([`crate::persist::ConfigStore`]): its magic, layout version and
//! length, and the store of a [`Config`] ([`ConfigStore::new`]).

#[cfg(feature = "linear")]
use super::codec::PAYLOAD_LEN_V9;
use super::codec::{
    PAYLOAD_LEN_V2, PAYLOAD_LEN_V3, PAYLOAD_LEN_V4, PAYLOAD_LEN_V5, PAYLOAD_LEN_V6, PAYLOAD_LEN_V7,
    PAYLOAD_LEN_V8,
};
use super::{Config, PAYLOAD_LEN};
use crate::persist::{record_len, ConfigStore, Payload, Record, SLOT_LEN};
use crate::ports::Storage;

/// Layout version written by this firmware: 2 added `log.status_min`, 3
/// the operator's hold, 4 the Modbus, weather-stow, supply and overcast
/// settings (`modbus.*`, `stow.*`, `supply.*`, `overcast.*`), 5 the C
/// axis's `axis.c.continuous`, 6 `site.utc_offset_h`, `wind.m_s_per_hz`
/// and `modbus.timeout_stow`, 7 each axis's `drive`, `max_current_ma`
/// and `overcurrent_ms`, 8 each axis's `back_speed_deg_s`, 9
/// `supply.calibration_mv`, 10 each axis's linear actuator
/// (`pivot_a_mm` to `pot_extended_counts`: written by an image built
/// with the `linear` feature; one without writes version 9). Slots of
/// versions 2 to 9 are read (with the
/// defaults of what they lack, and no hold in force from version 2), so a
/// configuration saved before survives the update; one of version 1 is
/// reported as [`SlotState::OldVersion`](crate::persist::SlotState::OldVersion)
/// and not used.
pub const LAYOUT_VERSION: u16 = if cfg!(feature = "linear") { 10 } else { 9 };

/// The first four bytes of a slot holding a [`Config`].
const MAGIC: [u8; 4] = *b"STCF";

/// Bytes one stored copy takes at the start of its slot: header, payload
/// and CRC-32 (12 + [`PAYLOAD_LEN`] + 4). The rest of the slot is never
/// written; [`ConfigStore`] keeps this many bytes in RAM for a save.
pub const RECORD_LEN: usize = record_len(PAYLOAD_LEN);

// The record fits in its slot (checked when compiling).
const _: () = assert!(RECORD_LEN <= SLOT_LEN);

impl Record for Config {
    const MAGIC: [u8; 4] = MAGIC;
    const VERSION: u16 = LAYOUT_VERSION;
    const PAYLOAD_LEN: usize = PAYLOAD_LEN;
    const PREVIOUS: &'static [(u16, usize)] = &[
        #[cfg(feature = "linear")]
        (9, PAYLOAD_LEN_V9),
        (8, PAYLOAD_LEN_V8),
        (7, PAYLOAD_LEN_V7),
        (6, PAYLOAD_LEN_V6),
        (5, PAYLOAD_LEN_V5),
        (4, PAYLOAD_LEN_V4),
        (3, PAYLOAD_LEN_V3),
        (2, PAYLOAD_LEN_V2),
    ];
    fn encode(&self, buf: &mut [u8]) -> Option<usize> {
        Config::encode(self, buf)
    }
    fn decode_from(payload: &mut dyn Payload, out: &mut Self) -> bool {
        Config::decode_from(payload, out)
    }
    fn is_valid(&self) -> bool {
        Config::is_valid(self)
    }
    fn defaults() -> Self {
        Config::default()
    }
    fn write_defaults(out: &mut Self) {
        super::table::write_defaults(out);
    }
}

impl<S: Storage> ConfigStore<S> {
    /// A store of the tracker's [`Config`] over `storage`; nothing is read
    /// until [`ConfigStore::load`] or a save.
    pub fn new(storage: S) -> Self {
        Self::for_record(storage)
    }
}
