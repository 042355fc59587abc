//! The crate's ADC trait through the scripted test channel, and the
//! raw-count → millivolt conversion against hand-computed values.

mod common;

use common::{AdcError, ScriptedAdc};
use drivers::adc::{millivolts, AdcChannel};

#[test]
fn scripted_channel_returns_its_readings_in_order() {
    let mut adc = ScriptedAdc::new(1_023, &[Ok(0), Ok(1_023), Err(AdcError)]);
    assert_eq!(adc.full_scale(), 1_023);
    assert_eq!(adc.read_raw(), Ok(0));
    // Through `&mut` (the blanket impl) the same queue is read.
    let r = &mut adc;
    assert_eq!(r.read_raw(), Ok(1_023));
    assert_eq!(adc.read_raw(), Err(AdcError));
    adc.done();
}

#[test]
fn millivolts_by_hand() {
    // 10 bits over 5 V: 1 count = 5000 / 1023 = 4.887 mV.
    assert_eq!(millivolts(0, 1_023, 5_000), Some(0));
    assert_eq!(millivolts(1, 1_023, 5_000), Some(4));
    assert_eq!(millivolts(1_023, 1_023, 5_000), Some(5_000));
    // 12 bits over 3.3 V: 2048 · 3300 / 4095 = 1650.4 → 1650.
    assert_eq!(millivolts(2_048, 4_095, 3_300), Some(1_650));
    // The largest inputs: 65,535 · 65,535 / 65,535 = 65,535, no overflow.
    assert_eq!(millivolts(u16::MAX, u16::MAX, u16::MAX), Some(65_535));
    // Above full scale: limited; no full scale: refused.
    assert_eq!(millivolts(1_024, 1_023, 5_000), Some(5_000));
    assert_eq!(millivolts(0, 0, 5_000), None);
}
