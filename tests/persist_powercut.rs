//! Power cuts during a configuration save, on fault-injecting models of the
//! two storages the boards use, through the same code the boards run
//! (`ConfigStore`'s stepped save, `storage::EepromStorage`,
//! `storage::NorFlashStorage`):
//!
//! - a byte EEPROM (the AVR's): one byte write at a time, each busy for a
//!   few polls; a cut leaves the byte being written old, new or garbage and
//!   nothing after it written;
//! - a NOR flash (program in 4-byte words, erase in 2 KiB sectors; the
//!   slots in sectors 1 and 2 as on the STM32F411): a cut program leaves
//!   the word erased, new, part-programmed or garbage; a cut erase leaves
//!   the sector with an erased prefix (every word boundary of the slot),
//!   with bits part-erased, or garbage.
//!
//! From empty storage, one good slot and two good slots, the power is cut
//! at every byte write, every word and every erase variant of a save; then
//! the storage is powered up again and loaded: the result is exactly the
//! old or the new configuration, never the defaults while a good copy
//! existed. The number of cut points is computed from the record this test
//! builds itself (layout of `src/persist/store.rs`: magic, version, length,
//! sequence, payload, CRC-32 by `crc32`, whose check value
//! `tests/config_store.rs` verifies) and the storage's contents.
//!
//! The EEPROM helpers are generic over the record kept ([`Record`]): the
//! same three EEPROM sweeps run on the Arduino Uno's settings
//! (`servo_tracker::settings::Settings`, magic "STUN", version 1,
//! latitude, longitude and two gear ratios as `f32` little-endian), whose
//! record this test also builds from that module's documentation.

use std::fmt::Debug;

use embedded_storage::nor_flash::{
    check_erase, check_read, check_write, ErrorType, NorFlash, NorFlashErrorKind, ReadNorFlash,
};
use suntracker::config::{Config, LAYOUT_VERSION, RECORD_LEN};
use suntracker::persist::{
    crc32, ConfigStore, EepromCells, EepromError, EepromStorage, Loaded, NorError, NorFlashStorage,
    Record, SaveError, SaveStatus, SlotState, SLOT_LEN,
};
use suntracker::ports::Storage;
use suntracker::servo_tracker::settings::{self as settings, Settings};

// ---------------------------------------------------------------------------
// Configurations and the record, built here independently of the store.

fn config_a() -> Config {
    let mut c = Config::default();
    c.site.latitude_deg = 69.65;
    c.site.longitude_deg = 18.96;
    c.site.elevation_m = 10.0;
    c.calibration.declination_deg = 9.5;
    c
}

fn config_b() -> Config {
    let mut c = config_a();
    c.safety.max_retries = 7;
    c.wind.threshold_hz = 31.5;
    c
}

fn config_new() -> Config {
    let mut c = Config::default();
    c.site.latitude_deg = -33.87;
    c.site.longitude_deg = 151.21;
    c.axes[1].backlash_deg = 0.35;
    c.schedule.table_step_s = 120;
    c
}

/// Settings of a board never set: Kano (the module's defaults).
fn settings_a() -> Settings {
    settings::DEFAULTS
}

/// Sydney, Chowdhury et al.'s (2019) direct drives.
fn settings_b() -> Settings {
    Settings {
        lat_deg: -33.8688,
        lon_deg: 151.2093,
        ..settings::DEFAULTS
    }
}

/// Sydney with gears 2 (C) and 3 (A).
fn settings_new() -> Settings {
    Settings {
        gear_ratio: [2.0, 3.0],
        ..settings_b()
    }
}

/// A record kept by the store, with its stored layout as documented: what
/// [`record`] builds without the store.
trait Documented: Record + PartialEq + Debug {
    /// The slot's first four bytes.
    const DOC_MAGIC: [u8; 4];
    /// The layout version.
    const DOC_VERSION: u16;
    /// The payload.
    fn payload(&self) -> Vec<u8>;
}

impl Documented for Config {
    const DOC_MAGIC: [u8; 4] = *b"STCF";
    const DOC_VERSION: u16 = LAYOUT_VERSION;
    fn payload(&self) -> Vec<u8> {
        let mut payload = [0u8; 512];
        let n = self.encode(&mut payload).expect("payload fits");
        payload[..n].to_vec()
    }
}

/// Module docs of `src/servo_tracker/settings.rs`: magic "STUN",
/// version 1, latitude, longitude, gear C, gear A as `f32` little-endian.
impl Documented for Settings {
    const DOC_MAGIC: [u8; 4] = *b"STUN";
    const DOC_VERSION: u16 = 1;
    fn payload(&self) -> Vec<u8> {
        [
            self.lat_deg,
            self.lon_deg,
            self.gear_ratio[0],
            self.gear_ratio[1],
        ]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
    }
}

/// The stored record of `rec` with sequence `seq`: magic ("STCF" for the
/// configuration), layout version, payload length, sequence
/// (little-endian), payload, CRC-32 of all before it.
fn record<R: Documented>(rec: &R, seq: u32) -> Vec<u8> {
    let payload = rec.payload();
    let mut r = Vec::new();
    r.extend_from_slice(&R::DOC_MAGIC);
    r.extend_from_slice(&R::DOC_VERSION.to_le_bytes());
    r.extend_from_slice(
        &u16::try_from(payload.len())
            .expect("short payload")
            .to_le_bytes(),
    );
    r.extend_from_slice(&seq.to_le_bytes());
    r.extend_from_slice(&payload);
    let crc = crc32(&r);
    r.extend_from_slice(&crc.to_le_bytes());
    r
}

