//! The configuration's storage: the two-slot CRC-32 store ([`ConfigStore`],
//! its slot layout and records, in `store`), and what it is kept on: byte
//! EEPROM ([`EepromStorage`], the AVR's through
//! `suntracker_avr::eeprom::Eeprom`), NOR flash through `embedded-storage`
//! ([`NorFlashStorage`], the STM32F411's through `stm32f411::ConfigSectors`),
//! both written in steps that never wait, for [`ConfigStore`]'s stepped save,
//! and RAM ([`MemStorage`], in `mem`).
//!
//! # What is stored where
//!
//! | board | storage | slot 0 | slot 1 | one save |
//! |---|---|---|---|---|
//! | Arduino Uno (ATmega328P, 1 KiB EEPROM) | EEPROM | bytes 0–255 | bytes 256–511 | the record's changed bytes, one started per step, 3.4 ms each in the background |
//! | Arduino Mega 2560 (ATmega2560, 4 KiB EEPROM) | EEPROM | bytes 0–255 | bytes 256–511 | as the Uno |
//! | Black Pill (STM32F411CE, 512 KiB flash) | flash sectors 1 and 2 | 0x0800_4000 (sector 1, 16 KiB) | 0x0800_8000 (sector 2, 16 KiB) | erase the sector (the CPU stalls), then program 16 bytes a step |
//! | QEMU mps2-an386, hosts | RAM ([`MemStorage`]) | bytes 0–255 | bytes 256–511 | one write |
//!
//! A build with the core's `linear` feature (the linear actuators' keys:
//! a configuration record of 296 bytes) has slots of 512 bytes: slot 1 at
//! byte 512, and the old slot 1 at byte 256 still read ([`SLOT_LEN`]; the
//! store's module docs). The hosts' tests and simulator are built so.
//!
//! Each slot holds one record of [`RECORD_LEN`](crate::config::RECORD_LEN)
//! bytes at its start (layout in `store`, [`ConfigStore`]); a save writes the slot
//! without the newest good copy, so the other one stays good through any
//! power cut (shown by `tests/persist_powercut.rs` on the fault models of an
//! EEPROM and a NOR flash, through this module's code).
//!
//! # EEPROM (AVR)
//!
//! ATmega328P datasheet §8.4 / ATmega2560 datasheet §8.6 "EEPROM Data
//! Memory": the EEPROM is written one byte at a time through EEAR (address),
//! EEDR (data) and EECR: set EEMPE, then within four clock cycles EEPE; the
//! write then runs in the background and EEPE reads one until it is done,
//! 3.4 ms for an erase and write in one operation (EEPM = 00, table "EEPROM
//! Mode Bits"). While it runs the EEPROM can neither be read nor be given a
//! new address. [`EepromStorage::write_step`] therefore never waits: with
//! EEPE set it takes nothing; else it checks the byte started last (read
//! back), skips the bytes that already hold their value (no wear, no time)
//! and starts the first one that differs. A record of about 160 bytes
//! changes only some of its bytes between saves (header and unchanged
//! fields are skipped), so a save takes at most 160 × 3.4 ms ≈ 0.55 s of
//! background time, the loop running all along.
//!
//! Reads wait for a write in progress (at most the 3.4 ms of one byte):
//! [`ConfigStore::load`] only reads, and
//! a load during a save is rare (the console's `load`).
//!
//! Endurance (datasheets, features page): 100,000 write/erase cycles per
//! byte. The sequence number changes at every save and each slot is
//! written every second save: 200,000 saves before the first byte is worn.
//!
//! # NOR flash
//!
//! [`NorFlashStorage`] maps the two slots onto two erase regions of any
//! `embedded_storage::nor_flash::NorFlash` (regions of whole erase units,
//! the first at `base`): a save erases the target slot's region one erase
//! unit a step ([`Storage::erase_step`]), then programs the record `STEP`
//! bytes a step (default 16), reading each step back. The last word is
//! padded with 0xFF (the erased value), so any write size up to `STEP`
//! works. Power-cut safety needs nothing else: an erase or a program cut
//! short leaves the target region's contents undefined (the trait's own
//! contract), the other region untouched.
//!
//! ## What blocks on the STM32F411
//!
//! The F411 has one flash bank, and RM0383 §3.5 ("Erase and program
//! operations") says that any read of the flash while it is being written
//! or erased stalls the bus until the operation is over: the CPU fetches its
//! code from that flash, so it stops — interrupt handlers included (their
//! vectors and code are in flash too) — for as long as the erase lasts,
//! whatever the driver's API. A sector erase is one such stall; how long
//! (DS10314, table "Flash memory programming"): a 16 KiB sector takes 400 ms
//! typical, 800 ms at most with the x8 parallelism that stm32f4xx-hal 0.23
//! uses (250 / 500 ms at x32, which needs VDD 2.7–3.6 V); a 128 KiB sector
//! 2 s / 4 s at x8 — longer than the board's 2 s watchdog. Hence sectors 1
//! and 2: 16 KiB, the shortest erase, with the vector table alone in sector
//! 0 and `.text` from sector 3 (boards/stm32f411/memory.x sets
//! cortex-m-rt's `_stext`). Programming stalls too, but one byte (x8) takes
//! 16 µs typical, 100 µs at most (same table): a 16-byte step stalls 0.26 ms
//! typical, 1.6 ms at most. During the erase no interrupt runs: the
//! SysTick interrupts due meanwhile are taken once at its end (a counter
//! of them falls behind by the erase's length), received GPS bytes overrun
//! (counted as dropped), and the steppers hold their position. So
//! [`NorFlashStorage::in_code_flash`] marks such a flash with its longest
//! stall ([`crate::ports::Storage::stall_ms`]), and the firmware loop takes
//! the steps of a save on it only while no axis moves and no controller
//! tick is due for that long: a `save` typed during a move waits for its
//! end, and no step of the axes falls in the stall. The independent watchdog (2 s) outlasts the
//! 800 ms.
//!
//! The flash driver is stm32f4xx-hal 0.23's `flash` module: it implements
//! `NorFlash` for its `UnlockedFlash` (erase per physical sector, program
//! byte by byte at x8, both waiting on BSY). Its `NorFlash::ERASE_SIZE` is
//! 128 KiB for the whole part (the largest sector), which would make a
//! generic adapter erase 128 KiB, so `stm32f411::ConfigSectors` puts a
//! `NorFlash` of its own over sectors 1–2 only (ERASE_SIZE 16 KiB, true
//! there), unlocks the flash for each operation only, clears FLASH_SR's
//! sticky error flags first (the HAL never clears them and reports a flag
//! still set as the failure of every later operation) and resets the data
//! cache afterwards, so that
//! the read-back sees the new contents (as ST's own HAL does after an erase
//! or program, `FLASH_FlushCaches`, "to be sure of the data consistency";
//! FLASH_ACR.DCRST may only be set with the cache off).
//!
//! ## Why not `sequential-storage`
//!
//! `sequential-storage` keeps a key–value map in flash pages and appends
//! new values, erasing a page only when the pages fill: with a 16 KiB page
//! and a 160-byte record, one erase (and one stall) per ~100 saves instead
//! of one per save, and wear spread over the pages. For frequent saves it
//! would serve the flash better. It is not used because: its operations are
//! `async` futures over `embedded-storage-async` (this firmware has no
//! executor, and its docs warn that a future cancelled part-way can leave
//! the flash in a state to repair); each poll of such a future still runs
//! the blocking erase on the F411, so the stall stays; its in-flash format
//! changes with its major versions; and the AVR EEPROM, which needs no erase,
//! would keep the two-slot format anyway — one format and one power-cut
//! proof for every board was worth more. The configuration is saved by hand
//! on the console, rarely: sector endurance (10,000 cycles, DS10314) gives
//! 20,000 saves across the two sectors.

