//! One analog input, as the drivers need it: embedded-hal 1.0 has no ADC
//! trait, so the crate defines a small one of its own and each board
//! implements it for its converter (AVR ADC, STM32 ADC1, an I²C ADS1115, …).
//!
//! A reading is a raw count `0..=full_scale` proportional to the input
//! voltage over the converter's reference: `V = raw · vref / full_scale`
//! ([`millivolts`]). The DC-motor current sense ([`crate::dc_motor`]) and the
//! actuator potentiometer ([`crate::linear::PotCalibration`]) read through it.

/// One analog input channel.
///
/// ```
/// use drivers::adc::AdcChannel;
/// use core::convert::Infallible;
///
/// // A 10-bit converter (ATmega2560-class: 0..=1023) that always reads mid-scale.
/// struct MidScale;
/// impl AdcChannel for MidScale {
///     type Error = Infallible;
///     fn read_raw(&mut self) -> Result<u16, Infallible> {
///         Ok(512)
///     }
///     fn full_scale(&self) -> u16 {
///         1_023
///     }
/// }
///
/// let mut adc = MidScale;
/// assert_eq!(adc.read_raw(), Ok(512));
/// // Through a `&mut` as well (the blanket impl), without giving the channel away.
/// let borrowed = &mut adc;
/// assert_eq!(borrowed.full_scale(), 1_023);
/// ```
pub trait AdcChannel {
    /// Conversion error (bus error of an external ADC, timeout, …).
    type Error: core::fmt::Debug;

    /// One conversion, raw count `0..=full_scale()`.
    fn read_raw(&mut self) -> Result<u16, Self::Error>;

    /// The count that corresponds to the reference voltage (1023 for a
    /// 10-bit converter, 4095 for 12 bits). Constant for a channel.
    fn full_scale(&self) -> u16;
}

impl<T: AdcChannel + ?Sized> AdcChannel for &mut T {
    type Error = T::Error;

    fn read_raw(&mut self) -> Result<u16, Self::Error> {
        T::read_raw(self)
    }

    fn full_scale(&self) -> u16 {
        T::full_scale(self)
    }
}

/// A raw count as millivolts: `raw · vref_mv / full_scale`, rounded down,
/// in 32-bit integers (`raw`, `vref_mv` ≤ 65,535: the product is under
/// 2³²). A count above `full_scale` is taken as `full_scale`; a zero
/// `full_scale` gives `None`.
///
/// ```
/// use drivers::adc::millivolts;
///
/// // 10 bits over 5 V: 512 · 5000 / 1023 = 2502.4 → 2502 mV.
/// assert_eq!(millivolts(512, 1_023, 5_000), Some(2_502));
/// // 12 bits over 3.3 V: 4095 → 3300 mV exactly.
/// assert_eq!(millivolts(4_095, 4_095, 3_300), Some(3_300));
/// assert_eq!(millivolts(5_000, 4_095, 3_300), Some(3_300)); // limited to full scale
/// assert_eq!(millivolts(1, 0, 3_300), None);
/// ```
pub fn millivolts(raw: u16, full_scale: u16, vref_mv: u16) -> Option<u32> {
    if full_scale == 0 {
        return None;
    }
    let raw = raw.min(full_scale);
    // Both factors ≤ 65,535: the product stays under 2³².
    let num = u32::from(raw).checked_mul(u32::from(vref_mv))?;
    Some(num / u32::from(full_scale))
}
