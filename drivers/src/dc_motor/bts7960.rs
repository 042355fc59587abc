//! Infineon BTS7960 half-bridge pair (IBT-2 module): two PWM inputs, two
//! enables, current sense on the IS pins.
//!
//! Each BTS7960 is one half bridge (Infineon, *BTS 7960 High Current PN Half
//! Bridge*, data sheet Rev. 1.1, 2004-12-07, section 2.2 "Pin definitions
//! and functions"): IN selects the high-side (IN high) or the low-side switch
//! (IN low), INH low puts the device to sleep with both switches off, IS
//! sources the sense current. The IBT-2 module joins two of them into a full
//! bridge and brings their inputs out as RPWM/LPWM (IN), R_EN/L_EN (INH)
//! and R_IS/L_IS (IS) (IBT-2 pin table in docs.kitto.cloud, "IBT-2 Motor
//! Driver", which also gives RPWM as the forward and LPWM as the reverse
//! PWM input). With the motor between the two half bridges:
//!
//! | R_EN L_EN | RPWM | LPWM | motor                                   |
//! |-----------|------|------|-----------------------------------------|
//! | 1 1       | PWM  | 0    | forward (right high side switched)      |
//! | 1 1       | 0    | PWM  | backward                                |
//! | 1 1       | 0    | 0    | brake (both low sides on)               |
//! | 0 0       | 0    | 0    | coast (both half bridges asleep)        |
//!
//! Writes go down before up: the input that falls to 0 is written before
//! the one that rises, so both high sides are never on together; enables go
//! high after the PWM inputs are set and low before they are cleared.
//!
//! # Current sense
//!
//! While a high-side switch conducts, its IS pin sources `I_IS = I_L /
//! k_ILIS` into a resistor to ground (data sheet section 4.4, "Current
//! sense", item 4.4.6: k_ILIS typically 8.5 · 10³, min./max. 6 / 11 · 10³ at
//! I_L = 30 A, 3 / 14 · 10³ at 5 A, characterised with R_IS = 1 kΩ). The
//! voltage is read with an [`AdcChannel`]; [`CurrentSense::current_ma`]
//! turns it back into load current:
//!
//! `I_L [mA] = raw · vref_mv · k_ILIS / (full_scale · R_IS [Ω])`
//!
//! evaluated in 64-bit integers (every factor ≤ 65,535: the product is under
//! 2⁴⁸) and divided with `suntracker_time::div_rem_u64` (no 64-bit division
//! routine on an 8-bit part). Only the conducting half bridge's IS carries
//! the sense current (the other one leaks at most 1 µA, item 4.4.8), so
//! R_IS and L_IS may share one ADC input. The resistor fitted on a given
//! IBT-2 board is not documented by the module makers, and boards differ
//! from the schematic that circulates for them (Arduino forum thread
//! "BTS7960 BTN7960N IBT_2 motor drive module", 2023, on the SR and IS
//! resistors): measure it and put it in [`SenseConfig::r_is_ohm`]. Modules
//! sold with the BTN7960 instead take that part's k_ILIS from its own data
//! sheet. In a fault (over-temperature, current
//! limit) IS sources I_IS(lim), 4 – 7 mA (item 4.4.7), which reads as a large
//! current. The spread of k_ILIS makes the value an estimate (±30 % at
//! 30 A), good for stall and overload detection, not for metering.

use embedded_hal::digital::OutputPin;
use embedded_hal::pwm::SetDutyCycle;

use super::{duty_counts, write_duty, write_pin, Bridge, DcMotor, Error, Output};
use crate::adc::AdcChannel;

/// The module's four control inputs.
///
/// ```
/// use drivers::dc_motor::bts7960::Bts7960Pins;
/// use embedded_hal_mock::eh1::digital::Mock as Pin;
/// use embedded_hal_mock::eh1::pwm::Mock as Pwm;
///
/// let pins = Bts7960Pins { rpwm: Pwm::new(&[]), lpwm: Pwm::new(&[]), r_en: Pin::new(&[]), l_en: Pin::new(&[]) };
/// let Bts7960Pins { mut rpwm, mut lpwm, mut r_en, mut l_en } = pins;
/// rpwm.done();
/// lpwm.done();
/// r_en.done();
/// l_en.done();
/// ```
#[derive(Debug)]
pub struct Bts7960Pins<R, L, E> {
    /// RPWM: IN of the right half bridge (PWM for forward).
    pub rpwm: R,
    /// LPWM: IN of the left half bridge (PWM for backward).
    pub lpwm: L,
    /// R_EN: INH of the right half bridge.
    pub r_en: E,
    /// L_EN: INH of the left half bridge.
    pub l_en: E,
}