/// What a load after a cut may return.
fn check_after_cut<R: Record + PartialEq + Debug>(
    l: &Loaded<R>,
    old: Option<&R>,
    new: &R,
    what: &str,
) {
    match old {
        Some(old) => {
            assert!(!l.defaults, "{what}: defaults while a good copy existed");
            assert!(
                l.config == *old || l.config == *new,
                "{what}: neither the old nor the new configuration: {:?}",
                l.config
            );
        }
        None => assert!(
            (l.defaults && l.config == R::defaults()) || (!l.defaults && l.config == *new),
            "{what}: from empty storage only the defaults or the new configuration: {:?}",
            l.config
        ),
    }
}

/// A small deterministic generator (xorshift64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn byte(&mut self) -> u8 {
        (self.next() >> 24) as u8
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A value other than `a` and `b`: what a cut write can leave.
fn garbage(a: u8, b: u8) -> u8 {
    [!b, a ^ 0x5A, 0xA5, 0x3C]
        .into_iter()
        .find(|g| *g != a && *g != b)
        .expect("four candidates, two excluded")
}

// ---------------------------------------------------------------------------
// The EEPROM model.

/// ATmega328P size.
const EEPROM_LEN: usize = 1024;
/// Polls of the busy flag a byte write lasts.
const WRITE_POLLS: u32 = 3;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ByteCut {
    Old,
    New,
    Garbage,
}

const BYTE_CUTS: [ByteCut; 3] = [ByteCut::Old, ByteCut::New, ByteCut::Garbage];

struct CutEeprom {
    bytes: Vec<u8>,
    /// Polls of `busy` left before the running write ends.
    busy_for: u32,
    /// Byte writes started.
    writes: usize,
    /// The power fails during byte write number `.0`, leaving it `.1`.
    cut: Option<(usize, ByteCut)>,
    dead: bool,
    /// A worn cell: address and the bits stuck at one.
    worn: Option<(u16, u8)>,
}

impl CutEeprom {
    fn new(bytes: Vec<u8>, cut: Option<(usize, ByteCut)>) -> Self {
        CutEeprom {
            bytes,
            busy_for: 0,
            writes: 0,
            cut,
            dead: false,
            worn: None,
        }
    }
}

impl EepromCells for CutEeprom {
    fn size_bytes(&self) -> usize {
        self.bytes.len()
    }
    fn busy(&mut self) -> bool {
        if self.dead {
            return true;
        }
        if self.busy_for > 0 {
            self.busy_for -= 1;
            true
        } else {
            false
        }
    }
    fn read_byte(&mut self, address: u16) -> u8 {
        assert_eq!(self.busy_for, 0, "EEPROM read while a write runs");
        self.bytes[usize::from(address)]
    }
    fn start_write(&mut self, address: u16, value: u8) {
        assert_eq!(self.busy_for, 0, "EEPROM write started while one runs");
        assert!(!self.dead, "EEPROM written after the power cut");
        let k = self.writes;
        self.writes += 1;
        let a = usize::from(address);
        let old = self.bytes[a];
        if let Some((at, how)) = self.cut {
            if at == k {
                self.bytes[a] = match how {
                    ByteCut::Old => old,
                    ByteCut::New => value,
                    ByteCut::Garbage => garbage(old, value),
                };
                self.dead = true;
                return;
            }
        }
        self.bytes[a] = match self.worn {
            Some((w, ones)) if w == address => value | ones,
            _ => value,
        };
        self.busy_for = WRITE_POLLS;
    }
}

/// A store of record `R` (`N` bytes a copy) on the EEPROM model.
type EepromStore<R, const N: usize> = ConfigStore<EepromStorage<CutEeprom>, R, N>;

fn eeprom_store<R: Record + PartialEq + Debug, const N: usize>(
    bytes: &[u8],
    cut: Option<(usize, ByteCut)>,
) -> EepromStore<R, N> {
    ConfigStore::<_, R, N>::for_record(EepromStorage::new(CutEeprom::new(bytes.to_vec(), cut)))
}

/// Power-up and load, on an intact EEPROM holding `bytes`.
fn eeprom_load<R: Record + PartialEq + Debug, const N: usize>(bytes: &[u8]) -> Loaded<R> {
    eeprom_store::<R, N>(bytes, None).load()
}

/// How a save ended: the cut fired, or it finished with a result.
#[derive(Debug, PartialEq)]
enum End<E> {
    Cut,
    Done(Result<(), SaveError<E>>),
}

/// Boots on `bytes` (load), saves `new` polling as a firmware loop does,
/// with a power cut during byte write `cut`: the bytes left and how it
/// ended. Checks that no poll starts more than one byte write.
fn eeprom_save<R: Record + PartialEq + Debug, const N: usize>(
    bytes: &[u8],
    new: &R,
    cut: Option<(usize, ByteCut)>,
) -> (Vec<u8>, End<EepromError>) {
    let mut store = eeprom_store::<R, N>(bytes, cut);
    store.load();
    store.begin_save(new).expect("save staged");
    let mut polls = 0u32;
    let end = loop {
        let before = store.storage().cells().writes;
        let status = store.poll();
        let after = store.storage().cells().writes;
        assert!(
            after - before <= 1,
            "a poll started {} byte writes",
            after - before
        );
        if store.storage().cells().dead {
            break End::Cut;
        }
        match status {
            SaveStatus::Busy => {}
            SaveStatus::Done(r) => break End::Done(r),
            SaveStatus::Idle => panic!("idle during a save"),
        }
        polls += 1;
        assert!(polls < 100_000, "the save does not end");
    };
    (store.release().release().bytes, end)
}

