//! (being written by its helper; TEMPORARY body)
use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;

/// The five algorithms of Grena 2012.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// 1
    No1,
    /// 2
    No2,
    /// 3
    No3,
    /// 4
    No4,
    /// 5
    No5,
}

pub(crate) fn position<T: Float>(_inp: &Inputs<'_, T>, _v: Variant) -> SunPosition<T> {
    unimplemented!("grena2012")
}