/// A DC motor on an IBT-2 (two BTS7960): [`DcMotor`] over [`Bts7960Pins`],
/// so `Bts7960::new(pins, config)` and the commands of [`DcMotor`].
///
/// ```
/// use drivers::dc_motor::bts7960::{Bts7960, Bts7960Pins};
/// use drivers::dc_motor::{Config, Output, RestMode};
/// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
/// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
///
/// // 8-bit PWM (max duty 255). `new` leaves the bridge coasting: enables
/// // low, both inputs 0. Then a soft start to 50 % at 5 ‰/ms:
/// // 100 ms → 500 ‰ → round(500 · 255 / 1000) = round(127.5) = 128 counts,
/// // and the enables go high after RPWM is set.
/// let mut rpwm = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0), P::set_duty_cycle(64), P::set_duty_cycle(128)]);
/// let mut lpwm = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]);
/// let mut r_en = Pin::new(&[T::set(State::Low), T::set(State::High)]);
/// let mut l_en = Pin::new(&[T::set(State::Low), T::set(State::High)]);
/// let pins = Bts7960Pins { rpwm: rpwm.clone(), lpwm: lpwm.clone(), r_en: r_en.clone(), l_en: l_en.clone() };
/// let mut motor = Bts7960::new(pins, Config { ramp_permille_per_ms: 5, rest: RestMode::Brake })?;
/// motor.set_duty(0.5)?;
/// assert_eq!(motor.poll(0)?, Output::Coast); // starts the ramp clock
/// assert_eq!(motor.poll(50)?, Output::Forward(250)); // 250 ‰ → round(63.75) = 64
/// assert_eq!(motor.poll(100)?, Output::Forward(500));
/// motor.destroy();
/// for p in [&mut rpwm, &mut lpwm] { p.done(); }
/// for p in [&mut r_en, &mut l_en] { p.done(); }
/// # Ok::<(), Box<dyn core::error::Error>>(())
/// ```
pub type Bts7960<R, L, E> = DcMotor<Bts7960Pins<R, L, E>>;

/// What an IBT-2 keeps between writes: both channels' max duty and the
/// value last written to each input (`None`: unknown, written next time).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bts7960State {
    max_r: u16,
    max_l: u16,
    last_r: Option<u16>,
    last_l: Option<u16>,
    last_r_en: Option<bool>,
    last_l_en: Option<bool>,
}

