//! BTS7960 / IBT-2: exact PWM and enable writes, written from the module
//! table (forward: RPWM = PWM, LPWM = 0; backward: the mirror; brake: both
//! 0 enabled; coast: R_EN = L_EN = low) and duty = round(‰ · max / 1000);
//! the current sense against hand-computed values of
//! I_L = raw · vref · k_ILIS / (full_scale · R_IS).

mod common;

use common::{AdcError, ScriptedAdc};
use drivers::dc_motor::bts7960::{Bts7960, Bts7960Pins, CurrentSense, SenseConfig, SenseError};
use drivers::dc_motor::{Config, Direction, Error, Output, RestMode};
use embedded_hal_mock::eh1::digital::{Mock as Pin, State, Transaction as T};
use embedded_hal_mock::eh1::pwm::{Mock as Pwm, Transaction as P};
use embedded_hal_mock::eh1::MockError;

use State::{High as H, Low as L};

struct Rig {
    rpwm: Pwm,
    lpwm: Pwm,
    r_en: Pin,
    l_en: Pin,
}

/// Mocks expecting `max` read once, then these duties and levels.
fn rig(max: u16, r: &[u16], l: &[u16], en: &[State]) -> Rig {
    let pwm = |d: &[u16]| {
        let mut t = vec![P::max_duty_cycle(max)];
        t.extend(d.iter().map(|&x| P::set_duty_cycle(x)));
        Pwm::new(&t)
    };
    let pin = |s: &[State]| Pin::new(&s.iter().map(|&x| T::set(x)).collect::<Vec<_>>());
    Rig {
        rpwm: pwm(r),
        lpwm: pwm(l),
        r_en: pin(en),
        l_en: pin(en),
    }
}

impl Rig {
    fn pins(&self) -> Bts7960Pins<Pwm, Pwm, Pin> {
        Bts7960Pins {
            rpwm: self.rpwm.clone(),
            lpwm: self.lpwm.clone(),
            r_en: self.r_en.clone(),
            l_en: self.l_en.clone(),
        }
    }

    /// The motor on these mocks; `new` must succeed.
    fn motor(&self, ramp_permille_per_ms: u16, rest: RestMode) -> Bts7960<Pwm, Pwm, Pin> {
        let config = Config {
            ramp_permille_per_ms,
            rest,
        };
        Bts7960::new(self.pins(), config).unwrap()
    }

    fn done(mut self) {
        self.rpwm.done();
        self.lpwm.done();
        self.r_en.done();
        self.l_en.done();
    }
}

#[test]
fn soft_start_and_soft_stop_to_brake() {
    // Max duty 1000 (one count per ‰), 4 ‰/ms, rest = brake.
    // Start: 0 → 600 ‰: +400 after 100 ms, +200 (capped at the target) after
    // another 100 ms. Stop: 600 → 0: −400, then −200 to 0 = brake (both
    // inputs 0, enables stay high).
    let r = rig(1_000, &[0, 400, 600, 200, 0], &[0], &[L, H]);
    let mut m = r.motor(4, RestMode::Brake);
    m.set_permille(Direction::Forward, 600).unwrap();
    assert_eq!(m.poll(1_000).unwrap(), Output::Coast);
    assert_eq!(m.poll(1_100).unwrap(), Output::Forward(400));
    assert_eq!(m.poll(1_200).unwrap(), Output::Forward(600));
    assert_eq!(m.poll(1_300).unwrap(), Output::Forward(600));
    m.set_duty(0.0).unwrap();
    assert_eq!(m.poll(1_400).unwrap(), Output::Forward(600)); // clock restarted
    assert_eq!(m.poll(1_500).unwrap(), Output::Forward(200));
    assert_eq!(m.poll(1_600).unwrap(), Output::Brake);
    assert_eq!(m.duty_permille(), 0);
    m.destroy();
    r.done();
}

#[test]
fn reversal_in_one_step_clears_the_old_side_first() {
    // No ramp, 8-bit channels: +300 ‰ → round(76.5) = 77 on RPWM; then
    // −300 ‰: RPWM to 0 before LPWM to 77, enables untouched.
    let r = rig(255, &[0, 77, 0], &[0, 77], &[L, H]);
    let mut m = r.motor(0, RestMode::Coast);
    m.set_duty(0.3).unwrap();
    assert_eq!(m.poll(0).unwrap(), Output::Forward(300));
    m.set_duty(-0.3).unwrap();
    assert_eq!(m.poll(1).unwrap(), Output::Backward(300));
    m.destroy();
    r.done();
}

#[test]
fn ramp_down_to_coast_disables_before_clearing() {
    // 12-bit channels (max 4095), 10 ‰/ms, rest = coast. Backward 50 %:
    // 500 ‰ → round(2047.5) = 2048 after 50 ms. Stop: 0 after another
    // 50 ms: enables low first, then LPWM 0.
    let r = rig(4_095, &[0], &[0, 2_048, 0], &[L, H, L]);
    let mut m = r.motor(10, RestMode::Coast);
    m.set_permille(Direction::Backward, 500).unwrap();
    m.poll(0).unwrap();
    assert_eq!(m.poll(50).unwrap(), Output::Backward(500));
    m.set_permille(Direction::Forward, 0).unwrap();
    m.poll(60).unwrap();
    assert_eq!(m.poll(110).unwrap(), Output::Coast);
    m.destroy();
    r.done();
}

