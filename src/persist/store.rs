//! The two-slot CRC-32 store: any [`Record`] (the tracker's
//! [`Config`], the Arduino Uno's settings) kept in two slots of a
//! [`Storage`], saved in steps beside a main loop.
//!
//! # Slot layout (little-endian)
//! Each slot is [`Record::SLOT_LEN`] bytes (256, or 512 for a record
//! longer than 256: [`slot_len`]) at offset `slot × SLOT_LEN`:
//!
//! | bytes | field |
//! |---|---|
//! | 0..4 | magic ([`Record::MAGIC`]: `b"STCF"` for the [`Config`]) |
//! | 4..6 | layout version ([`Record::VERSION`]: [`LAYOUT_VERSION`] for the [`Config`]) |
//! | 6..8 | payload length `n` |
//! | 8..12 | sequence number (wrapping) |
//! | 12..12+n | payload ([`Record::encode`]: [`Config::encode`]) |
//! | 12+n..16+n | CRC-32 ([`crc32`]) of bytes 0..12+n |
//!
//! A save writes the slot that does *not* hold the newest good copy, with the
//! next sequence number; an interrupted write leaves at worst that slot
//! corrupt and the other one good. A load takes the good slot with the
//! newest sequence; a bad CRC, a wrong magic or version, a payload of the
//! wrong length or values out of range make a slot bad as a whole. With no
//! good slot the defaults are used. Nothing is ever applied in part.
//!
//! # Slots of 512 bytes
//! Before the configuration's layout 10 (whose record is 296 bytes) every
//! slot was 256 bytes: slot 1 began at byte 256. A store of 512-byte
//! slots also reads a record there ([`SHORT_SLOT_LEN`]) and takes it when
//! it is good and the newest, so that a configuration saved before the
//! update is not lost (nor an older copy in slot 0 taken for it). A save
//! then writes slot 1 (at byte 512), which leaves that copy intact until
//! a good one is there. On a NOR flash each slot has whole erase units of
//! its own, so the old slot 1 is the new one and the place at byte 256 of
//! slot 0 is erased.

use crate::config::codec::Writer;
// The store's defaults: `ConfigStore<S>` keeps the tracker's `Config`.
#[cfg(doc)]
use crate::config::LAYOUT_VERSION;
use crate::config::{Config, RECORD_LEN};
use crate::ports::Storage;

/// Bytes of a slot of a record of up to 256 bytes; where slot 1 began
/// in a store of longer records before their slots grew (module docs).
pub const SHORT_SLOT_LEN: usize = 256;

/// Bytes of a slot of a record of `record_len` bytes (header, payload and
/// CRC): [`SHORT_SLOT_LEN`], or 512 for a longer one.
pub const fn slot_len(record_len: usize) -> usize {
    if record_len > SHORT_SLOT_LEN {
        2 * SHORT_SLOT_LEN
    } else {
        SHORT_SLOT_LEN
    }
}

/// Bytes per slot of the tracker's [`Config`] (256; 512 with the
/// `linear` feature's keys): the slots a board's configuration storage
/// holds.
pub const SLOT_LEN: usize = slot_len(RECORD_LEN);

/// The index [`slot_offset`] takes for the old slot 1 at
/// [`SHORT_SLOT_LEN`] of a store of longer slots.
const LEGACY: usize = 2;
/// Header bytes before the payload.
const HEADER_LEN: usize = 12;
/// Bytes of the CRC-32 after the payload.
const CRC_LEN: usize = 4;

/// CRC-32 (IEEE 802.3: reflected, polynomial 0xEDB88320, initial and final
/// XOR 0xFFFFFFFF) of `data`: `crc32_update` with the inversions.
pub fn crc32(data: &[u8]) -> u32 {
    !crc32_update(!0, data)
}

/// The CRC-32 of [`crc32`] over pieces, bit by bit (small code, no
/// table): the register after `data`, without the initial and final
/// inversion, so that `!crc32_update(crc32_update(!0, a), b) == crc32(a ‖ b)`.
/// The one copy of the bit loop, for [`crc32`] and a slot's header, payload
/// and staging; not inlined. (The inversions inside it instead, as zlib's
/// `crc32(crc, buf)` has them, made it 174 B on AVR against 158 B, and the
/// Uno's `avr_tracker` 2 B larger.)
#[inline(never)]
fn crc32_update(mut crc: u32, data: &[u8]) -> u32 {
    for &b in data {
        crc ^= u32::from(b);
        for _ in 0..8 {
            let mask = (crc & 1).wrapping_neg();
            crc = (crc >> 1) ^ (0xEDB8_8320 & mask);
        }
    }
    crc
}