/// An EEPROM image after saving `configs` one after the other (uncut).
fn eeprom_image<R: Record + PartialEq + Debug, const N: usize>(configs: &[R]) -> Vec<u8> {
    let mut bytes = vec![0xFF; EEPROM_LEN];
    for c in configs {
        let (b, end) = eeprom_save::<R, N>(&bytes, c, None);
        assert_eq!(end, End::Done(Ok(())));
        bytes = b;
    }
    bytes
}

/// Cuts the power at every byte write of a save of `new` onto `image`,
/// each leaving the byte old, new or garbage; `old` is the configuration
/// in force before, `slot`/`seq` where the save goes. Returns the cut
/// points tried.
fn eeprom_sweep<R: Documented, const N: usize>(
    image: &[u8],
    old: Option<&R>,
    new: &R,
    slot: usize,
    seq: u32,
) -> usize {
    let new = *new;
    let rec = record(&new, seq);
    assert_eq!(rec.len(), N, "the record as documented is N bytes");
    let base = slot * R::SLOT_LEN;
    let other = (1 - slot) * R::SLOT_LEN;
    // Bytes that differ between the record and what the slot holds: the
    // writes a save makes (equal bytes are skipped).
    let writes = rec
        .iter()
        .zip(&image[base..base + rec.len()])
        .filter(|(r, i)| r != i)
        .count();
    assert!(writes > 0);

    // Uncut: exactly those writes, the slot holds the record, the other
    // slot is untouched, and a load gives the new configuration.
    let mut store = eeprom_store::<R, N>(image, None);
    store.load();
    store.save(&new).expect("uncut save");
    assert_eq!(store.storage().cells().writes, writes);
    let after = store.release().release().bytes;
    assert_eq!(&after[base..base + rec.len()], &rec[..]);
    assert_eq!(
        &after[other..other + R::SLOT_LEN],
        &image[other..other + R::SLOT_LEN]
    );
    assert_eq!(eeprom_load::<R, N>(&after).config, new);

    let mut tried = 0;
    let (mut saw_old, mut saw_new) = (false, false);
    for k in 0..writes {
        for how in BYTE_CUTS {
            let what = format!("slot {slot}, write {k} of {writes}, {how:?}");
            let (left, end) = eeprom_save::<R, N>(image, &new, Some((k, how)));
            assert_eq!(end, End::Cut, "{what}");
            assert_eq!(
                &left[other..other + R::SLOT_LEN],
                &image[other..other + R::SLOT_LEN],
                "{what}: the other slot changed"
            );
            let l = eeprom_load::<R, N>(&left);
            check_after_cut(&l, old, &new, &what);
            if k + 1 == writes && how == ByteCut::New {
                assert_eq!(l.config, new, "{what}: the record is complete");
            }
            saw_new |= !l.defaults && l.config == new;
            saw_old |= l.config != new;
            tried += 1;
        }
    }
    assert!(saw_old && saw_new, "both outcomes occur");
    assert_eq!(tried, BYTE_CUTS.len() * writes);
    tried
}

#[test]
fn eeprom_cut_at_every_byte_from_empty() {
    let image = vec![0xFF; EEPROM_LEN];
    let rec = record(&config_new(), 1);
    let tried = eeprom_sweep::<Config, RECORD_LEN>(&image, None, &config_new(), 0, 1);
    // Erased bytes (0xFF) of the record are skipped.
    let expected = 3 * rec.iter().filter(|b| **b != 0xFF).count();
    assert_eq!(tried, expected);
    println!("EEPROM, empty storage: {tried} cut points");
}

#[test]
fn eeprom_cut_at_every_byte_with_one_good_slot() {
    let image = eeprom_image::<Config, RECORD_LEN>(&[config_a()]);
    assert_eq!(
        eeprom_load::<Config, RECORD_LEN>(&image).slots,
        [SlotState::Good(1), SlotState::Empty]
    );
    let tried = eeprom_sweep::<Config, RECORD_LEN>(&image, Some(&config_a()), &config_new(), 1, 2);
    let rec = record(&config_new(), 2);
    assert_eq!(tried, 3 * rec.iter().filter(|b| **b != 0xFF).count());
    println!("EEPROM, one good slot: {tried} cut points");
}

#[test]
fn eeprom_cut_at_every_byte_with_two_good_slots() {
    let image = eeprom_image::<Config, RECORD_LEN>(&[config_a(), config_b()]);
    assert_eq!(
        eeprom_load::<Config, RECORD_LEN>(&image).slots,
        [SlotState::Good(1), SlotState::Good(2)]
    );
    // Slot 0 (sequence 1, config A) is overwritten with sequence 3; only
    // B or the new configuration may come back, never A.
    let tried = eeprom_sweep::<Config, RECORD_LEN>(&image, Some(&config_b()), &config_new(), 0, 3);
    let rec = record(&config_new(), 3);
    let differing = rec
        .iter()
        .zip(&image[..rec.len()])
        .filter(|(r, i)| r != i)
        .count();
    assert_eq!(tried, 3 * differing);
    // The header's magic, version and length are equal: skipped.
    assert!(differing <= rec.len() - 8);
    println!("EEPROM, two good slots: {tried} cut points");
}

// ---------------------------------------------------------------------------
// The Arduino Uno's settings (`servo_tracker::settings`), same sweeps.

/// Bytes of one stored copy of the settings.
const SETTINGS_LEN: usize = settings::RECORD_LEN;

