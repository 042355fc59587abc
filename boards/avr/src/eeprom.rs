//! The EEPROM (ATmega328P datasheet §8.4 / ATmega2560 datasheet §8.6
//! "EEPROM Data Memory": "EEPROM Read/Write Access", the register
//! description of EEARH/EEARL, EEDR and EECR, table "EEPROM Mode Bits").
//!
//! 1 KiB on the ATmega328P (Uno), 4 KiB on the ATmega2560 (Mega), the
//! same registers on both. [`Eeprom`] gives the cells to [`EepromStorage`],
//! which writes the configuration one byte per step without waiting:
//!
//! ```ignore
//! let storage = suntracker_avr::eeprom::Eeprom::storage(dp.EEPROM);
//! let mut store = suntracker::persist::ConfigStore::new(storage);
//! let loaded = store.load();
//! ```
//!
//! A byte write: with EEPE clear (no write running), the address into EEAR,
//! the value into EEDR, then EEMPE set (with EEPE written zero and EEPM =
//! 00: erase and write in one operation, 3.4 ms) and EEPE set within four
//! clock cycles — with interrupts off, or an interrupt between the two
//! stores would let EEMPE time out and the write never start. EEPE reads
//! one until the hardware has written the byte. A read: EEAR, then EERE;
//! the CPU halts four cycles and EEDR holds the byte (never while EEPE is
//! set: the datasheet forbids reading or changing EEAR during a write).
//!
//! Not handled here: a write by the self-programming of flash (SPMEN in
//! SPMCSR must be clear; these images never write their flash), and the
//! brown-out: the datasheet's "Preventing EEPROM Corruption" asks for the
//! brown-out detector, which the Arduino boards' fuses enable (BODLEVEL 2.7
//! V); a byte cut by a power loss is old, new or garbage, which the
//! two-slot store survives (tests/persist_powercut.rs).

use avr_device::interrupt;

use super::chip;
use suntracker::persist::{EepromCells, EepromStorage};

/// Bytes of EEPROM: 4 KiB on the ATmega2560.
#[cfg(avr_atmega2560)]
pub const EEPROM_LEN: usize = 4096;
/// Bytes of EEPROM: 1 KiB on the ATmega328P.
#[cfg(not(avr_atmega2560))]
pub const EEPROM_LEN: usize = 1024;

/// The EEPROM's registers.
pub struct Eeprom {
    regs: chip::EEPROM,
}

impl Eeprom {
    /// The EEPROM, over its registers.
    pub fn new(regs: chip::EEPROM) -> Self {
        Eeprom { regs }
    }

    /// The configuration storage on the whole EEPROM (slot 0 at byte 0,
    /// slot 1 at byte 256).
    pub fn storage(regs: chip::EEPROM) -> EepromStorage<Eeprom> {
        EepromStorage::new(Eeprom::new(regs))
    }

    /// Gives the registers back.
    pub fn release(self) -> chip::EEPROM {
        self.regs
    }
}

impl EepromCells for Eeprom {
    fn size_bytes(&self) -> usize {
        EEPROM_LEN
    }

    fn busy(&mut self) -> bool {
        self.regs.eecr().read().eepe().bit_is_set()
    }

    fn read_byte(&mut self, address: u16) -> u8 {
        self.regs.eear().write(|w| w.set(address));
        self.regs.eecr().write(|w| w.eere().set_bit());
        self.regs.eedr().read().bits()
    }

    fn start_write(&mut self, address: u16, value: u8) {
        interrupt::free(|_| {
            self.regs.eear().write(|w| w.set(address));
            self.regs.eedr().write(|w| w.set(value));
            // Timed sequence: EEMPE with EEPE zero and EEPM = 00, then EEPE
            // within four cycles (interrupts are off here).
            self.regs.eecr().write(|w| w.eempe().set_bit());
            self.regs
                .eecr()
                .write(|w| w.eempe().set_bit().eepe().set_bit());
        });
    }
}
