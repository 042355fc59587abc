//! Unit complex numbers and the small tables of them that the periodic
//! terms (Earth, Table A4.2) and the nutation (Table A4.3) are summed from.

use crate::float::Float;

/// A unit complex number `cos x + i sin x`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Rot<T> {
    pub c: T,
    pub s: T,
}

impl<T: Float> Rot<T> {
    pub const ONE: Rot<T> = Rot {
        c: T::ONE,
        s: T::ZERO,
    };

    /// e^{i x} for `x` in radians.
    #[inline(always)]
    pub fn of_rad(x: T) -> Rot<T> {
        let (s, c) = x.sin_cos();
        Rot { c, s }
    }

    /// e^{i (x + y)} from e^{i x} and e^{i y} (the addition theorem).
    #[inline(always)]
    pub fn mul(self, o: Rot<T>) -> Rot<T> {
        Rot {
            c: self.c * o.c - self.s * o.s,
            s: self.s * o.c + self.c * o.s,
        }
    }

    /// e^{−i x} from e^{i x}.
    #[inline(always)]
    pub fn conj(self) -> Rot<T> {
        Rot {
            c: self.c,
            s: -self.s,
        }
    }
}

/// `N` rotations as two arrays (cosines and sines), indexed by `u8`.
///
/// When `N` is a power of two the index is masked with `N − 1`: in range by
/// construction, so the hot loops carry neither a bounds check nor a panic
/// path (callers check at compile time that their indices are below `N`).
/// Otherwise (the `f32` tables, kept at their exact size for the stack of
/// small targets) a look-up is checked and an index out of range reads 1.
pub(super) struct RotTable<T, const N: usize> {
    c: [T; N],
    s: [T; N],
}

impl<T: Float, const N: usize> RotTable<T, N> {
    /// All slots 0 (not rotations; every slot a caller reads, it writes first).
    #[inline(always)]
    pub fn zeroed() -> Self {
        RotTable {
            c: [T::ZERO; N],
            s: [T::ZERO; N],
        }
    }

    /// Slot `i`.
    #[inline(always)]
    pub fn get(&self, i: u8) -> Rot<T> {
        let i = usize::from(i);
        if N.is_power_of_two() {
            Rot {
                c: self.c[i & (N - 1)],
                s: self.s[i & (N - 1)],
            }
        } else {
            match (self.c.get(i), self.s.get(i)) {
                (Some(&c), Some(&s)) => Rot { c, s },
                _ => Rot::ONE,
            }
        }
    }

    /// Stores slot `i` (ignored out of range when `N` is not a power of two).
    #[inline(always)]
    pub fn set(&mut self, i: u8, v: Rot<T>) {
        let i = usize::from(i);
        if N.is_power_of_two() {
            self.c[i & (N - 1)] = v.c;
            self.s[i & (N - 1)] = v.s;
        } else if let (Some(c), Some(s)) = (self.c.get_mut(i), self.s.get_mut(i)) {
            *c = v.c;
            *s = v.s;
        }
    }
}