#[test]
fn settings_record_is_as_documented() {
    // Header 12, payload four f32s, CRC-32 4.
    assert_eq!(record(&settings_new(), 1).len(), 12 + 16 + 4);
    assert_eq!(SETTINGS_LEN, 12 + 16 + 4);
    assert_eq!(settings::EEPROM_LEN, EEPROM_LEN);
    // The store writes exactly the record built here.
    let image = eeprom_image::<Settings, SETTINGS_LEN>(&[settings_b()]);
    let rec = record(&settings_b(), 1);
    assert_eq!(&image[..rec.len()], &rec[..]);
    assert!(image[rec.len()..].iter().all(|b| *b == 0xFF));
    // The settings are distinct and valid.
    let all = [settings_a(), settings_b(), settings_new()];
    for (i, s) in all.iter().enumerate() {
        assert_eq!(s.validate(), Ok(()), "{s:?}");
        assert!(all[..i].iter().all(|t| t != s), "{s:?} twice");
    }
}

#[test]
fn settings_eeprom_cut_at_every_byte_from_empty() {
    let image = vec![0xFF; EEPROM_LEN];
    let rec = record(&settings_new(), 1);
    let tried = eeprom_sweep::<Settings, SETTINGS_LEN>(&image, None, &settings_new(), 0, 1);
    assert_eq!(tried, 3 * rec.iter().filter(|b| **b != 0xFF).count());
    println!("EEPROM settings, empty storage: {tried} cut points");
}

#[test]
fn settings_eeprom_cut_at_every_byte_with_one_good_slot() {
    let image = eeprom_image::<Settings, SETTINGS_LEN>(&[settings_a()]);
    assert_eq!(
        eeprom_load::<Settings, SETTINGS_LEN>(&image).slots,
        [SlotState::Good(1), SlotState::Empty]
    );
    let tried =
        eeprom_sweep::<Settings, SETTINGS_LEN>(&image, Some(&settings_a()), &settings_new(), 1, 2);
    let rec = record(&settings_new(), 2);
    assert_eq!(tried, 3 * rec.iter().filter(|b| **b != 0xFF).count());
    println!("EEPROM settings, one good slot: {tried} cut points");
}

#[test]
fn settings_eeprom_cut_at_every_byte_with_two_good_slots() {
    let image = eeprom_image::<Settings, SETTINGS_LEN>(&[settings_a(), settings_b()]);
    let l = eeprom_load::<Settings, SETTINGS_LEN>(&image);
    assert_eq!(l.slots, [SlotState::Good(1), SlotState::Good(2)]);
    assert_eq!(l.config, settings_b());
    // Slot 0 (sequence 1, Kano) is overwritten with sequence 3; only
    // Sydney or the new gears may come back, never Kano.
    let tried =
        eeprom_sweep::<Settings, SETTINGS_LEN>(&image, Some(&settings_b()), &settings_new(), 0, 3);
    let rec = record(&settings_new(), 3);
    let differing = rec
        .iter()
        .zip(&image[..rec.len()])
        .filter(|(r, i)| r != i)
        .count();
    assert_eq!(tried, 3 * differing);
    // The header's magic, version and length are equal: skipped.
    assert!(differing <= rec.len() - 8);
    println!("EEPROM settings, two good slots: {tried} cut points");
}

#[test]
fn eeprom_repeated_cut_saves_then_a_whole_one() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut bytes = eeprom_image::<Config, RECORD_LEN>(&[config_a()]);
    let mut good = config_a();
    for i in 0..12u32 {
        let mut next = config_new();
        next.wind.release_s = 100 + i;
        // Cut somewhere in the first writes of this save (its writes are at
        // most the record's length).
        let k = rng.below(RECORD_LEN);
        let how = BYTE_CUTS[rng.below(3)];
        let (left, end) = eeprom_save::<Config, RECORD_LEN>(&bytes, &next, Some((k, how)));
        let l = eeprom_load::<Config, RECORD_LEN>(&left);
        check_after_cut(&l, Some(&good), &next, &format!("attempt {i}"));
        if end != End::Cut {
            // The save had fewer writes than k: it completed.
            assert_eq!(end, End::Done(Ok(())));
            assert_eq!(l.config, next);
        }
        good = l.config;
        bytes = left;
    }
    let last = config_b();
    let (after, end) = eeprom_save::<Config, RECORD_LEN>(&bytes, &last, None);
    assert_eq!(end, End::Done(Ok(())));
    assert_eq!(eeprom_load::<Config, RECORD_LEN>(&after).config, last);
}

#[test]
fn eeprom_load_during_a_save_gives_the_old_copy() {
    let image = eeprom_image::<Config, RECORD_LEN>(&[config_a()]);
    let mut store = eeprom_store::<Config, RECORD_LEN>(&image, None);
    store.load();
    store.begin_save(&config_new()).unwrap();
    for _ in 0..20 {
        assert_eq!(store.poll(), SaveStatus::Busy);
    }
    // A write is running: the load waits for it (bounded), then reads.
    let l = store.load();
    assert_eq!(l.config, config_a());
    assert!(store.is_saving());
    let end = loop {
        match store.poll() {
            SaveStatus::Busy => {}
            other => break other,
        }
    };
    assert_eq!(end, SaveStatus::Done(Ok(())));
    assert_eq!(store.load().config, config_new());
}