use embedded_storage::nor_flash::NorFlash;

use crate::ports::Storage;

mod mem;
mod store;

pub use mem::{MemError, MemStorage};
pub use store::{
    crc32, record_len, slot_len, ConfigStore, LoadReport, Loaded, Payload, PayloadBytes, Record,
    SaveError, SaveStatus, SlotState, SHORT_SLOT_LEN, SLOT_LEN,
};

/// The cells of a byte-writable EEPROM: what [`EepromStorage`] needs from
/// the hardware. Implemented by `suntracker_avr::eeprom::Eeprom`
/// (EEAR/EEDR/EECR) and by the fault model of `tests/persist_powercut.rs`.
pub trait EepromCells {
    /// Bytes of EEPROM.
    fn size_bytes(&self) -> usize;
    /// True while a byte write is in progress (EEPE set).
    fn busy(&mut self) -> bool;
    /// Reads the byte at `address`; only called while not busy.
    fn read_byte(&mut self, address: u16) -> u8;
    /// Starts an erase-and-write of `value` at `address` and returns at
    /// once; only called while not busy.
    fn start_write(&mut self, address: u16, value: u8);
}

/// Errors of [`EepromStorage`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EepromError {
    /// An access beyond the end of the EEPROM.
    OutOfRange,
    /// A byte write did not end within [`EEPROM_WAIT_POLLS`] polls of the
    /// busy flag (only the blocking `read` and `write` wait).
    Timeout,
    /// The byte at this address reads back other than written: a worn or
    /// failing cell (or a write interrupted by a brown-out).
    Verify {
        /// The EEPROM address.
        address: u16,
    },
}