impl<R, L, E> Bridge for Bts7960Pins<R, L, E>
where
    R: SetDutyCycle,
    L: SetDutyCycle<Error = R::Error>,
    E: OutputPin,
{
    type PwmError = R::Error;
    type PinError = E::Error;
    type State = Bts7960State;

    /// Reads both channels' max duty, then puts the bridge in coast
    /// (R_EN, L_EN low, then RPWM, LPWM 0).
    ///
    /// ```
    /// use drivers::dc_motor::bts7960::{Bts7960, Bts7960Pins};
    /// use drivers::dc_motor::{Config, Error, Output, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// let mut rpwm = Pwm::new(&[P::max_duty_cycle(1_000), P::set_duty_cycle(0)]);
    /// let mut lpwm = Pwm::new(&[P::max_duty_cycle(1_000), P::set_duty_cycle(0)]);
    /// let mut r_en = Pin::new(&[T::set(State::Low)]);
    /// let mut l_en = Pin::new(&[T::set(State::Low)]);
    /// let pins = Bts7960Pins { rpwm: rpwm.clone(), lpwm: lpwm.clone(), r_en: r_en.clone(), l_en: l_en.clone() };
    /// let motor = Bts7960::new(pins, Config { ramp_permille_per_ms: 0, rest: RestMode::Brake })?;
    /// assert_eq!(motor.output(), Output::Coast);
    /// let mut pins = motor.destroy();
    /// pins.rpwm.done();
    /// pins.lpwm.done();
    /// pins.r_en.done();
    /// pins.l_en.done();
    /// // Either channel with max duty 0 is refused before any write.
    /// let (mut r, mut l) = (Pwm::new(&[P::max_duty_cycle(255)]), Pwm::new(&[P::max_duty_cycle(0)]));
    /// let (mut r_en, mut l_en) = (Pin::new(&[]), Pin::new(&[]));
    /// let zero = Bts7960Pins { rpwm: r.clone(), lpwm: l.clone(), r_en: r_en.clone(), l_en: l_en.clone() };
    /// let e = Bts7960::new(zero, Config { ramp_permille_per_ms: 0, rest: RestMode::Brake }).unwrap_err();
    /// assert_eq!(e, Error::InvalidConfig);
    /// for p in [&mut r, &mut l] { p.done(); }
    /// for p in [&mut r_en, &mut l_en] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn init(&mut self) -> Result<Bts7960State, Error<R::Error, E::Error>> {
        let max_r = self.rpwm.max_duty_cycle();
        let max_l = self.lpwm.max_duty_cycle();
        if max_r == 0 || max_l == 0 {
            return Err(Error::InvalidConfig);
        }
        let mut s = Bts7960State {
            max_r,
            max_l,
            last_r: None,
            last_l: None,
            last_r_en: None,
            last_l_en: None,
        };
        self.apply(&mut s, Output::Coast)?;
        Ok(s)
    }

    /// Forward: LPWM 0, then RPWM the duty; backward the mirror; brake: both
    /// inputs 0 (both low-side switches on, the motor shorted); all three
    /// with both enables high, written last. Coast: both half bridges
    /// asleep, enables low first, then both inputs 0.
    ///
    /// ```
    /// use drivers::dc_motor::bts7960::{Bts7960, Bts7960Pins};
    /// use drivers::dc_motor::{Config, Output, RestMode};
    /// use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
    /// use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
    ///
    /// // No ramp, max duty 1000 (one count per ‰): backward 30 %, then a
    /// // stop that ends in the rest mode, brake (both inputs 0, enabled).
    /// let mut rpwm = Pwm::new(&[P::max_duty_cycle(1_000), P::set_duty_cycle(0)]);
    /// let mut lpwm = Pwm::new(&[P::max_duty_cycle(1_000), P::set_duty_cycle(0), P::set_duty_cycle(300), P::set_duty_cycle(0)]);
    /// let mut r_en = Pin::new(&[T::set(State::Low), T::set(State::High)]);
    /// let mut l_en = Pin::new(&[T::set(State::Low), T::set(State::High)]);
    /// let pins = Bts7960Pins { rpwm: rpwm.clone(), lpwm: lpwm.clone(), r_en: r_en.clone(), l_en: l_en.clone() };
    /// let mut motor = Bts7960::new(pins, Config { ramp_permille_per_ms: 0, rest: RestMode::Brake })?;
    /// motor.set_duty(-0.3)?;
    /// assert_eq!(motor.poll(0)?, Output::Backward(300));
    /// motor.set_duty(0.0)?;
    /// assert_eq!(motor.poll(1)?, Output::Brake);
    /// assert_eq!(motor.poll(2)?, Output::Brake); // nothing written
    /// motor.destroy();
    /// for p in [&mut rpwm, &mut lpwm] { p.done(); }
    /// for p in [&mut r_en, &mut l_en] { p.done(); }
    ///
    /// // Brake from coast: the inputs are already 0, only the enables go high.
    /// let pwm = [P::max_duty_cycle(255), P::set_duty_cycle(0)];
    /// let (mut rpwm, mut lpwm) = (Pwm::new(&pwm), Pwm::new(&pwm));
    /// let en = [T::set(State::Low), T::set(State::High)];
    /// let (mut r_en, mut l_en) = (Pin::new(&en), Pin::new(&en));
    /// let pins = Bts7960Pins { rpwm: rpwm.clone(), lpwm: lpwm.clone(), r_en: r_en.clone(), l_en: l_en.clone() };
    /// let mut motor = Bts7960::new(pins, Config { ramp_permille_per_ms: 1, rest: RestMode::Coast })?;
    /// motor.brake()?;
    /// assert_eq!((motor.output(), motor.duty_permille()), (Output::Brake, 0));
    /// motor.destroy();
    /// for p in [&mut rpwm, &mut lpwm] { p.done(); }
    /// for p in [&mut r_en, &mut l_en] { p.done(); }
    ///
    /// // Full forward without a ramp (255 counts), then coast: enables low
    /// // first, then RPWM back to 0.
    /// let mut rpwm = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0), P::set_duty_cycle(255), P::set_duty_cycle(0)]);
    /// let mut lpwm = Pwm::new(&[P::max_duty_cycle(255), P::set_duty_cycle(0)]);
    /// let en = [T::set(State::Low), T::set(State::High), T::set(State::Low)];
    /// let (mut r_en, mut l_en) = (Pin::new(&en), Pin::new(&en));
    /// let pins = Bts7960Pins { rpwm: rpwm.clone(), lpwm: lpwm.clone(), r_en: r_en.clone(), l_en: l_en.clone() };
    /// let mut motor = Bts7960::new(pins, Config { ramp_permille_per_ms: 0, rest: RestMode::Brake })?;
    /// motor.set_duty(1.0)?;
    /// motor.poll(0)?;
    /// motor.coast()?;
    /// assert_eq!(motor.output(), Output::Coast);
    /// motor.destroy();
    /// for p in [&mut rpwm, &mut lpwm] { p.done(); }
    /// for p in [&mut r_en, &mut l_en] { p.done(); }
    /// # Ok::<(), Box<dyn core::error::Error>>(())
    /// ```
    fn apply(
        &mut self,
        s: &mut Bts7960State,
        output: Output,
    ) -> Result<(), Error<R::Error, E::Error>> {
        match output {
            Output::Forward(permille) => {
                write_duty(&mut self.lpwm, &mut s.last_l, 0).map_err(Error::Pwm)?;
                let d = duty_counts(permille, s.max_r);
                write_duty(&mut self.rpwm, &mut s.last_r, d).map_err(Error::Pwm)?;
            }
            Output::Backward(permille) => {
                write_duty(&mut self.rpwm, &mut s.last_r, 0).map_err(Error::Pwm)?;
                let d = duty_counts(permille, s.max_l);
                write_duty(&mut self.lpwm, &mut s.last_l, d).map_err(Error::Pwm)?;
            }
            Output::Brake => {
                write_duty(&mut self.rpwm, &mut s.last_r, 0).map_err(Error::Pwm)?;
                write_duty(&mut self.lpwm, &mut s.last_l, 0).map_err(Error::Pwm)?;
            }
            Output::Coast => {
                write_pin(&mut self.r_en, &mut s.last_r_en, false).map_err(Error::Pin)?;
                write_pin(&mut self.l_en, &mut s.last_l_en, false).map_err(Error::Pin)?;
                write_duty(&mut self.rpwm, &mut s.last_r, 0).map_err(Error::Pwm)?;
                return write_duty(&mut self.lpwm, &mut s.last_l, 0).map_err(Error::Pwm);
            }
        }
        write_pin(&mut self.r_en, &mut s.last_r_en, true).map_err(Error::Pin)?;
        write_pin(&mut self.l_en, &mut s.last_l_en, true).map_err(Error::Pin)
    }
}