#[test]
fn eeprom_worn_cell_fails_the_save_and_keeps_the_old_copy() {
    let image = eeprom_image::<Config, RECORD_LEN>(&[config_a()]);
    let rec = record(&config_new(), 2);
    // A byte of slot 1's payload that must take a zero bit it cannot hold.
    let i = (12..rec.len()).find(|&i| rec[i] != 0xFF).unwrap();
    let address = u16::try_from(SLOT_LEN + i).unwrap();
    let mut store = eeprom_store::<Config, RECORD_LEN>(&image, None);
    store.load();
    let mut cells = store.release().release();
    cells.worn = Some((address, 0xFF));
    let mut store = ConfigStore::new(EepromStorage::new(cells));
    store.load();
    // Worn: the bits stay one. Run the save until the worn byte has been
    // started, then load (the console's `load` during a save): the failed
    // byte belongs to the slot being written, the old copy stays in force.
    // Slot 1 is erased: the writes before the worn byte's are the record's
    // bytes before it that are not 0xFF.
    let before = rec[..i].iter().filter(|b| **b != 0xFF).count();
    store.begin_save(&config_new()).unwrap();
    while store.storage().cells().writes <= before {
        assert_eq!(store.poll(), SaveStatus::Busy);
    }
    let l = store.load();
    assert!(!l.defaults);
    assert_eq!(l.config, config_a());
    let r = loop {
        match store.poll() {
            SaveStatus::Busy => {}
            SaveStatus::Done(r) => break r,
            SaveStatus::Idle => panic!("idle during a save"),
        }
    };
    assert_eq!(r, Err(SaveError::Storage(EepromError::Verify { address })));
    let bytes = store.release().release().bytes;
    assert_eq!(eeprom_load::<Config, RECORD_LEN>(&bytes).config, config_a());
}

#[test]
fn eeprom_access_beyond_the_end_is_an_error() {
    let mut s = EepromStorage::new(CutEeprom::new(vec![0xFF; 100], None));
    let mut buf = [0u8; 8];
    assert_eq!(s.read(96, &mut buf), Err(EepromError::OutOfRange));
    assert_eq!(s.read(usize::MAX, &mut buf), Err(EepromError::OutOfRange));
    assert_eq!(s.write_step(99, &[1, 2]), Err(EepromError::OutOfRange));
    // A store on it is too small for two slots.
    let mut store = ConfigStore::new(s);
    assert_eq!(store.begin_save(&config_a()), Err(SaveError::TooSmall));
}

// ---------------------------------------------------------------------------
// The NOR flash model.

/// Erase unit.
const SECTOR: usize = 2048;
/// Program unit.
const WORD: usize = 4;
/// Sectors: 0 and 3 hold "code", 1 and 2 the slots.
const SECTORS: usize = 4;
/// Bytes the store programs per write step (the adapter's default).
const STEP: usize = 16;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum EraseCut {
    /// The first `n` bytes of the sector erased, the rest as before.
    Prefix(usize),
    /// Every bit part-erased: some old zero bits are one.
    Bits,
    /// Anything.
    Garbage,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum WordCut {
    Erased,
    New,
    /// Some of the zero bits programmed.
    Partial,
    Garbage,
}

const WORD_CUTS: [WordCut; 4] = [
    WordCut::Erased,
    WordCut::New,
    WordCut::Partial,
    WordCut::Garbage,
];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NorCut {
    /// During the save's erase.
    Erase(EraseCut),
    /// During word number `.0` the save programs.
    Word(usize, WordCut),
}

/// Every erase outcome: an erased prefix at every word boundary of the
/// slot (0: untouched), the whole sector, part-erased bits, garbage.
fn erase_cuts() -> Vec<EraseCut> {
    let mut v: Vec<EraseCut> = (0..=SLOT_LEN).step_by(WORD).map(EraseCut::Prefix).collect();
    v.push(EraseCut::Prefix(SECTOR));
    v.push(EraseCut::Bits);
    v.push(EraseCut::Garbage);
    v
}

struct CutNor {
    bytes: Vec<u8>,
    /// Words programmed since their sector's last erase.
    programmed: Vec<bool>,
    erases: usize,
    words: usize,
    cut: Option<NorCut>,
    dead: bool,
    rng: Rng,
    /// A stuck bit: byte offset and the bits that stay one.
    stuck: Option<(usize, u8)>,
}

impl CutNor {
    fn new(bytes: Vec<u8>, cut: Option<NorCut>) -> Self {
        let words = bytes.len() / WORD;
        CutNor {
            bytes,
            programmed: vec![false; words],
            erases: 0,
            words: 0,
            cut,
            dead: false,
            rng: Rng(0x2545_F491_4F6C_DD1D),
            stuck: None,
        }
    }

    /// A flash with code in sectors 0 and 3 and 1–2 erased.
    fn fresh_image() -> Vec<u8> {
        let mut b = vec![0xFF; SECTORS * SECTOR];
        for (i, x) in b[..SECTOR].iter_mut().enumerate() {
            *x = i as u8;
        }
        for (i, x) in b[3 * SECTOR..].iter_mut().enumerate() {
            *x = (i as u8).wrapping_mul(7);
        }
        b
    }
}

impl ErrorType for CutNor {
    type Error = NorFlashErrorKind;
}

impl ReadNorFlash for CutNor {
    const READ_SIZE: usize = 1;
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        check_read(self, offset, bytes.len())?;
        let o = offset as usize;
        bytes.copy_from_slice(&self.bytes[o..o + bytes.len()]);
        Ok(())
    }
    fn capacity(&self) -> usize {
        self.bytes.len()
    }
}