#[test]
fn brake_and_coast_act_at_once_and_reset_the_ramp() {
    // No ramp: forward full (1000 counts), brake (RPWM 0, enables stay
    // high), coast (enables low; inputs already 0).
    let r = rig(1_000, &[0, 1_000, 0], &[0], &[L, H, L]);
    let mut m = r.motor(0, RestMode::Coast);
    m.set_duty(1.0).unwrap();
    m.poll(0).unwrap();
    m.brake().unwrap();
    assert_eq!(
        (m.output(), m.duty_permille(), m.target_permille()),
        (Output::Brake, 0, 0)
    );
    assert_eq!(m.poll(5).unwrap(), Output::Brake); // the ramp does not undo it
    m.coast().unwrap();
    assert_eq!(m.output(), Output::Coast);
    m.destroy();
    r.done();
}

#[test]
fn failed_write_is_repeated_by_the_next_poll() {
    // Forward 100 ‰ on 1000 counts: the RPWM write fails once; the next
    // poll (ramp settled) writes it again, then the enables.
    let err = MockError::Io(std::io::ErrorKind::Other);
    let en = [T::set(L), T::set(H)];
    let r = Rig {
        rpwm: Pwm::new(&[
            P::max_duty_cycle(1_000),
            P::set_duty_cycle(0),
            P::set_duty_cycle(100).with_error(err.clone()),
            P::set_duty_cycle(100),
        ]),
        lpwm: Pwm::new(&[P::max_duty_cycle(1_000), P::set_duty_cycle(0)]),
        r_en: Pin::new(&en),
        l_en: Pin::new(&en),
    };
    let mut m = r.motor(0, RestMode::Coast);
    m.set_duty(0.1).unwrap();
    assert_eq!(m.poll(0), Err(Error::Pwm(err)));
    assert_eq!(m.poll(1).unwrap(), Output::Forward(100));
    assert_eq!(m.poll(2).unwrap(), Output::Forward(100)); // nothing more
    m.destroy();
    r.done();
}

#[test]
fn zero_max_duty_is_refused_before_any_write() {
    let r = Rig {
        rpwm: Pwm::new(&[P::max_duty_cycle(255)]),
        lpwm: Pwm::new(&[P::max_duty_cycle(0)]),
        r_en: Pin::new(&[]),
        l_en: Pin::new(&[]),
    };
    let config = Config {
        ramp_permille_per_ms: 1,
        rest: RestMode::Brake,
    };
    assert!(matches!(
        Bts7960::new(r.pins(), config),
        Err(Error::InvalidConfig)
    ));
    r.done();
}

#[test]
fn current_sense_by_hand() {
    // 10-bit ADC over 5 V, R_IS = 1 kΩ, k_ILIS = 8500 (BTS7960 data sheet
    // item 4.4.6, typical):
    //   205 counts: 205 · 5000 · 8500 / (1023 · 1000) = 8 712 500 000 / 1 023 000
    //             = 8516.6 → 8517 mA;
    //   1 count:    42 500 000 / 1 023 000 = 41.54 → 42 mA;
    //   0 counts:   0 mA.
    let adc = ScriptedAdc::new(1_023, &[Ok(205), Ok(1), Ok(0), Err(AdcError)]);
    let mut s = CurrentSense::new(adc.clone(), SenseConfig::DATASHEET_1K_5V).unwrap();
    assert_eq!(s.current_ma(), Ok(8_517));
    assert_eq!(s.current_ma(), Ok(42));
    assert_eq!(s.current_ma(), Ok(0));
    assert_eq!(s.current_ma(), Err(SenseError::Adc(AdcError)));
    s.destroy();
    adc.done();
}

#[test]
fn current_sense_extremes_cannot_overflow() {
    // Every factor at 65 535 and R_IS = 1 Ω:
    // 65 535³ / 65 535 = 65 535² = 4 294 836 225 mA, still a u32.
    let c = SenseConfig {
        k_ilis: u16::MAX,
        r_is_ohm: 1,
        vref_mv: u16::MAX,
    };
    assert_eq!(c.milliamps(u16::MAX, u16::MAX), Some(4_294_836_225));
    // A reading above full scale counts as full scale: 5000 · 8500 / 1000.
    assert_eq!(
        SenseConfig::DATASHEET_1K_5V.milliamps(u16::MAX, 1_023),
        Some(42_500)
    );
    // Zero factors are refused, by `new` and by the conversion.
    let zero_k = SenseConfig {
        k_ilis: 0,
        ..SenseConfig::DATASHEET_1K_5V
    };
    assert_eq!(zero_k.milliamps(1, 1_023), None);
    let adc = ScriptedAdc::new(1_023, &[]);
    assert!(matches!(
        CurrentSense::new(adc.clone(), zero_k),
        Err(SenseError::InvalidConfig)
    ));
    let no_scale = ScriptedAdc::new(0, &[]);
    assert!(matches!(
        CurrentSense::new(no_scale, SenseConfig::DATASHEET_1K_5V),
        Err(SenseError::InvalidConfig)
    ));
    adc.done();
}