/// Why a slot was not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SlotState {
    /// Good, with its sequence number.
    Good(u32),
    /// Never written (magic missing).
    Empty,
    /// Written by another layout version.
    OldVersion(u16),
    /// CRC, length or a value is wrong.
    Corrupt,
    /// The storage could not be read.
    Unreadable,
}

/// What a [`ConfigStore`] keeps in its two slots: the tracker's
/// [`Config`], or a board's smaller record (the Arduino Uno's settings),
/// each with its own magic and layout version so that one is never read
/// as the other.
pub trait Record: Copy {
    /// The slot's first four bytes.
    const MAGIC: [u8; 4];
    /// The layout version written; a slot of another version is reported
    /// as [`SlotState::OldVersion`] and not used.
    const VERSION: u16;
    /// Payload bytes of this version.
    const PAYLOAD_LEN: usize;
    /// Earlier layout versions still read, each with its payload length:
    /// [`Record::decode_from`] takes a payload of those lengths too.
    const PREVIOUS: &'static [(u16, usize)] = &[];
    /// Bytes of each slot: [`slot_len`] of the record.
    const SLOT_LEN: usize = slot_len(record_len(Self::PAYLOAD_LEN));
    /// Serialises into `buf` (at least [`Record::PAYLOAD_LEN`] bytes);
    /// the length written, or `None` when `buf` is too small.
    fn encode(&self, buf: &mut [u8]) -> Option<usize>;
    /// Parses a payload read from `payload` into `out` and checks every
    /// value: true when it is good (then in `out`), false for a wrong
    /// length, a value out of range or a failed read (`out` then holds no
    /// record to use). In place and from where the payload lies: the
    /// store reads a slot into its caller's copy with no copy of the
    /// payload in RAM.
    fn decode_from(payload: &mut dyn Payload, out: &mut Self) -> bool;
    /// Every value inside its range.
    fn is_valid(&self) -> bool;
    /// The record used when no slot is good.
    fn defaults() -> Self;
    /// Writes [`Record::defaults`] over `out` (in place where the record
    /// can: a large one built and returned is a second copy on the
    /// stack).
    fn write_defaults(out: &mut Self) {
        *out = Self::defaults();
    }
}

/// A stored payload read in order, a few bytes at a time, from where it
/// lies: a slot of the storage while the store loads
/// ([`Record::decode_from`]), or a buffer ([`PayloadBytes`]).
pub trait Payload {
    /// The payload's length, bytes (its layout's).
    fn length(&self) -> usize;
    /// Fills `out` with the next bytes; false when fewer are left or they
    /// could not be read.
    fn read(&mut self, out: &mut [u8]) -> bool;
}

/// A payload in a buffer.
#[derive(Debug)]
pub struct PayloadBytes<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> PayloadBytes<'a> {
    /// The payload `bytes`, read from its start.
    pub fn new(bytes: &'a [u8]) -> Self {
        PayloadBytes { bytes, pos: 0 }
    }
}

impl Payload for PayloadBytes<'_> {
    fn length(&self) -> usize {
        self.bytes.len()
    }
    fn read(&mut self, out: &mut [u8]) -> bool {
        let end = self.pos.saturating_add(out.len());
        match self.bytes.get(self.pos..end) {
            Some(part) => {
                crate::bytes::copy_prefix(out, part);
                self.pos = end;
                true
            }
            None => false,
        }
    }
}

/// The payload of one slot, read from the storage into the CRC; a failed
/// read is kept for the load to report.
struct SlotPayload<'s, S: Storage> {
    storage: &'s mut S,
    /// Where the payload starts in the storage.
    base: usize,
    len: usize,
    pos: usize,
    /// The CRC-32 register over the header and the bytes read.
    crc: u32,
    error: Option<S::Error>,
}