impl NorFlash for CutNor {
    const WRITE_SIZE: usize = WORD;
    const ERASE_SIZE: usize = SECTOR;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        check_erase(self, from, to)?;
        assert!(!self.dead, "flash erased after the power cut");
        for s in (from as usize / SECTOR)..(to as usize / SECTOR) {
            let k = self.erases;
            self.erases += 1;
            let sector = s * SECTOR..(s + 1) * SECTOR;
            self.programmed[s * SECTOR / WORD..(s + 1) * SECTOR / WORD].fill(false);
            if let Some(NorCut::Erase(how)) = self.cut {
                if k == 0 {
                    match how {
                        EraseCut::Prefix(n) => {
                            self.bytes[sector.start..sector.start + n].fill(0xFF)
                        }
                        EraseCut::Bits => {
                            for b in &mut self.bytes[sector] {
                                *b |= self.rng.byte();
                            }
                        }
                        EraseCut::Garbage => {
                            for b in &mut self.bytes[sector] {
                                *b = self.rng.byte();
                            }
                        }
                    }
                    self.dead = true;
                    return Err(NorFlashErrorKind::Other);
                }
            }
            self.bytes[sector].fill(0xFF);
        }
        Ok(())
    }

    fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), Self::Error> {
        check_write(self, offset, data.len())?;
        assert!(!self.dead, "flash programmed after the power cut");
        for (j, word) in data.chunks(WORD).enumerate() {
            let at = offset as usize + j * WORD;
            let w = at / WORD;
            assert!(
                !self.programmed[w],
                "word at {at:#x} programmed twice without an erase"
            );
            self.programmed[w] = true;
            let k = self.words;
            self.words += 1;
            if let Some(NorCut::Word(cut_at, how)) = self.cut {
                if cut_at == k {
                    for (i, &v) in word.iter().enumerate() {
                        let b = &mut self.bytes[at + i];
                        *b = match how {
                            WordCut::Erased => *b,
                            WordCut::New => *b & v,
                            WordCut::Partial => *b & (v | self.rng.byte()),
                            WordCut::Garbage => self.rng.byte(),
                        };
                    }
                    self.dead = true;
                    return Err(NorFlashErrorKind::Other);
                }
            }
            for (i, &v) in word.iter().enumerate() {
                let stuck = match self.stuck {
                    Some((o, bits)) if o == at + i => bits,
                    _ => 0,
                };
                // Programming only clears bits.
                self.bytes[at + i] &= v | stuck;
            }
        }
        Ok(())
    }
}

type NorStore = ConfigStore<NorFlashStorage<CutNor, STEP>>;

fn nor_store(bytes: &[u8], cut: Option<NorCut>) -> NorStore {
    let storage = NorFlashStorage::new(CutNor::new(bytes.to_vec(), cut), SECTOR as u32)
        .expect("slots in sectors 1 and 2");
    ConfigStore::new(storage)
}

fn nor_load(bytes: &[u8]) -> Loaded {
    nor_store(bytes, None).load()
}

/// Boots on `bytes`, saves `new` polling, with a cut: the bytes left and
/// how it ended. Checks that a poll erases at most one sector, or programs
/// at most `STEP` bytes, never both.
fn nor_save(
    bytes: &[u8],
    new: &Config,
    cut: Option<NorCut>,
) -> (Vec<u8>, End<NorError<NorFlashErrorKind>>) {
    let mut store = nor_store(bytes, cut);
    store.load();
    store.begin_save(new).expect("save staged");
    let mut polls = 0u32;
    let end = loop {
        let f = store.storage().flash();
        let (e0, w0) = (f.erases, f.words);
        let status = store.poll();
        let f = store.storage().flash();
        let (de, dw) = (f.erases - e0, f.words - w0);
        assert!(
            de <= 1 && dw <= STEP / WORD && !(de > 0 && dw > 0),
            "one step per poll"
        );
        if f.dead {
            break End::Cut;
        }
        match status {
            SaveStatus::Busy => {}
            SaveStatus::Done(r) => break End::Done(r),
            SaveStatus::Idle => panic!("idle during a save"),
        }
        polls += 1;
        assert!(polls < 10_000, "the save does not end");
    };
    (store.release().release().bytes, end)
}

fn nor_image(configs: &[Config]) -> Vec<u8> {
    let mut bytes = CutNor::fresh_image();
    for c in configs {
        let (b, end) = nor_save(&bytes, c, None);
        assert_eq!(end, End::Done(Ok(())));
        bytes = b;
    }
    bytes
}

/// Cuts the power at every erase outcome and every programmed word of a
/// save of `new` onto `image` (target slot `slot`, sequence `seq`).
fn nor_sweep(image: &[u8], old: Option<&Config>, slot: usize, seq: u32) -> usize {
    let new = config_new();
    let rec = record(&new, seq);
    let base = (1 + slot) * SECTOR;
    let other = (2 - slot) * SECTOR;
    let words = rec.len().div_ceil(WORD);

    // Uncut: one erase, `words` words, the record (0xFF-padded) in the
    // target sector, everything else untouched.
    let mut store = nor_store(image, None);
    store.load();
    store.save(&new).expect("uncut save");
    assert_eq!(
        (
            store.storage().flash().erases,
            store.storage().flash().words
        ),
        (1, words)
    );
    let after = store.release().release().bytes;
    assert_eq!(&after[base..base + rec.len()], &rec[..]);
    assert!(after[base + rec.len()..base + SECTOR]
        .iter()
        .all(|b| *b == 0xFF));
    assert_eq!(&after[other..other + SECTOR], &image[other..other + SECTOR]);
    assert_eq!(&after[..SECTOR], &image[..SECTOR], "code sector 0 changed");
    assert_eq!(
        &after[3 * SECTOR..],
        &image[3 * SECTOR..],
        "code sector 3 changed"
    );
    assert_eq!(nor_load(&after).config, new);

    let mut cuts: Vec<NorCut> = erase_cuts().into_iter().map(NorCut::Erase).collect();
    for k in 0..words {
        cuts.extend(WORD_CUTS.iter().map(|&how| NorCut::Word(k, how)));
    }
    let mut tried = 0;
    let (mut saw_old, mut saw_new) = (false, false);
    for cut in cuts {
        let what = format!("slot {slot}, {cut:?} of {words} words");
        let (left, end) = nor_save(image, &new, Some(cut));
        assert_eq!(end, End::Cut, "{what}");
        assert_eq!(
            &left[other..other + SECTOR],
            &image[other..other + SECTOR],
            "{what}"
        );
        let l = nor_load(&left);
        check_after_cut(&l, old, &new, &what);
        if cut == NorCut::Word(words - 1, WordCut::New) {
            assert_eq!(l.config, new, "{what}: the record is complete");
        }
        saw_new |= !l.defaults && l.config == new;
        saw_old |= l.config != new;
        tried += 1;
    }
    assert!(saw_old && saw_new, "both outcomes occur");
    tried
}