/// Conversion factors of the IS current sense.
///
/// ```
/// use drivers::dc_motor::bts7960::SenseConfig;
///
/// // The data sheet's test condition (k_ILIS = 8500 with R_IS = 1 kΩ) on a
/// // 5 V, 10-bit ADC: full scale is 5 V / 1 kΩ = 5 mA of sense current,
/// // 5 mA · 8500 = 42.5 A of load current.
/// let c = SenseConfig::DATASHEET_1K_5V;
/// assert_eq!(c.milliamps(1_023, 1_023), Some(42_500));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SenseConfig {
    /// Current sense ratio k_ILIS = I_L / I_IS (typ. 8500, data sheet item
    /// 4.4.6; calibrate per part for better than ±30 %).
    pub k_ilis: u16,
    /// Resistor from IS to ground, Ω.
    pub r_is_ohm: u16,
    /// ADC reference voltage, mV.
    pub vref_mv: u16,
}

impl SenseConfig {
    /// k_ILIS 8500 (typical), R_IS 1 kΩ (the data sheet's test resistor),
    /// 5 V ADC reference.
    ///
    /// ```
    /// use drivers::dc_motor::bts7960::SenseConfig;
    ///
    /// let c = SenseConfig::DATASHEET_1K_5V;
    /// assert_eq!((c.k_ilis, c.r_is_ohm, c.vref_mv), (8_500, 1_000, 5_000));
    /// ```
    pub const DATASHEET_1K_5V: Self = Self {
        k_ilis: 8_500,
        r_is_ohm: 1_000,
        vref_mv: 5_000,
    };

