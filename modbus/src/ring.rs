//! The queue between a UART's receive interrupt and the frame layer: each
//! byte with its arrival time in µs, stamped in the interrupt (the frame
//! layer tells frames apart by the silences between bytes, Modbus over
//! Serial Line §2.5.1.1, so a byte's time is the time it came, not the
//! time the loop took it).

/// A ring of `N` received bytes with their µs stamps. A full ring drops the
/// newest bytes (the frame they belong to then fails its CRC or its gap,
/// and the frame layer drops it: no reply, as for a frame with a parity
/// error). Stamps never go back: a stamp more than 2³¹ µs before the
/// latest (a clock that stepped back) is taken as the latest.
#[derive(Debug, Clone)]
pub struct StampedRing<const N: usize> {
    bytes: [u8; N],
    stamps_us: [u32; N],
    head: usize,
    len: usize,
    last_us: u32,
    received: u32,
    dropped: u32,
}

impl<const N: usize> Default for StampedRing<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> StampedRing<N> {
    /// An empty ring.
    pub const fn new() -> Self {
        StampedRing {
            bytes: [0; N],
            stamps_us: [0; N],
            head: 0,
            len: 0,
            last_us: 0,
            received: 0,
            dropped: 0,
        }
    }

    /// Queues `byte`, received at `t_us` (a wrapping µs clock).
    pub fn push(&mut self, byte: u8, t_us: u32) {
        self.received = self.received.wrapping_add(1);
        if t_us.wrapping_sub(self.last_us) < 1 << 31 {
            self.last_us = t_us;
        }
        if self.len < N {
            let at = (self.head + self.len) % N;
            if let (Some(b), Some(s)) = (self.bytes.get_mut(at), self.stamps_us.get_mut(at)) {
                *b = byte;
                *s = self.last_us;
                self.len += 1;
                return;
            }
        }
        self.dropped = self.dropped.wrapping_add(1);
    }

    /// Counts a byte the UART lost or received damaged (an overrun, a
    /// framing or parity error) with the dropped ones: its frame then
    /// misses a byte and the frame layer drops it.
    pub fn lose(&mut self) {
        self.received = self.received.wrapping_add(1);
        self.dropped = self.dropped.wrapping_add(1);
    }

    /// The oldest byte with its stamp.
    pub fn pop(&mut self) -> Option<(u8, u32)> {
        if self.len == 0 {
            return None;
        }
        let at = self.head;
        let popped = (*self.bytes.get(at)?, *self.stamps_us.get(at)?);
        self.head = (self.head + 1) % N;
        self.len -= 1;
        Some(popped)
    }

    /// Forgets the bytes waiting (a half-duplex line that starts sending:
    /// what came meanwhile was not for it, Modbus over Serial Line §2.5.1).
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// Bytes waiting.
    pub fn len(&self) -> usize {
        self.len
    }

    /// No byte waiting.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Bytes received since start (wrapping), kept or not.
    pub fn received(&self) -> u32 {
        self.received
    }

    /// Bytes the full ring dropped or the UART lost since start
    /// (wrapping).
    pub fn dropped(&self) -> u32 {
        self.dropped
    }
}

#[cfg(test)]
mod tests {
    use super::StampedRing;

    #[test]
    fn bytes_come_out_in_order_with_their_stamps() {
        let mut ring = StampedRing::<4>::new();
        ring.push(1, 10);
        ring.push(2, 20);
        assert_eq!(ring.pop(), Some((1, 10)));
        ring.push(3, 30);
        ring.push(4, 40);
        ring.push(5, 50);
        assert_eq!(ring.len(), 4);
        assert_eq!(ring.pop(), Some((2, 20)));
        assert_eq!(ring.pop(), Some((3, 30)));
        assert_eq!(ring.pop(), Some((4, 40)));
        assert_eq!(ring.pop(), Some((5, 50)));
        assert_eq!(ring.pop(), None);
        assert_eq!(ring.received(), 5);
        assert_eq!(ring.dropped(), 0);
    }

    #[test]
    fn a_full_ring_drops_the_newest_and_counts_them() {
        let mut ring = StampedRing::<2>::new();
        for (b, t) in [(1, 1), (2, 2), (3, 3), (4, 4)] {
            ring.push(b, t);
        }
        assert_eq!((ring.received(), ring.dropped(), ring.len()), (4, 2, 2));
        assert_eq!(ring.pop(), Some((1, 1)));
        assert_eq!(ring.pop(), Some((2, 2)));
        assert!(ring.is_empty());
    }

    #[test]
    fn stamps_never_go_back_and_wrap_forward() {
        let mut ring = StampedRing::<8>::new();
        // A clock counting from 0 up across the wrap of 2^32 µs.
        for (b, t) in [
            (1, 1_000_000_000),
            (2, 2_000_000_000),
            (3, 4_000_000_000),
            (4, 5),
        ] {
            ring.push(b, t);
        }
        // 294,967,301 µs back from the latest: kept at the latest.
        ring.push(5, 4_000_000_000);
        let popped: [Option<(u8, u32)>; 5] = core::array::from_fn(|_| ring.pop());
        assert_eq!(
            popped,
            [
                Some((1, 1_000_000_000)),
                Some((2, 2_000_000_000)),
                Some((3, 4_000_000_000)),
                Some((4, 5)),
                Some((5, 5)),
            ]
        );
    }

    #[test]
    fn clear_forgets_what_waits_but_not_the_counts() {
        let mut ring = StampedRing::<4>::new();
        ring.push(1, 1);
        ring.push(2, 2);
        ring.clear();
        assert_eq!(ring.pop(), None);
        ring.push(3, 3);
        assert_eq!(ring.pop(), Some((3, 3)));
        assert_eq!(ring.received(), 3);
    }
}