impl<S: Storage> Payload for SlotPayload<'_, S> {
    fn length(&self) -> usize {
        self.len
    }
    fn read(&mut self, out: &mut [u8]) -> bool {
        let end = self.pos.saturating_add(out.len());
        if end > self.len {
            return false;
        }
        // Inside the slot (its CRC's place was checked): no overflow.
        match self.storage.read(self.base.saturating_add(self.pos), out) {
            Ok(()) => {
                self.pos = end;
                self.crc = crc32_update(self.crc, out);
                true
            }
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }
}

/// What [`ConfigStore::load_into`] found: whether a slot was good and
/// what each held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadReport {
    /// True when no slot was good: the configuration read is the defaults.
    pub defaults: bool,
    /// What each slot held.
    pub slots: [SlotState; 2],
}

/// The result of [`ConfigStore::load`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loaded<R = Config> {
    /// The configuration in force (defaults when no slot was good).
    pub config: R,
    /// True when `config` are the defaults because no slot was good.
    pub defaults: bool,
    /// What each slot held.
    pub slots: [SlotState; 2],
}

/// Errors of [`ConfigStore::save`] and [`ConfigStore::begin_save`], and
/// the failed end of a stepped save ([`SaveStatus::Done`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveError<E> {
    /// The configuration has a value out of range.
    Invalid,
    /// The storage is smaller than two slots.
    TooSmall,
    /// The storage failed.
    Storage(E),
}

/// Where a stepped save stands: the answer of [`ConfigStore::poll`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveStatus<E> {
    /// No save is staged.
    Idle,
    /// A save goes on: poll again (at the next pass of the loop).
    Busy,
    /// The save has just ended, with its result; reported once, then
    /// [`SaveStatus::Idle`]. On `Ok` the new copy is in the storage and is
    /// what [`ConfigStore::load`] returns; on `Err` the storage holds what it
    /// held before (the slot written was not the newest good one).
    Done(Result<(), SaveError<E>>),
}

/// Which slot holds the newest good copy, as far as the store knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Newest {
    /// Not read yet, or a slot could not be read.
    Unknown,
    /// Both slots were read and neither is good.
    NoGoodSlot,
    /// This slot, with this sequence number.
    Slot { slot: usize, seq: u32 },
}

/// The step a save is at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Preparing the slot (erasing it on NOR flash); `done` bytes are ready.
    Erase { done: usize },
    /// Writing the record; `pos` bytes are taken.
    Write { pos: usize },
    /// Waiting until the last bytes are in the storage.
    Flush,
}

/// A save under way: the staged record goes to `slot` with `seq`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Job {
    slot: usize,
    seq: u32,
    /// Bytes of the staged record.
    len: usize,
    phase: Phase,
}

/// The result of reading both slots (the newest good configuration goes
/// to the caller's place, see [`ConfigStore::scan`]).
struct Scan<E> {
    slots: [SlotState; 2],
    /// The newest good slot: its index and sequence number.
    best: Option<(usize, u32)>,
    /// The first read error, if a slot could not be read.
    error: Option<E>,
}