/// How many times the blocking [`EepromStorage`] methods poll the busy flag
/// before they give up. One byte takes 3.4 ms (datasheets, table "EEPROM
/// Mode Bits"): 54,400 cycles at 16 MHz; a poll takes at least 4 cycles
/// (register load, branch, counter), so a write ends within 13,600 polls;
/// 100,000 leave more than 7 times that before the hardware is declared
/// failed.
pub const EEPROM_WAIT_POLLS: u32 = 100_000;

/// A byte EEPROM as [`Storage`], written in steps that never wait: one
/// byte started per [`Storage::write_step`], bytes that already hold their
/// value skipped, each written byte read back once it is done.
#[derive(Debug)]
pub struct EepromStorage<C> {
    cells: C,
    /// The byte started last and not yet read back: address and value.
    pending: Option<(u16, u8)>,
}

impl<C: EepromCells> EepromStorage<C> {
    /// The storage over `cells`.
    pub fn new(cells: C) -> Self {
        EepromStorage {
            cells,
            pending: None,
        }
    }

    /// The cells, to look at.
    pub fn cells(&self) -> &C {
        &self.cells
    }

    /// Gives the cells back (a byte write may still be running).
    pub fn release(self) -> C {
        self.cells
    }

    /// Checks that an access of `len` bytes at `offset` lies inside the
    /// EEPROM.
    fn check(&self, offset: usize, len: usize) -> Result<(), EepromError> {
        match offset.checked_add(len) {
            Some(end) if end <= self.cells.size_bytes() => Ok(()),
            _ => Err(EepromError::OutOfRange),
        }
    }

    /// The EEPROM address of byte `i` of an access at `offset`.
    fn address(offset: usize, i: usize) -> Result<u16, EepromError> {
        offset
            .checked_add(i)
            .and_then(|a| u16::try_from(a).ok())
            .ok_or(EepromError::OutOfRange)
    }

    /// Waits (bounded) until no byte write runs: for the blocking methods.
    fn wait_ready(&mut self) -> Result<(), EepromError> {
        for _ in 0..EEPROM_WAIT_POLLS {
            if !self.cells.busy() {
                return Ok(());
            }
        }
        Err(EepromError::Timeout)
    }