    fn is_valid(&self) -> bool {
        self.k_ilis != 0 && self.r_is_ohm != 0 && self.vref_mv != 0
    }

    /// Load current, mA, for a raw reading of a converter with this full
    /// scale, rounded to the nearest; `None` for a zero factor or full
    /// scale. A reading above full scale is taken as full scale; a result
    /// above `u32::MAX` saturates (it cannot, with k_ILIS and the reference
    /// in 16 bits and R_IS ≥ 1 Ω: at most 65,535 · 65,535 ≈ 4.3 · 10⁹).
    ///
    /// ```
    /// use drivers::dc_motor::bts7960::SenseConfig;
    ///
    /// // 12 bits over 3.3 V, R_IS 2.2 kΩ, 1000 counts:
    /// // 1000 · 3300 · 8500 / (4095 · 2200) = 28 050 000 000 / 9 009 000
    /// // = 3113.5 → 3114 mA.
    /// let c = SenseConfig { k_ilis: 8_500, r_is_ohm: 2_200, vref_mv: 3_300 };
    /// assert_eq!(c.milliamps(1_000, 4_095), Some(3_114));
    /// assert_eq!(c.milliamps(0, 4_095), Some(0));
    /// assert_eq!(c.milliamps(1, 0), None);
    /// ```
    pub fn milliamps(&self, raw: u16, full_scale: u16) -> Option<u32> {
        if !self.is_valid() || full_scale == 0 {
            return None;
        }
        let raw = raw.min(full_scale);
        // Three factors ≤ 65,535: under 2⁴⁸.
        let num = u64::from(raw) * u64::from(self.vref_mv) * u64::from(self.k_ilis);
        // Two factors ≤ 65,535: under 2³².
        let den = u32::from(full_scale) * u32::from(self.r_is_ohm);
        let (q, r) = suntracker_time::div_rem_u64(num, den)?;
        // Round half up: r ≥ den − r, without forming 2r.
        let q = if r >= den - r { q.saturating_add(1) } else { q };
        Some(u32::try_from(q).unwrap_or(u32::MAX))
    }
}

/// Current-sense errors.
///
/// ```
/// use drivers::dc_motor::bts7960::{CurrentSense, SenseConfig, SenseError};
/// use drivers::adc::AdcChannel;
///
/// struct Broken;
/// impl AdcChannel for Broken {
///     type Error = &'static str;
///     fn read_raw(&mut self) -> Result<u16, &'static str> { Err("timeout") }
///     fn full_scale(&self) -> u16 { 1_023 }
/// }
/// let mut sense = CurrentSense::new(Broken, SenseConfig::DATASHEET_1K_5V)?;
/// assert_eq!(sense.current_ma(), Err(SenseError::Adc("timeout")));
/// assert_eq!(SenseError::Adc("timeout").to_string(), "current sense ADC error: \"timeout\"");
/// # Ok::<(), SenseError<&'static str>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SenseError<E> {
    /// The conversion failed.
    Adc(E),
    /// A zero factor in the configuration, or an ADC with full scale 0.
    InvalidConfig,
}

