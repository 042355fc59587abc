//! (being written by its helper; TEMPORARY body)
use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;

/// PSA coefficient sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// 2001
    Psa2001,
    /// 2020
    Psa2020,
    /// li-2022 corrected
    Modified,
    /// li-2022 as printed
    ModifiedAsPrinted,
}

pub(crate) fn position<T: Float>(_inp: &Inputs<'_, T>, _v: Variant) -> SunPosition<T> {
    unimplemented!("psa")
}
