//! The STM32F411's configuration sectors: flash sectors 1 and 2 (RM0383 §3.3, table "Flash module
//! organization": sectors 0–3 are 16 KiB at 0x0800_0000, 0x0800_4000,
//! 0x0800_8000, 0x0800_C000), kept free of code by
//! boards/stm32f411/memory.x.
//!
//! ```ignore
//! let storage = suntracker_stm32f411::flash::ConfigSectors::storage(dp.FLASH)?;
//! let mut store = suntracker::persist::ConfigStore::new(storage);
//! ```

use embedded_storage::nor_flash::{
    check_erase, check_read, check_write, ErrorType, NorFlash, NorFlashError, NorFlashErrorKind,
    ReadNorFlash,
};
use stm32f4xx_hal::flash::{Error as HalError, FlashExt};
use stm32f4xx_hal::pac::FLASH;

use suntracker::persist::{NorError, NorFlashStorage};

/// Offset of sector 1 from the start of the flash (0x0800_4000).
pub const WINDOW_OFFSET: usize = 0x4000;
/// Bytes of sectors 1 and 2 each.
pub const SECTOR_LEN: usize = 16 * 1024;
/// The first configuration sector's number (FLASH_CR.SNB).
const FIRST_SECTOR: u8 = 1;
/// Configuration sectors.
const SECTORS: usize = 2;

/// Errors of [`ConfigSectors`].
#[derive(Debug, Clone, Copy)]
pub enum ConfigFlashError {
    /// The flash controller reported an error (FLASH_SR).
    Hal(HalError),
    /// An access outside sectors 1–2 or not aligned.
    Access(NorFlashErrorKind),
}

impl NorFlashError for ConfigFlashError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            ConfigFlashError::Hal(e) => e.kind(),
            ConfigFlashError::Access(k) => *k,
        }
    }
}

/// Flash sectors 1 and 2 as a `NorFlash` of 32 KiB: offset 0 is
/// 0x0800_4000, erase unit one 16 KiB sector, write unit one byte
/// (stm32f4xx-hal programs at x8). Unlocks the flash for each operation
/// only; every erase or program stalls the CPU while it runs (module
/// docs).
pub struct ConfigSectors {
    flash: FLASH,
}

/// Longest stall of a 16 KiB sector erase at x8 parallelism, ms (DS10314,
/// table "Flash memory programming"; see [`suntracker::persist`]).
const ERASE_MAX_MS: u32 = 800;

impl ConfigSectors {
    /// The sectors, over the flash controller.
    pub fn new(flash: FLASH) -> Self {
        ConfigSectors { flash }
    }

    /// The configuration storage on these sectors: slot 0 in sector 1,
    /// slot 1 in sector 2; the code runs from the same flash, so that every
    /// erase and write stalls the CPU (saves wait for the axes to rest).
    pub fn storage(
        flash: FLASH,
    ) -> Result<NorFlashStorage<ConfigSectors>, NorError<ConfigFlashError>> {
        NorFlashStorage::new(ConfigSectors::new(flash), 0).map(|s| s.in_code_flash(ERASE_MAX_MS))
    }

    /// Gives the flash controller back.
    pub fn release(self) -> FLASH {
        self.flash
    }

    /// Clears FLASH_SR's sticky error flags (written as ones), which
    /// would otherwise fail every later operation.
    fn clear_errors(&mut self) {
        self.flash.sr().write(|w| {
            w.operr().clear();
            w.wrperr().clear();
            w.pgaerr().clear();
            w.pgperr().clear();
            w.pgserr().clear()
        });
    }

    /// Resets the data cache after an erase or program (FLASH_ACR.DCRST,
    /// set only with the cache off), so that reads see the new contents.
    fn reset_data_cache(&mut self) {
        let acr = self.flash.acr();
        let on = acr.read().dcen().bit_is_set();
        acr.modify(|_, w| w.dcen().clear_bit());
        acr.modify(|_, w| w.dcrst().set_bit());
        acr.modify(|_, w| w.dcrst().clear_bit());
        if on {
            acr.modify(|_, w| w.dcen().set_bit());
        }
    }

    fn absolute(offset: u32) -> Result<usize, ConfigFlashError> {
        usize::try_from(offset)
            .ok()
            .and_then(|o| o.checked_add(WINDOW_OFFSET))
            .ok_or(ConfigFlashError::Access(NorFlashErrorKind::OutOfBounds))
    }
}

impl ErrorType for ConfigSectors {
    type Error = ConfigFlashError;
}

impl ReadNorFlash for ConfigSectors {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), ConfigFlashError> {
        check_read(self, offset, bytes.len()).map_err(ConfigFlashError::Access)?;
        let start = Self::absolute(offset)?;
        let src = start
            .checked_add(bytes.len())
            .and_then(|end| FlashExt::read(&self.flash).get(start..end))
            .ok_or(ConfigFlashError::Access(NorFlashErrorKind::OutOfBounds))?;
        bytes.copy_from_slice(src);
        Ok(())
    }

    fn capacity(&self) -> usize {
        SECTORS * SECTOR_LEN
    }
}

impl NorFlash for ConfigSectors {
    const WRITE_SIZE: usize = 1;
    const ERASE_SIZE: usize = SECTOR_LEN;

    /// Erases the sectors in `from..to`, each a stall of up to 800 ms.
    fn erase(&mut self, from: u32, to: u32) -> Result<(), ConfigFlashError> {
        check_erase(self, from, to).map_err(ConfigFlashError::Access)?;
        let bounds = ConfigFlashError::Access(NorFlashErrorKind::OutOfBounds);
        let first = usize::try_from(from).map_err(|_| bounds)? / SECTOR_LEN;
        let last = usize::try_from(to).map_err(|_| bounds)? / SECTOR_LEN;
        for k in first..last {
            let sector = u8::try_from(k)
                .ok()
                .and_then(|k| k.checked_add(FIRST_SECTOR))
                .ok_or(bounds)?;
            self.clear_errors();
            let result = self.flash.unlocked().erase(sector);
            self.reset_data_cache();
            result.map_err(ConfigFlashError::Hal)?;
        }
        Ok(())
    }

    /// Programs `bytes` at `offset` (erased bytes only), 16 µs a byte.
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), ConfigFlashError> {
        check_write(self, offset, bytes.len()).map_err(ConfigFlashError::Access)?;
        let at = Self::absolute(offset)?;
        self.clear_errors();
        let result = self.flash.unlocked().program(at, bytes.iter());
        self.reset_data_cache();
        result.map_err(ConfigFlashError::Hal)
    }
}