impl<E: core::fmt::Debug> core::fmt::Display for SenseError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SenseError::Adc(e) => write!(f, "current sense ADC error: {e:?}"),
            SenseError::InvalidConfig => f.write_str("unusable current sense configuration"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for SenseError<E> {}

/// The load current of a BTS7960 bridge from its IS pin(s) on one ADC input.
///
/// ```
/// use drivers::dc_motor::bts7960::{CurrentSense, SenseConfig};
/// use drivers::adc::AdcChannel;
/// use core::convert::Infallible;
///
/// // 10 bits over 5 V, R_IS 1 kΩ: 48 counts = 48 · 5000 / 1023 = 234.6 mV,
/// // 0.2346 mA of sense current, · 8500 = 1994.1 → 1994 mA.
/// struct Reads48;
/// impl AdcChannel for Reads48 {
///     type Error = Infallible;
///     fn read_raw(&mut self) -> Result<u16, Infallible> { Ok(48) }
///     fn full_scale(&self) -> u16 { 1_023 }
/// }
/// let mut sense = CurrentSense::new(Reads48, SenseConfig::DATASHEET_1K_5V)?;
/// assert_eq!(sense.current_ma()?, 1_994);
/// let _adc: Reads48 = sense.destroy();
/// # Ok::<(), drivers::dc_motor::bts7960::SenseError<Infallible>>(())
/// ```
#[derive(Debug)]
pub struct CurrentSense<A> {
    adc: A,
    config: SenseConfig,
}

impl<A: AdcChannel> CurrentSense<A> {
    /// Checks the factors (all non-zero) and the ADC's full scale.
    ///
    /// ```
    /// use drivers::dc_motor::bts7960::{CurrentSense, SenseConfig, SenseError};
    /// use drivers::adc::AdcChannel;
    /// use core::convert::Infallible;
    ///
    /// struct Adc;
    /// impl AdcChannel for Adc {
    ///     type Error = Infallible;
    ///     fn read_raw(&mut self) -> Result<u16, Infallible> { Ok(0) }
    ///     fn full_scale(&self) -> u16 { 4_095 }
    /// }
    /// let open = SenseConfig { r_is_ohm: 0, ..SenseConfig::DATASHEET_1K_5V };
    /// assert!(matches!(CurrentSense::new(Adc, open), Err(SenseError::InvalidConfig)));
    /// ```
    pub fn new(adc: A, config: SenseConfig) -> Result<Self, SenseError<A::Error>> {
        if !config.is_valid() || adc.full_scale() == 0 {
            return Err(SenseError::InvalidConfig);
        }
        Ok(Self { adc, config })
    }

    /// One conversion, as load current in mA ([`SenseConfig::milliamps`]).
    ///
    /// ```
    /// use drivers::dc_motor::bts7960::{CurrentSense, SenseConfig};
    /// use drivers::adc::AdcChannel;
    /// use core::convert::Infallible;
    ///
    /// // Full scale of a 12-bit ADC at 3.3 V over 1 kΩ: 3.3 mA · 8500 = 28.05 A.
    /// struct Full;
    /// impl AdcChannel for Full {
    ///     type Error = Infallible;
    ///     fn read_raw(&mut self) -> Result<u16, Infallible> { Ok(4_095) }
    ///     fn full_scale(&self) -> u16 { 4_095 }
    /// }
    /// let config = SenseConfig { vref_mv: 3_300, ..SenseConfig::DATASHEET_1K_5V };
    /// let mut sense = CurrentSense::new(Full, config)?;
    /// assert_eq!(sense.current_ma()?, 28_050);
    /// # Ok::<(), drivers::dc_motor::bts7960::SenseError<Infallible>>(())
    /// ```
    pub fn current_ma(&mut self) -> Result<u32, SenseError<A::Error>> {
        let raw = self.adc.read_raw().map_err(SenseError::Adc)?;
        self.config
            .milliamps(raw, self.adc.full_scale())
            .ok_or(SenseError::InvalidConfig)
    }

    /// The configuration.
    ///
    /// ```
    /// use drivers::dc_motor::bts7960::{CurrentSense, SenseConfig};
    /// use drivers::adc::AdcChannel;
    /// use core::convert::Infallible;
    ///
    /// struct Adc;
    /// impl AdcChannel for Adc {
    ///     type Error = Infallible;
    ///     fn read_raw(&mut self) -> Result<u16, Infallible> { Ok(0) }
    ///     fn full_scale(&self) -> u16 { 1_023 }
    /// }
    /// let sense = CurrentSense::new(Adc, SenseConfig::DATASHEET_1K_5V)?;
    /// assert_eq!(sense.config().k_ilis, 8_500);
    /// # Ok::<(), drivers::dc_motor::bts7960::SenseError<Infallible>>(())
    /// ```
    pub fn config(&self) -> SenseConfig {
        self.config
    }

    /// Gives the ADC channel back.
    ///
    /// ```
    /// use drivers::dc_motor::bts7960::{CurrentSense, SenseConfig};
    /// use drivers::adc::AdcChannel;
    /// use core::convert::Infallible;
    ///
    /// struct Adc(u16);
    /// impl AdcChannel for Adc {
    ///     type Error = Infallible;
    ///     fn read_raw(&mut self) -> Result<u16, Infallible> { Ok(self.0) }
    ///     fn full_scale(&self) -> u16 { 1_023 }
    /// }
    /// let sense = CurrentSense::new(Adc(7), SenseConfig::DATASHEET_1K_5V)?;
    /// assert_eq!(sense.destroy().0, 7);
    /// # Ok::<(), drivers::dc_motor::bts7960::SenseError<Infallible>>(())
    /// ```
    pub fn destroy(self) -> A {
        self.adc
    }
}