/// Two-slot configuration store over a [`Storage`], with a save that runs
/// in steps beside a main loop.
///
/// A save writes the slot that does not hold the newest good copy, with the
/// next sequence number (wrapping, compared RFC 1982 style); the other slot
/// is never touched, so a power cut at any point of a save leaves either
/// the old copy or the new one in force, never the defaults while a good
/// copy existed and never a mix (a part-written slot fails its CRC-32).
/// `tests/persist_powercut.rs` cuts the power at every byte, word and erase
/// of a save on fault-injecting EEPROM and NOR flash models to show it.
///
/// # In a main loop
///
/// ```
/// use suntracker::persist::{ConfigStore, MemStorage, SaveStatus, SLOT_LEN};
///
/// let mut store = ConfigStore::new(MemStorage::<{ 2 * SLOT_LEN }>::new());
/// let config = store.load().config; // at boot: reads only
/// store.begin_save(&config).unwrap(); // console `save`: stages, writes nothing
/// loop {
///     // ... step the motors, serve the console ...
///     match store.poll() {
///         SaveStatus::Busy => continue,           // at most one storage step per pass
///         SaveStatus::Done(result) => { result.unwrap(); break }
///         SaveStatus::Idle => break,
///     }
/// }
/// ```
///
/// Each [`ConfigStore::poll`] makes at most one call into the storage: one
/// [`Storage::erase_step`], [`Storage::write_step`] or
/// [`Storage::flush_step`], none of which waits (an AVR EEPROM byte is
/// started and left to the hardware; a NOR flash write step programs a few
/// words). What the hardware itself stalls is the storage's to document: a
/// sector erase of the STM32F411's flash stalls every flash read, and so
/// the CPU, for the whole erase ([`crate::persist`]).
///
/// RAM: the store keeps the staged record (`N` bytes: [`RECORD_LEN`] for
/// the [`Config`]) and a few words. A load ([`ConfigStore::load_into`])
/// needs no buffer: each slot is read once, into its CRC and (when its
/// layout is one this firmware reads) decoded straight from the storage
/// into the caller's record ([`Record::decode_from`]); the newest good
/// copy is read a second time when a slot read after it overwrote it.
///
/// The store keeps any [`Record`] `R` in records of `N` bytes (header,
/// payload, CRC-32: [`record_len`]); [`ConfigStore::new`] makes the
/// [`Config`]'s, [`ConfigStore::for_record`] another record's.
#[derive(Debug)]
pub struct ConfigStore<S, R = Config, const N: usize = RECORD_LEN> {
    storage: S,
    newest: Newest,
    job: Option<Job>,
    staged: [u8; N],
    record: core::marker::PhantomData<R>,
}

/// Bytes one stored copy of a record with `payload_len` bytes of payload
/// takes: header, payload and CRC-32 (the `N` of a [`ConfigStore`]).
pub const fn record_len(payload_len: usize) -> usize {
    HEADER_LEN + payload_len + CRC_LEN
}

fn seq_newer(a: u32, b: u32) -> bool {
    // Serial-number arithmetic (RFC 1982 style): a is newer than b.
    a != b && a.wrapping_sub(b) < 0x8000_0000
}

/// Offset of byte `at` of slot `slot` (0, 1, or [`LEGACY`] when slots
/// are longer than [`SHORT_SLOT_LEN`]) of slots of `len` bytes, checked.
fn slot_offset(len: usize, slot: usize, at: usize) -> Option<usize> {
    if len > SHORT_SLOT_LEN && slot == LEGACY {
        SHORT_SLOT_LEN.checked_add(at)
    } else {
        slot.checked_mul(len)?.checked_add(at)
    }
}

impl<S: Storage, R: Record, const N: usize> ConfigStore<S, R, N> {
    /// `N` holds a record of `R` and a slot holds `N` (checked when
    /// compiling each store type).
    const FITS: () = assert!(N == record_len(R::PAYLOAD_LEN) && N <= R::SLOT_LEN);

    /// The slots a load reads: 0 and 1, and [`LEGACY`] in a store of
    /// slots longer than [`SHORT_SLOT_LEN`].
    const SLOTS_READ: usize = if R::SLOT_LEN > SHORT_SLOT_LEN {
        LEGACY + 1
    } else {
        2
    };

    /// A store of record `R` over `storage`; nothing is read until
    /// [`ConfigStore::load`] or a save.
    pub fn for_record(storage: S) -> Self {
        let () = Self::FITS;
        ConfigStore {
            storage,
            newest: Newest::Unknown,
            job: None,
            staged: [0; N],
            record: core::marker::PhantomData,
        }
    }

    /// Gives the storage back; a save under way is abandoned (the storage
    /// then holds the old copy, and the slot being written is not good).
    pub fn release(self) -> S {
        self.storage
    }

    /// The storage, to look at (a board's status, tests).
    pub fn storage(&self) -> &S {
        &self.storage
    }

    /// True while a save is staged and not yet done.
    pub fn is_saving(&self) -> bool {
        self.job.is_some()
    }

