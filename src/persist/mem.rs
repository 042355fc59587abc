//! Storage in RAM for hosts, tests and the simulation: [`MemStorage`], with
//! a write that can be cut short as a power cut would.

use crate::ports::Storage;

/// Storage in RAM (tests, simulation): `N` bytes, erased to 0xFF.
#[derive(Debug, Clone)]
pub struct MemStorage<const N: usize> {
    /// The bytes.
    pub bytes: [u8; N],
    /// When `Some(k)`, the next write stops after `k` bytes and fails, as a
    /// power cut would (then the budget is cleared).
    pub tear_after: Option<usize>,
}

/// Errors of [`MemStorage`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MemError {
    /// Access beyond the end.
    OutOfRange,
    /// The write was cut short.
    Torn,
}

impl<const N: usize> MemStorage<N> {
    /// Erased storage.
    pub fn new() -> Self {
        MemStorage {
            bytes: [0xFF; N],
            tear_after: None,
        }
    }
}

impl<const N: usize> Default for MemStorage<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Storage for MemStorage<N> {
    type Error = MemError;
    fn capacity(&self) -> usize {
        N
    }
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), MemError> {
        let end = offset.checked_add(buf.len()).ok_or(MemError::OutOfRange)?;
        let src = self.bytes.get(offset..end).ok_or(MemError::OutOfRange)?;
        buf.copy_from_slice(src);
        Ok(())
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), MemError> {
        let end = offset.checked_add(data.len()).ok_or(MemError::OutOfRange)?;
        let dst = self
            .bytes
            .get_mut(offset..end)
            .ok_or(MemError::OutOfRange)?;
        match self.tear_after.take() {
            Some(k) if k < data.len() => {
                if let (Some(d), Some(s)) = (dst.get_mut(..k), data.get(..k)) {
                    d.copy_from_slice(s);
                }
                Err(MemError::Torn)
            }
            _ => {
                dst.copy_from_slice(data);
                Ok(())
            }
        }
    }
}