    /// Reads back the byte started last; only while not busy.
    fn check_pending(&mut self) -> Result<(), EepromError> {
        if let Some((address, value)) = self.pending.take() {
            if self.cells.read_byte(address) != value {
                return Err(EepromError::Verify { address });
            }
        }
        Ok(())
    }
}

impl<C: EepromCells> Storage for EepromStorage<C> {
    type Error = EepromError;

    fn capacity(&self) -> usize {
        self.cells.size_bytes()
    }

    /// Waits for a byte write in progress (at most one byte's 3.4 ms), then
    /// reads. The byte started last is read back by the next write or flush
    /// step, not here: a failed byte of the slot being written must not
    /// make the other slot look unreadable.
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), EepromError> {
        self.check(offset, buf.len())?;
        self.wait_ready()?;
        for (i, b) in buf.iter_mut().enumerate() {
            *b = self.cells.read_byte(Self::address(offset, i)?);
        }
        Ok(())
    }

    /// Writes every byte that differs, waiting for each (blocking: hosts
    /// and tests; a firmware loop uses the steps).
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), EepromError> {
        self.check(offset, data.len())?;
        for (i, &value) in data.iter().enumerate() {
            let address = Self::address(offset, i)?;
            self.wait_ready()?;
            self.check_pending()?;
            if self.cells.read_byte(address) != value {
                self.cells.start_write(address, value);
                self.pending = Some((address, value));
            }
        }
        self.wait_ready()?;
        self.check_pending()
    }

    /// Nothing to prepare: each byte write erases its byte.
    fn erase_step(&mut self, offset: usize, len: usize) -> Result<usize, EepromError> {
        self.check(offset, len)?;
        Ok(len)
    }

    /// With a write in progress: takes nothing. Else reads back the byte
    /// started last, skips the bytes of `data` the EEPROM already holds and
    /// starts the first that differs: returns the bytes taken (skipped ones
    /// and the started one).
    fn write_step(&mut self, offset: usize, data: &[u8]) -> Result<usize, EepromError> {
        self.check(offset, data.len())?;
        if self.cells.busy() {
            return Ok(0);
        }
        self.check_pending()?;
        for (i, &value) in data.iter().enumerate() {
            let address = Self::address(offset, i)?;
            if self.cells.read_byte(address) != value {
                self.cells.start_write(address, value);
                self.pending = Some((address, value));
                return Ok(i.saturating_add(1));
            }
        }
        Ok(data.len())
    }

    /// Done when no write runs and the byte started last reads back right.
    fn flush_step(&mut self) -> Result<bool, EepromError> {
        if self.cells.busy() {
            return Ok(false);
        }
        self.check_pending()?;
        Ok(true)
    }
}

/// Errors of [`NorFlashStorage`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NorError<E> {
    /// The flash failed.
    Flash(E),
    /// An access outside the two slots, or slot regions beyond the flash.
    OutOfRange,
    /// `base` not on an erase unit, `STEP` not a multiple of the write
    /// size, or an access not on a write unit.
    NotAligned,
    /// Programmed bytes read back other than written.
    Verify,
}

/// Largest read size [`NorFlashStorage`] supports (its read buffer).
const MAX_READ_SIZE: usize = 32;

/// The two configuration slots on a NOR flash: slot `k` at the start of
/// region `k` (whole erase units covering [`SLOT_LEN`] bytes, region 0 at
/// `base`). Erases one erase unit per [`Storage::erase_step`]; programs at
/// most `STEP` bytes (a multiple of the write size) per
/// [`Storage::write_step`] and reads them back. What a step stalls is the
/// flash's own (module docs).
#[derive(Debug)]
pub struct NorFlashStorage<F, const STEP: usize = 16> {
    flash: F,
    /// Offset of slot 0's region in the flash.
    base: usize,
    /// Bytes of each slot's region: whole erase units.
    region: usize,
    /// The longest stall of an erase or write, ms ([`Storage::stall_ms`]).
    stall_ms: u32,
}

