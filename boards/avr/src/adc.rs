//! The 10-bit ADC, single conversions without waiting (ATmega328P datasheet
//! §24 "Analog-to-Digital Converter" / ATmega2560 §26: "Starting a
//! Conversion", "Prescaling and Conversion Timing", "ADC Conversion
//! Result", register description of ADMUX, ADCSRA, ADCSRB, ADCL/ADCH).
//!
//! Reference AVcc (REFS1:0 = 01; the Uno and Mega have the 100 nF from AREF
//! to ground the datasheet asks for), right-adjusted result, prescaler 128:
//! 16 MHz / 128 = 125 kHz, inside the 50–200 kHz the datasheet asks for full
//! 10-bit resolution (§24.4). A conversion takes 13 ADC clocks (104 µs),
//! the first after enabling 25 (200 µs). The result (§24.7) is
//! `ADC = Vin · 1024 / Vref`, 0..=1023 (`suntracker::panel` turns codes into
//! millivolts).
//!
//! [`Adc::start`] selects the channel and sets ADSC; [`Adc::poll`] reads
//! ADCSRA once and, when ADSC has returned to zero ("when the conversion
//! is complete, it returns to zero", §24.9.2), the result (ADCL then ADCH,
//! §24.9.3). Neither waits; the image's loop calls `poll` until it gives
//! the code. No interrupt is used and ADIF is left alone (simavr 1.6, the
//! Debian package, does not clear it on a write of one; ADSC is enough).

#[cfg(avr_atmega2560)]
use core::cell::RefCell;

use super::chip;

/// Single-ended input channels: ADC0..ADC7 on the ATmega328P (ADC6/ADC7
/// only on the TQFP/QFN packages; the Uno's DIP has ADC0..ADC5 on A0..A5).
#[cfg(not(avr_atmega2560))]
pub const ADC_CHANNELS: u8 = 8;
/// Single-ended input channels: ADC0..ADC15 on the ATmega2560 (Mega A0..A15).
#[cfg(avr_atmega2560)]
pub const ADC_CHANNELS: u8 = 16;

/// The largest code (10 bits).
pub const ADC_MAX_CODE: u16 = 1_023;

/// Errors of the ADC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdcError {
    /// No single-ended input with this number ([`ADC_CHANNELS`]).
    NoSuchChannel(u8),
    /// A conversion is still running (its channel stays selected until it
    /// ends, §24.5 "Changing Channel or Reference Selection").
    Busy,
}

/// The ADC, enabled, AVcc reference, 125 kHz.
pub struct Adc {
    adc: chip::ADC,
    /// A conversion was started and its result not yet taken.
    pending: bool,
}

/// ADCSRA: ADC enabled, prescaler 128, and ADSC when `start`.
fn control(w: &mut chip::adc::adcsra::W, start: bool) -> &mut chip::adc::adcsra::W {
    w.aden().set_bit().adsc().bit(start).adps().prescaler_128()
}

impl Adc {
    /// Takes the ADC and enables it (channel ADC0 selected, nothing
    /// started).
    pub fn new(adc: chip::ADC) -> Self {
        adc.admux().write(|w| w.refs().avcc());
        adc.adcsra().write(|w| control(w, false));
        Adc {
            adc,
            pending: false,
        }
    }

    /// Starts one conversion of single-ended input `channel` (0 = ADC0).
    /// Refused while one is running; a result not yet taken with
    /// [`Adc::poll`] is dropped.
    pub fn start(&mut self, channel: u8) -> Result<(), AdcError> {
        if channel >= ADC_CHANNELS {
            return Err(AdcError::NoSuchChannel(channel));
        }
        if self.is_busy() {
            return Err(AdcError::Busy);
        }
        self.select(channel);
        self.adc.adcsra().write(|w| control(w, true));
        self.pending = true;
        Ok(())
    }

