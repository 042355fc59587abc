//! (being written by its helper; TEMPORARY body)
use crate::algorithm::Inputs;
use crate::float::Float;
use crate::position::SunPosition;

pub(crate) fn position<T: Float>(_inp: &Inputs<'_, T>) -> SunPosition<T> {
    unimplemented!("textbook")
}