impl<F: NorFlash, const STEP: usize> NorFlashStorage<F, STEP> {
    /// The slots on `flash`, the first region at offset `base`: checks that
    /// `base` lies on an erase unit, that both regions fit in the flash,
    /// that `STEP` is a multiple of the write size and that the write size
    /// divides a slot.
    pub fn new(flash: F, base: u32) -> Result<Self, NorError<F::Error>> {
        let erase = F::ERASE_SIZE;
        let write = F::WRITE_SIZE;
        let base = usize::try_from(base).map_err(|_| NorError::OutOfRange)?;
        if erase == 0
            || write == 0
            || STEP == 0
            || !STEP.is_multiple_of(write)
            || !SLOT_LEN.is_multiple_of(write)
            || !base.is_multiple_of(erase)
            || F::READ_SIZE == 0
            || F::READ_SIZE > MAX_READ_SIZE
        {
            return Err(NorError::NotAligned);
        }
        let region = SLOT_LEN
            .div_ceil(erase)
            .checked_mul(erase)
            .ok_or(NorError::OutOfRange)?;
        let end = region
            .checked_mul(2)
            .and_then(|both| base.checked_add(both))
            .ok_or(NorError::OutOfRange)?;
        if end > flash.capacity() {
            return Err(NorError::OutOfRange);
        }
        Ok(NorFlashStorage {
            flash,
            base,
            region,
            stall_ms: 0,
        })
    }

    /// Marks the flash as the one the code runs from: an erase or write
    /// stalls the CPU for up to `stall_ms` ([`Storage::stall_ms`]).
    pub fn in_code_flash(mut self, stall_ms: u32) -> Self {
        self.stall_ms = stall_ms;
        self
    }

    /// The flash, to look at.
    pub fn flash(&self) -> &F {
        &self.flash
    }

    /// Gives the flash back.
    pub fn release(self) -> F {
        self.flash
    }

    /// Offset of slot 0's region in the flash.
    pub fn base(&self) -> usize {
        self.base
    }

    /// Bytes of each slot's region (whole erase units).
    pub fn region_len(&self) -> usize {
        self.region
    }

    /// The flash offset of logical `offset` (slot × [`SLOT_LEN`] + byte),
    /// for an access of `len` bytes that must stay inside its slot.
    fn map(&self, offset: usize, len: usize) -> Result<usize, NorError<F::Error>> {
        let slot = offset / SLOT_LEN;
        let within = offset % SLOT_LEN;
        if slot >= 2 || within.checked_add(len).is_none_or(|end| end > SLOT_LEN) {
            return Err(NorError::OutOfRange);
        }
        slot.checked_mul(self.region)
            .and_then(|r| r.checked_add(self.base))
            .and_then(|r| r.checked_add(within))
            .ok_or(NorError::OutOfRange)
    }

    fn flash_offset(at: usize) -> Result<u32, NorError<F::Error>> {
        u32::try_from(at).map_err(|_| NorError::OutOfRange)
    }

    /// Reads `buf.len()` bytes at flash offset `at`, through aligned reads
    /// when the flash reads in units.
    fn read_flash(&mut self, at: usize, buf: &mut [u8]) -> Result<(), NorError<F::Error>> {
        let unit = F::READ_SIZE;
        if unit == 1 {
            return self
                .flash
                .read(Self::flash_offset(at)?, buf)
                .map_err(NorError::Flash);
        }
        let mut block = [0u8; MAX_READ_SIZE];
        let block = block.get_mut(..unit).ok_or(NorError::NotAligned)?;
        let mut done = 0;
        while done < buf.len() {
            let p = at.checked_add(done).ok_or(NorError::OutOfRange)?;
            let skip = p % unit;
            self.flash
                .read(Self::flash_offset(p - skip)?, block)
                .map_err(NorError::Flash)?;
            let n = (unit - skip).min(buf.len() - done);
            let (Some(dst), Some(src)) = (buf.get_mut(done..done + n), block.get(skip..skip + n))
            else {
                return Err(NorError::OutOfRange);
            };
            // Both n bytes.
            crate::bytes::copy_prefix(dst, src);
            done += n;
        }
        Ok(())
    }

