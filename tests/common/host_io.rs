//! The serial ports of the firmware-loop tests (`firmware_app`,
//! `firmware_console`): a UART the test fills and the firmware reads, and a
//! log sink that keeps what the firmware wrote; and the sink of the
//! console and log-line tests.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::convert::Infallible;
use std::rc::Rc;

use suntracker::log::Sink;

/// A receive-only UART: bytes the test queued, read by the firmware.
#[derive(Default, Clone)]
pub struct Uart(pub Rc<RefCell<VecDeque<u8>>>);

impl embedded_io::ErrorType for Uart {
    type Error = Infallible;
}
impl embedded_io::Read for Uart {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let mut q = self.0.borrow_mut();
        let n = buf.len().min(q.len());
        for b in buf.iter_mut().take(n) {
            *b = q.pop_front().unwrap_or(0);
        }
        Ok(n)
    }
}
impl embedded_io::ReadReady for Uart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(!self.0.borrow().is_empty())
    }
}

/// A sink that keeps what is written until the test takes it (the
/// console's replies, log lines).
#[derive(Default)]
pub struct Buf(pub Vec<u8>);

impl Sink for Buf {
    fn put(&mut self, bytes: &[u8]) {
        self.0.extend_from_slice(bytes);
    }
}

impl Buf {
    /// What was written since the last take, as text.
    pub fn take(&mut self) -> String {
        String::from_utf8(std::mem::take(&mut self.0)).expect("ASCII output")
    }
}

/// The log serial: everything written, kept.
#[derive(Default, Clone)]
pub struct Log(pub Rc<RefCell<Vec<u8>>>);

impl Sink for Log {
    fn put(&mut self, bytes: &[u8]) {
        self.0.borrow_mut().extend_from_slice(bytes);
    }
}
