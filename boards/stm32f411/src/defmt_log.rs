//! The log over defmt (feature `defmt`, Cortex-M images): a [`Sink`] that
//! collects the text the firmware writes and hands each complete line to
//! `defmt::println!("{=str}", line)`, so the same events as the serial text
//! log go out as defmt frames — over RTT with `defmt-rtt`, read by a debug
//! probe (`probe-rs run` decodes them with the ELF's string table).
//!
//! `println!` rather than `info!`: defmt filters its levelled macros when
//! compiling, by the `DEFMT_LOG` environment variable, and keeps only
//! `error!` when it is not set (defmt-macros 1.x, `env_filter.rs`,
//! `LEVEL_WHEN_NOTHING_IS_SPECIFIED`): with `info!` an image built without
//! `DEFMT_LOG=info` would log nothing. These lines are the firmware's
//! output, not debug levels, so they are never filtered.
//!
//! defmt does not format on the target: a frame is an index into the
//! ELF's `.defmt` section plus the arguments, here the line's bytes. The
//! lines are built by the same writers as the serial log (`suntracker::log`,
//! `suntracker::console`), so the host shows the same text.
//!
//! RAM: one line buffer of [`LINE_BYTES`] bytes (plus defmt-rtt's own
//! channel buffer, 1 KiB by default). A longer line goes out in pieces of
//! that length; bytes that are not UTF-8 (the firmware writes ASCII) go as
//! a byte string (`{=[u8]:a}`).

use suntracker::log::Sink;

/// The longest line sent as one frame: longer than every log line and
/// console reply (the `status` line, the longest, is about 150 bytes).
pub const LINE_BYTES: usize = 192;

/// The log as defmt frames, one per line.
pub struct DefmtLog {
    line: [u8; LINE_BYTES],
    len: usize,
}

impl DefmtLog {
    /// A log with nothing pending.
    pub const fn new() -> Self {
        DefmtLog {
            line: [0; LINE_BYTES],
            len: 0,
        }
    }

    /// Sends what is collected as one frame (nothing when empty).
    fn send(&mut self) {
        let bytes = self.line.get(..self.len).unwrap_or(&[]);
        if !bytes.is_empty() {
            match core::str::from_utf8(bytes) {
                Ok(text) => defmt::println!("{=str}", text),
                Err(_) => defmt::println!("{=[u8]:a}", bytes),
            }
        }
        self.len = 0;
    }
}

impl Default for DefmtLog {
    fn default() -> Self {
        Self::new()
    }
}

impl Sink for DefmtLog {
    fn put(&mut self, bytes: &[u8]) {
        for &b in bytes {
            match b {
                b'\n' => self.send(),
                // Line ends of CRLF text: the frame is the line.
                b'\r' => {}
                _ => {
                    if self.len >= LINE_BYTES {
                        self.send();
                    }
                    if let Some(slot) = self.line.get_mut(self.len) {
                        *slot = b;
                        self.len += 1;
                    }
                }
            }
        }
    }
}
