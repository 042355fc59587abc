//! Byte copies without a panic path.
//!
//! `<[u8]>::copy_from_slice` checks that both slices have the same length
//! and panics when they do not. Where the optimiser inlines it with lengths
//! it can see, the check goes; where it does not (code built at opt-level
//! "z"), the call keeps the panic in the image. The firmware copies with
//! [`copy_prefix`] instead.

/// Copies the first `min(dst.len(), src.len())` bytes of `src` into `dst`;
/// returns how many it copied.
pub(crate) fn copy_prefix(dst: &mut [u8], src: &[u8]) -> usize {
    let mut n = 0;
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
        n += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::copy_prefix;

    #[test]
    fn copies_the_shorter_length() {
        let mut dst = [0u8; 4];
        assert_eq!(copy_prefix(&mut dst, b"ab"), 2);
        assert_eq!(dst, *b"ab\0\0");
        assert_eq!(copy_prefix(&mut dst, b"wxyz!"), 4);
        assert_eq!(dst, *b"wxyz");
        assert_eq!(copy_prefix(&mut [], b"abc"), 0);
    }
}
