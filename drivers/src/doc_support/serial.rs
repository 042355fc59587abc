// Test support for the examples of the GPS reader and the Modbus master in
// src/gps/reader.rs and src/tilt/ (pulled in with `include!`, not a module of
// the crate). embedded-hal-mock covers embedded-hal but not embedded-io, so
// this is a scripted serial port: `read` hands out the queued bytes, at
// most `chunk` per call (0 at the end: end of stream), `read_ready` says
// whether any are left, and every byte written is kept for the example to
// compare with the bytes the protocol prescribes.

use std::collections::VecDeque;
use std::convert::Infallible;

/// A serial port that replays `rx` and records what is written.
pub struct ScriptedSerial {
    rx: VecDeque<u8>,
    chunk: usize,
    written: Vec<u8>,
    flushes: usize,
}

impl ScriptedSerial {
    /// A port that will receive `rx`, handed out `chunk` bytes per `read`.
    pub fn new(rx: &[u8], chunk: usize) -> Self {
        Self {
            rx: rx.iter().copied().collect(),
            chunk: chunk.max(1),
            written: Vec::new(),
            flushes: 0,
        }
    }

    /// Every byte written so far.
    pub fn written(&self) -> &[u8] {
        &self.written
    }

    /// How often `flush` was called.
    pub fn flushes(&self) -> usize {
        self.flushes
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.rx.len()
    }
}

impl embedded_io::ErrorType for ScriptedSerial {
    type Error = Infallible;
}

impl embedded_io::Read for ScriptedSerial {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let n = buf.len().min(self.chunk).min(self.rx.len());
        for (slot, byte) in buf.iter_mut().zip(self.rx.drain(..n)) {
            *slot = byte;
        }
        Ok(n)
    }
}

impl embedded_io::ReadReady for ScriptedSerial {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(!self.rx.is_empty())
    }
}

impl embedded_io::Write for ScriptedSerial {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        self.written.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        self.flushes += 1;
        Ok(())
    }
}