    /// Reads and checks slot `slot`: its state, and when its layout is one
    /// this firmware reads, its record decoded into `out` as its bytes go
    /// into the CRC (good only when the CRC is good too; written either
    /// way: the caller reads its best slot again when a later one
    /// overwrote it); `Err` when the storage could not be read.
    // The slot state alone is returned: a returned `(SlotState,
    // Option<Config>)` made the compiler keep a 149-byte constant of it in
    // an AVR's RAM. Decoded from the storage, into the caller's copy: a
    // payload buffer and a copy of the record here were 580 B of the
    // ATmega2560's deepest stack (a console `load`).
    // Not inlined: one copy for every slot.
    #[inline(never)]
    fn read_slot(&mut self, slot: usize, out: &mut R) -> Result<SlotState, S::Error> {
        const CORRUPT: SlotState = SlotState::Corrupt;
        let Some(base) = slot_offset(R::SLOT_LEN, slot, 0) else {
            return Ok(CORRUPT);
        };
        let mut header = [0u8; HEADER_LEN];
        self.storage.read(base, &mut header)?;
        let [m0, m1, m2, m3, v0, v1, l0, l1, s0, s1, s2, s3] = header;
        if [m0, m1, m2, m3] != R::MAGIC {
            return Ok(SlotState::Empty);
        }
        let version = u16::from_le_bytes([v0, v1]);
        let len = usize::from(u16::from_le_bytes([l0, l1]));
        let seq = u32::from_le_bytes([s0, s1, s2, s3]);
        // The CRC must lie inside the slot.
        let crc_at = match HEADER_LEN.checked_add(len) {
            Some(at)
                if at.checked_add(CRC_LEN).is_some_and(|end| {
                    end <= if R::SLOT_LEN > SHORT_SLOT_LEN && slot == LEGACY {
                        SHORT_SLOT_LEN
                    } else {
                        R::SLOT_LEN
                    }
                }) =>
            {
                at
            }
            _ => return Ok(CORRUPT),
        };
        // The slot's bytes lie at `base` on (`slot_offset`): the payload
        // and the CRC after it, inside the slot (checked above).
        let (Some(payload_at), Some(stored_at)) =
            (base.checked_add(HEADER_LEN), base.checked_add(crc_at))
        else {
            return Ok(CORRUPT);
        };
        // The payload read once, into the CRC as it goes: decoded into
        // `out` when it has a layout's version and length this firmware
        // reads, the rest (all of another one's) read in small pieces.
        // The record decoded counts only when the CRC is good too.
        let current = (version == R::VERSION && len == R::PAYLOAD_LEN)
            || R::PREVIOUS.contains(&(version, len));
        let mut payload = SlotPayload {
            storage: &mut self.storage,
            base: payload_at,
            len,
            pos: 0,
            crc: crc32_update(!0, &header),
            error: None,
        };
        let decoded = current && R::decode_from(&mut payload, out);
        let mut chunk = [0u8; 16];
        while let Some(part) = chunk.get_mut(..(len - payload.pos).min(16)) {
            if part.is_empty() || !payload.read(part) {
                break;
            }
        }
        let (read, crc) = (payload.pos, payload.crc);
        if let Some(e) = payload.error {
            return Err(e);
        }
        let mut stored = [0u8; CRC_LEN];
        self.storage.read(stored_at, &mut stored)?;
        if read != len || !crc != u32::from_le_bytes(stored) {
            return Ok(CORRUPT);
        }
        if version != R::VERSION && !R::PREVIOUS.iter().any(|&(v, _)| v == version) {
            return Ok(SlotState::OldVersion(version));
        }
        Ok(if decoded {
            SlotState::Good(seq)
        } else {
            CORRUPT
        })
    }