    /// Reads back `expected.len()` bytes at flash offset `at`.
    fn verify(&mut self, at: usize, expected: &[u8]) -> Result<(), NorError<F::Error>> {
        let mut back = [0u8; STEP];
        let back = back.get_mut(..expected.len()).ok_or(NorError::OutOfRange)?;
        self.read_flash(at, back)?;
        if back != expected {
            return Err(NorError::Verify);
        }
        Ok(())
    }
}

impl<F: NorFlash, const STEP: usize> Storage for NorFlashStorage<F, STEP> {
    type Error = NorError<F::Error>;

    fn stall_ms(&self) -> u32 {
        self.stall_ms
    }

    /// Two slots of [`SLOT_LEN`] bytes.
    fn capacity(&self) -> usize {
        2 * SLOT_LEN
    }

    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), Self::Error> {
        let at = self.map(offset, buf.len())?;
        self.read_flash(at, buf)
    }

    /// Programs `data` (the range must have been erased since it was last
    /// programmed), `STEP` bytes at a time.
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), Self::Error> {
        let mut done = 0;
        while let Some(rest) = data.get(done..).filter(|r| !r.is_empty()) {
            let at = offset.checked_add(done).ok_or(NorError::OutOfRange)?;
            // A flash step always takes bytes of a non-empty piece.
            match self.write_step(at, rest)? {
                0 => return Err(NorError::OutOfRange),
                n => done = done.saturating_add(n),
            }
        }
        Ok(())
    }

    /// Erases the erase unit that starts at `offset` (a slot's start or a
    /// unit boundary inside it): returns the slot bytes it covers.
    fn erase_step(&mut self, offset: usize, len: usize) -> Result<usize, Self::Error> {
        if len == 0 {
            return Ok(0);
        }
        let at = self.map(offset, len)?;
        let unit = F::ERASE_SIZE;
        if !at.is_multiple_of(unit) {
            return Err(NorError::NotAligned);
        }
        let to = at.checked_add(unit).ok_or(NorError::OutOfRange)?;
        self.flash
            .erase(Self::flash_offset(at)?, Self::flash_offset(to)?)
            .map_err(NorError::Flash)?;
        Ok(len.min(unit))
    }

    /// Programs the first `STEP` bytes of `data` (whole write units; the
    /// last piece shorter than a unit is padded with 0xFF) and reads them
    /// back: returns the bytes taken.
    fn write_step(&mut self, offset: usize, data: &[u8]) -> Result<usize, Self::Error> {
        if data.is_empty() {
            return Ok(0);
        }
        let unit = F::WRITE_SIZE;
        let take = data.len().min(STEP);
        let at = self.map(offset, take)?;
        if !at.is_multiple_of(unit) {
            return Err(NorError::NotAligned);
        }
        let whole = take - take % unit;
        if whole > 0 {
            let part = data.get(..whole).ok_or(NorError::OutOfRange)?;
            self.flash
                .write(Self::flash_offset(at)?, part)
                .map_err(NorError::Flash)?;
            self.verify(at, part)?;
            return Ok(whole);
        }
        // The record's last bytes, fewer than a write unit: pad with the
        // erased value (programming 0xFF leaves a byte erased). The padded
        // unit stays inside the slot, whose length is a multiple of it.
        self.map(offset, unit)?;
        let src = data.get(..take).ok_or(NorError::OutOfRange)?;
        let mut padded = [0xFFu8; STEP];
        crate::bytes::copy_prefix(padded.get_mut(..take).ok_or(NorError::OutOfRange)?, src);
        let piece = padded.get(..unit).ok_or(NorError::NotAligned)?;
        self.flash
            .write(Self::flash_offset(at)?, piece)
            .map_err(NorError::Flash)?;
        self.verify(at, src)?;
        Ok(take)
    }
}