/// Erase outcomes (every word boundary of a slot, the whole sector,
/// part-erased bits, garbage) plus four outcomes per programmed word.
fn nor_cut_points() -> usize {
    let words = (12 + Config::default().encode(&mut [0u8; 512]).unwrap() + 4).div_ceil(WORD);
    (SLOT_LEN / WORD + 1 + 3) + 4 * words
}

#[test]
fn nor_cut_at_every_word_and_erase_from_empty() {
    let tried = nor_sweep(&CutNor::fresh_image(), None, 0, 1);
    assert_eq!(tried, nor_cut_points());
    println!("NOR flash, empty storage: {tried} cut points");
}

#[test]
fn nor_cut_at_every_word_and_erase_with_one_good_slot() {
    let image = nor_image(&[config_a()]);
    assert_eq!(
        nor_load(&image).slots,
        [SlotState::Good(1), SlotState::Empty]
    );
    let tried = nor_sweep(&image, Some(&config_a()), 1, 2);
    assert_eq!(tried, nor_cut_points());
    println!("NOR flash, one good slot: {tried} cut points");
}

#[test]
fn nor_cut_at_every_word_and_erase_with_two_good_slots() {
    let image = nor_image(&[config_a(), config_b()]);
    assert_eq!(
        nor_load(&image).slots,
        [SlotState::Good(1), SlotState::Good(2)]
    );
    let tried = nor_sweep(&image, Some(&config_b()), 0, 3);
    assert_eq!(tried, nor_cut_points());
    println!("NOR flash, two good slots: {tried} cut points");
}

#[test]
fn nor_repeated_cut_saves_then_a_whole_one() {
    let mut rng = Rng(0xD1B5_4A32_D192_ED03);
    let mut bytes = nor_image(&[config_a(), config_b()]);
    let mut good = config_b();
    let erase = erase_cuts();
    let words = RECORD_LEN.div_ceil(WORD);
    for i in 0..12u32 {
        let mut next = config_new();
        next.safety.stall_timeout_s = 10 + i;
        let cut = if rng.below(4) == 0 {
            NorCut::Erase(erase[rng.below(erase.len())])
        } else {
            NorCut::Word(rng.below(words), WORD_CUTS[rng.below(4)])
        };
        let (left, end) = nor_save(&bytes, &next, Some(cut));
        assert_eq!(end, End::Cut);
        let l = nor_load(&left);
        check_after_cut(&l, Some(&good), &next, &format!("attempt {i}, {cut:?}"));
        good = l.config;
        bytes = left;
    }
    let last = config_a();
    let (after, end) = nor_save(&bytes, &last, None);
    assert_eq!(end, End::Done(Ok(())));
    assert_eq!(nor_load(&after).config, last);
}

#[test]
fn nor_save_restarted_midway_erases_again() {
    let image = nor_image(&[config_a()]);
    let mut store = nor_store(&image, None);
    store.load();
    store.begin_save(&config_b()).unwrap();
    // Erase, then two program steps.
    for _ in 0..3 {
        assert_eq!(store.poll(), SaveStatus::Busy);
    }
    assert!(store.storage().flash().words > 0);
    // A new save replaces it: same slot, erased again (the model fails a
    // word programmed twice).
    store.begin_save(&config_new()).unwrap();
    let end = loop {
        match store.poll() {
            SaveStatus::Busy => {}
            other => break other,
        }
    };
    assert_eq!(end, SaveStatus::Done(Ok(())));
    assert_eq!(store.poll(), SaveStatus::Idle);
    assert_eq!(store.storage().flash().erases, 2);
    let bytes = store.release().release().bytes;
    let l = nor_load(&bytes);
    assert_eq!(l.config, config_new());
    assert_eq!(l.slots, [SlotState::Good(1), SlotState::Good(2)]);
}

#[test]
fn nor_stuck_bit_fails_the_save_and_keeps_the_old_copy() {
    let image = nor_image(&[config_a()]);
    let rec = record(&config_new(), 2);
    let i = (12..rec.len()).find(|&i| rec[i] != 0xFF).unwrap();
    let mut flash = CutNor::new(image, None);
    flash.stuck = Some((2 * SECTOR + i, 0xFF));
    let mut store =
        ConfigStore::new(NorFlashStorage::<_, STEP>::new(flash, SECTOR as u32).unwrap());
    assert_eq!(store.load().config, config_a());
    assert_eq!(
        store.save(&config_new()),
        Err(SaveError::Storage(NorError::Verify))
    );
    let bytes = store.release().release().bytes;
    assert_eq!(nor_load(&bytes).config, config_a());
}