    /// Selects AVcc and `channel` (checked by the caller).
    #[cfg(not(avr_atmega2560))]
    fn select(&mut self, channel: u8) {
        self.adc.admux().write(|w| {
            let mux = w.refs().avcc().mux();
            match channel {
                0 => mux.adc0(),
                1 => mux.adc1(),
                2 => mux.adc2(),
                3 => mux.adc3(),
                4 => mux.adc4(),
                5 => mux.adc5(),
                6 => mux.adc6(),
                _ => mux.adc7(),
            }
        });
    }

    /// Selects AVcc and `channel` (checked by the caller): MUX5 in ADCSRB
    /// selects ADC8..15 (ATmega2560 §26.8.1, Table 26-4).
    #[cfg(avr_atmega2560)]
    fn select(&mut self, channel: u8) {
        self.adc.adcsrb().modify(|_, w| w.mux5().bit(channel >= 8));
        self.adc
            .admux()
            .write(|w| w.refs().avcc().mux().set(channel & 0b111));
    }

    /// True while a conversion runs (ADSC, §24.9.2).
    pub fn is_busy(&self) -> bool {
        self.adc.adcsra().read().adsc().bit_is_set()
    }

    /// The code of the conversion [`Adc::start`] began, once it is
    /// complete (once per conversion); `None` while it runs or when none
    /// was started.
    pub fn poll(&mut self) -> Option<u16> {
        if !self.pending || self.is_busy() {
            return None;
        }
        self.pending = false;
        Some(self.adc.adc().read().bits() & ADC_MAX_CODE)
    }

    /// One conversion of `channel`, waited for (13 ADC clocks, 104 µs,
    /// after any conversion under way ends): for a reading taken where it
    /// is needed (a motor's current sense, [`SharedAdcChannel`]). A
    /// conversion [`Adc::start`] began and [`Adc::poll`] has not taken is
    /// started again on its own channel afterwards, so that its reader
    /// gets a code of its channel, one conversion later.
    #[cfg(avr_atmega2560)]
    pub fn convert(&mut self, channel: u8) -> Result<u16, AdcError> {
        if channel >= ADC_CHANNELS {
            return Err(AdcError::NoSuchChannel(channel));
        }
        while self.is_busy() {}
        let resume = self.pending.then(|| self.selected());
        self.select(channel);
        self.adc.adcsra().write(|w| control(w, true));
        while self.is_busy() {}
        let code = self.adc.adc().read().bits() & ADC_MAX_CODE;
        if let Some(previous) = resume {
            self.select(previous);
            self.adc.adcsra().write(|w| control(w, true));
        }
        Ok(code)
    }

    /// The selected single-ended channel (MUX2:0 of ADMUX, MUX5 of ADCSRB).
    #[cfg(avr_atmega2560)]
    fn selected(&self) -> u8 {
        let low = self.adc.admux().read().bits() & 0b111;
        let high = if self.adc.adcsrb().read().mux5().bit_is_set() {
            8
        } else {
            0
        };
        low | high
    }

    /// Disables the ADC and gives it back.
    pub fn release(self) -> chip::ADC {
        self.adc.adcsra().reset();
        self.adc
    }
}

/// One ADC input of an [`Adc`] shared with other readers (the image's own
/// sampling of its supply and sensors): each reading is an
/// [`Adc::convert`], a conversion waited for. Refused with
/// [`AdcError::Busy`] while another reader holds the converter.
#[cfg(avr_atmega2560)]
pub struct SharedAdcChannel<'a> {
    adc: &'a RefCell<Adc>,
    channel: u8,
}

#[cfg(avr_atmega2560)]
impl<'a> SharedAdcChannel<'a> {
    /// Input `channel` (0 = ADC0) of `adc`; checked at each reading.
    pub fn new(adc: &'a RefCell<Adc>, channel: u8) -> Self {
        SharedAdcChannel { adc, channel }
    }
}

#[cfg(avr_atmega2560)]
impl drivers::adc::AdcChannel for SharedAdcChannel<'_> {
    type Error = AdcError;

    fn read_raw(&mut self) -> Result<u16, AdcError> {
        let mut adc = self.adc.try_borrow_mut().map_err(|_| AdcError::Busy)?;
        adc.convert(self.channel)
    }

    fn full_scale(&self) -> u16 {
        ADC_MAX_CODE
    }
}