    /// Reads both slots; remembers which holds the newest good copy, and
    /// leaves its record in `best_config` (anything when no slot is good:
    /// each slot is decoded into it).
    // The configuration goes to the caller's place, not into the returned
    // scan: a scan holding it was built in this frame and copied out
    // whole, and the frame's small slots lay beyond `ldd`/`std` reach on
    // the AVR.
    fn scan(&mut self, best_config: &mut R) -> Scan<S::Error> {
        let mut scan = Scan {
            slots: [SlotState::Unreadable; 2],
            best: None,
            error: None,
        };
        // Slot 0, slot 1, and in a store of longer slots the old slot 1
        // (module docs), not reported.
        for slot in 0..Self::SLOTS_READ {
            let state = match self.read_slot(slot, best_config) {
                Ok(state) => {
                    if let SlotState::Good(seq) = state {
                        if scan.best.is_none_or(|(_, best)| seq_newer(seq, best)) {
                            scan.best = Some((slot, seq));
                        }
                    }
                    state
                }
                Err(e) => {
                    if scan.error.is_none() {
                        scan.error = Some(e);
                    }
                    SlotState::Unreadable
                }
            };
            if let Some(s) = scan.slots.get_mut(slot) {
                *s = state;
            }
        }
        // The newest good copy read again when a slot read after it
        // overwrote its record. It reads the same unless the storage fails
        // or changed: then no copy is taken and the newest is not known
        // (the next save reads the slots again rather than guess one).
        let mut unsure = false;
        if let Some((slot, seq)) = scan.best {
            if slot + 1 != Self::SLOTS_READ {
                let again = self.read_slot(slot, best_config);
                if !matches!(again, Ok(SlotState::Good(s)) if s == seq) {
                    scan.best = None;
                    unsure = true;
                    if scan.error.is_none() {
                        scan.error = again.err();
                    }
                }
            }
        }
        self.newest = match (&scan.best, &scan.error) {
            (Some((slot, seq)), _) => Newest::Slot {
                slot: *slot,
                seq: *seq,
            },
            (None, Some(_)) => Newest::Unknown,
            (None, None) if unsure => Newest::Unknown,
            (None, None) => Newest::NoGoodSlot,
        };
        scan
    }

    /// Reads both slots and returns the newest good configuration, or the
    /// defaults when neither is good. Only reads (each slot once, and the
    /// newest good copy again when a slot read after it overwrote it); a
    /// save under way goes on.
    pub fn load(&mut self) -> Loaded<R> {
        let mut config = R::defaults();
        let report = self.load_into(&mut config);
        Loaded {
            config,
            defaults: report.defaults,
            slots: report.slots,
        }
    }

    /// [`ConfigStore::load`] into the caller's `config`: the newest good
    /// copy, or the defaults when neither slot is good. No configuration
    /// is returned: on an 8-bit board each one is a few percent of the
    /// RAM, and the console's `load` runs on top of the loop's stack.
    pub fn load_into(&mut self, config: &mut R) -> LoadReport {
        let scan = self.scan(config);
        let defaults = scan.best.is_none();
        if defaults {
            R::write_defaults(config);
        }
        LoadReport {
            defaults,
            slots: scan.slots,
        }
    }

    /// The slot and sequence number the next save writes: the slot not
    /// holding the newest good copy. Reads the slots when that is not known;
    /// refuses to write when a slot cannot be read (it might be the only
    /// good copy).
    fn target(&mut self) -> Result<(usize, u32), SaveError<S::Error>> {
        if self.newest == Newest::Unknown {
            if let Some(e) = self.rescan() {
                return Err(SaveError::Storage(e));
            }
        }
        Ok(match self.newest {
            // Not the newest's slot; after a copy at the old slot 1's
            // place, slot 1 (which leaves it intact).
            Newest::Slot { slot, seq } => (usize::from(slot != 1), seq.wrapping_add(1)),
            Newest::NoGoodSlot | Newest::Unknown => (0, 1),
        })
    }