#[test]
fn nor_adapter_checks_its_layout() {
    let flash = || CutNor::new(CutNor::fresh_image(), None);
    // Base not on a sector.
    assert!(matches!(
        NorFlashStorage::<_, STEP>::new(flash(), 100),
        Err(NorError::NotAligned)
    ));
    // Two regions past the end.
    assert!(matches!(
        NorFlashStorage::<_, STEP>::new(flash(), (3 * SECTOR) as u32),
        Err(NorError::OutOfRange)
    ));
    // A step that is not whole words.
    assert!(matches!(
        NorFlashStorage::<_, 6>::new(flash(), SECTOR as u32),
        Err(NorError::NotAligned)
    ));
    let mut s = NorFlashStorage::<_, STEP>::new(flash(), SECTOR as u32).unwrap();
    assert_eq!(
        (s.base(), s.region_len(), s.capacity()),
        (SECTOR, SECTOR, 2 * SLOT_LEN)
    );
    let mut buf = [0u8; 8];
    // Across the end of slot 0, and past slot 1.
    assert_eq!(s.read(SLOT_LEN - 4, &mut buf), Err(NorError::OutOfRange));
    assert_eq!(s.read(2 * SLOT_LEN, &mut buf), Err(NorError::OutOfRange));
    // A write not on a word.
    assert_eq!(s.write_step(2, &[0; 4]), Err(NorError::NotAligned));
    // Slot 1 is read from sector 2.
    s.read(SLOT_LEN, &mut buf).unwrap();
    assert_eq!(buf, [0xFF; 8]);
    // The blocking write: erase, then 21 bytes (five words and a padded
    // one), programmed in sector 2.
    let data: Vec<u8> = (1..=21).collect();
    assert_eq!(s.erase_step(SLOT_LEN, SLOT_LEN), Ok(SLOT_LEN));
    s.write(SLOT_LEN, &data).unwrap();
    let mut back = [0u8; 24];
    s.read(SLOT_LEN, &mut back).unwrap();
    assert_eq!(&back[..21], &data[..]);
    assert_eq!(&back[21..], &[0xFF; 3]);
    let flash = s.release();
    assert_eq!(&flash.bytes[2 * SECTOR..2 * SECTOR + 21], &data[..]);
    assert_eq!(flash.words, 6);
}

// ---------------------------------------------------------------------------
// Sequence numbers across the wrap.

/// An EEPROM image with `cfg` at `seq` in `slot` (built by this test).
fn put(bytes: &mut [u8], slot: usize, cfg: &Config, seq: u32) {
    let r = record(cfg, seq);
    bytes[slot * SLOT_LEN..slot * SLOT_LEN + r.len()].copy_from_slice(&r);
}

#[test]
fn sequence_numbers_roll_over_the_wrap() {
    let start = u32::MAX - 2;
    let mut bytes = vec![0xFF; EEPROM_LEN];
    put(&mut bytes, 0, &config_a(), start);
    assert_eq!(
        eeprom_load::<Config, RECORD_LEN>(&bytes).slots,
        [SlotState::Good(start), SlotState::Empty]
    );
    for i in 1..=6u32 {
        let mut c = config_new();
        c.wind.release_s = 1000 + i;
        let (after, end) = eeprom_save::<Config, RECORD_LEN>(&bytes, &c, None);
        assert_eq!(end, End::Done(Ok(())));
        let l = eeprom_load::<Config, RECORD_LEN>(&after);
        assert_eq!(l.config, c, "save {i}");
        // Save i writes slot i mod 2 with sequence start + i (wrapping):
        // u32::MAX − 1, u32::MAX, 0, 1, 2, 3.
        let seq = start.wrapping_add(i);
        let prev = start.wrapping_add(i - 1);
        let expected = if i % 2 == 1 {
            [SlotState::Good(prev), SlotState::Good(seq)]
        } else {
            [SlotState::Good(seq), SlotState::Good(prev)]
        };
        assert_eq!(l.slots, expected, "save {i}");
        bytes = after;
    }
}

#[test]
fn cut_at_every_byte_of_the_save_that_wraps() {
    // Slot 1 holds u32::MAX (newest), slot 0 u32::MAX − 1: the next save
    // writes sequence 0 into slot 0, numerically smaller than the old one.
    let mut image = vec![0xFF; EEPROM_LEN];
    put(&mut image, 0, &config_a(), u32::MAX - 1);
    put(&mut image, 1, &config_b(), u32::MAX);
    assert_eq!(eeprom_load::<Config, RECORD_LEN>(&image).config, config_b());
    let tried = eeprom_sweep::<Config, RECORD_LEN>(&image, Some(&config_b()), &config_new(), 0, 0);
    let rec = record(&config_new(), 0);
    let differing = rec
        .iter()
        .zip(&image[..rec.len()])
        .filter(|(r, i)| r != i)
        .count();
    assert_eq!(tried, 3 * differing);
    println!("EEPROM, the save that wraps to sequence 0: {tried} cut points");
    let (after, _) = eeprom_save::<Config, RECORD_LEN>(&image, &config_new(), None);
    assert_eq!(
        eeprom_load::<Config, RECORD_LEN>(&after).slots,
        [SlotState::Good(0), SlotState::Good(u32::MAX)]
    );
}

// ---------------------------------------------------------------------------
// RAM.

#[test]
fn the_store_holds_the_record_not_the_slot() {
    let size = std::mem::size_of::<ConfigStore<()>>();
    println!("ConfigStore RAM on this host: {size} B (record {RECORD_LEN} B, slot {SLOT_LEN} B)");
    assert!(size >= RECORD_LEN);
    // The staged record and the store's bookkeeping (which slot is newest,
    // the save in progress: some tens of bytes on a 64-bit host), not a
    // second copy of the record nor a whole slot beside it.
    assert!(size < RECORD_LEN + 64, "{size} B");
}
