//! ΔT = TT − UT1 (being written).
use crate::float::Float;
use crate::time::UtcTime;

/// ΔT in seconds for an instant (TEMPORARY constant until the model lands).
pub fn estimate_s<T: Float>(_time: &UtcTime) -> T {
    T::from_f64(69.2)
}