    /// Reads the slots to learn which holds the newest good copy (before
    /// a save); the first read error, if any. Not inlined on the AVR: the
    /// record the slots are decoded into is on the stack only here.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn rescan(&mut self) -> Option<S::Error> {
        let mut scratch = R::defaults();
        self.scan(&mut scratch).error
    }

    /// Encodes `cfg` with sequence `seq` into the staged record; its
    /// length, or `None` when it does not fit. Out of line on the AVR:
    /// apart from the save's checks its temporaries leave their frame.
    #[cfg_attr(target_arch = "avr", inline(never))]
    fn stage(&mut self, cfg: &R, seq: u32) -> Option<usize> {
        let buf: &mut [u8] = &mut self.staged;
        let n = cfg.encode(buf.get_mut(HEADER_LEN..)?)?;
        let crc_at = HEADER_LEN.checked_add(n)?;
        let mut w = Writer {
            buf: &mut *buf,
            pos: 0,
            overflow: false,
        };
        w.bytes(&R::MAGIC);
        w.word(u32::from(R::VERSION), 2);
        w.word(u32::from(u16::try_from(n).ok()?), 2);
        w.word(seq, 4);
        if w.overflow {
            return None;
        }
        let crc = !crc32_update(!0, buf.get(..crc_at)?);
        let mut w = Writer {
            buf,
            pos: crc_at,
            overflow: false,
        };
        w.word(crc, 4);
        if w.overflow {
            return None;
        }
        crc_at.checked_add(CRC_LEN)
    }

    /// Starts saving `cfg`: checks it, picks the slot (reading the slots
    /// first if the store has not), encodes the record into RAM. Writes
    /// nothing: [`ConfigStore::poll`] does, step by step. A save already
    /// under way is replaced by this one (its slot is written again from
    /// the start). A refused request (an error) leaves a save under way
    /// going on.
    pub fn begin_save(&mut self, cfg: &R) -> Result<(), SaveError<S::Error>> {
        if !cfg.is_valid() {
            return Err(SaveError::Invalid);
        }
        if self.storage.capacity() < 2 * R::SLOT_LEN {
            return Err(SaveError::TooSmall);
        }
        let (slot, seq) = self.target()?;
        // The staged record is overwritten now: drop the old job first (an
        // encoding failure, which the fixed layout rules out, leaves none).
        self.job = None;
        let len = self.stage(cfg, seq).ok_or(SaveError::TooSmall)?;
        self.job = Some(Job {
            slot,
            seq,
            len,
            phase: Phase::Erase { done: 0 },
        });
        Ok(())
    }

    /// Advances a staged save by one storage step, without waiting:
    /// [`SaveStatus::Busy`] while it goes on, [`SaveStatus::Done`] once at
    /// its end, [`SaveStatus::Idle`] when no save is staged.
    pub fn poll(&mut self) -> SaveStatus<S::Error> {
        let Some(job) = self.job else {
            return SaveStatus::Idle;
        };
        match self.step(job) {
            Ok(Some(phase)) => {
                self.job = Some(Job { phase, ..job });
                SaveStatus::Busy
            }
            Ok(None) => {
                self.job = None;
                self.newest = Newest::Slot {
                    slot: job.slot,
                    seq: job.seq,
                };
                SaveStatus::Done(Ok(()))
            }
            Err(e) => {
                self.job = None;
                SaveStatus::Done(Err(e))
            }
        }
    }

    /// One storage step of `job`: the next phase, or `None` when done.
    fn step(&mut self, job: Job) -> Result<Option<Phase>, SaveError<S::Error>> {
        let offset = |at: usize| slot_offset(R::SLOT_LEN, job.slot, at).ok_or(SaveError::TooSmall);
        match job.phase {
            Phase::Erase { done } => {
                let left = R::SLOT_LEN.saturating_sub(done);
                let n = self
                    .storage
                    .erase_step(offset(done)?, left)
                    .map_err(SaveError::Storage)?;
                let done = done.saturating_add(n.min(left));
                Ok(Some(if done >= R::SLOT_LEN {
                    Phase::Write { pos: 0 }
                } else {
                    Phase::Erase { done }
                }))
            }
            Phase::Write { pos } => {
                let data = self.staged.get(pos..job.len).ok_or(SaveError::TooSmall)?;
                let n = self
                    .storage
                    .write_step(offset(pos)?, data)
                    .map_err(SaveError::Storage)?;
                let pos = pos.saturating_add(n.min(data.len()));
                Ok(Some(if pos >= job.len {
                    Phase::Flush
                } else {
                    Phase::Write { pos }
                }))
            }
            Phase::Flush => {
                if self.storage.flush_step().map_err(SaveError::Storage)? {
                    Ok(None)
                } else {
                    Ok(Some(Phase::Flush))
                }
            }
        }
    }

    /// Writes `cfg` into the slot not holding the newest good copy and
    /// returns when it is done: [`ConfigStore::begin_save`], then
    /// [`ConfigStore::poll`] until done (a storage that stays busy keeps it
    /// waiting). For hosts and tests; a firmware loop polls instead.
    pub fn save(&mut self, cfg: &R) -> Result<(), SaveError<S::Error>> {
        self.begin_save(cfg)?;
        loop {
            match self.poll() {
                SaveStatus::Busy => {}
                SaveStatus::Done(result) => return result,
                // Not reached: `begin_save` staged a job, and only `Done`
                // ends it.
                SaveStatus::Idle => return Ok(()),
            }
        }
    }
}
