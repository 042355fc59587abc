//! The board's serial port: lines in, console commands out.
//!
//! The port is opened 8N1 at the given baud rate with the `serialport`
//! crate (every image's log and console UART runs at 115200 8N1). Bytes are
//! cut into lines at `\n` (a `\r` before it is dropped; bytes that are not
//! UTF-8 are shown as U+FFFD), each handed to a [`Lines`] handler as it
//! completes.
//!
//! With `--send`, after the port is opened the session first waits up to
//! `settle` seconds, or until the board's `boot` line: opening the port of
//! an Arduino Uno or Mega pulls DTR, which resets the board through its
//! auto-reset capacitor, and the bootloader then listens for a new sketch
//! before the image starts (Arduino, "Arduino Uno Rev3" hardware notes,
//! section "Automatic (Software) Reset"); a line sent in that time is lost.
//! Then each line is written with `\n` and the replies are awaited: the
//! first line starting with `ok` or `error` within `reply_timeout`, then
//! every further reply line until none has come for [`REPLY_GAP`] (`help`,
//! `get` and `faults` answer with several lines). Log lines that come in
//! between are handled like any other.

use std::io::{ErrorKind, Read, Write};
use std::time::{Duration, Instant};

use super::board_log::{self, Line};

/// How long after a reply line the session waits for another one before it
/// takes the reply as complete. At 115200 baud a line of 100 characters
/// takes 9 ms; the console answers within one pass of the image's main
/// loop.
pub const REPLY_GAP: Duration = Duration::from_millis(300);

/// The longest line kept whole; longer runs of bytes without a `\n` are
/// handed on in pieces of this size. The longest line an image writes, the
/// status line, has about 150 characters.
const MAX_LINE: usize = 4096;

/// How long one read of the port waits for bytes.
const READ_POLL: Duration = Duration::from_millis(20);

/// What the session does with the lines.
pub trait Lines {
    /// A line read from the board (without its line end).
    fn line(&mut self, text: &str) -> Result<Line, String>;
    /// A line written to the board (without its line end).
    fn sent(&mut self, text: &str) -> Result<(), String>;
}

/// The session's settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Session {
    pub path: String,
    pub baud: u32,
    /// Console lines to send, in order.
    pub send: Vec<String>,
    /// Stop this long after opening the port; `None`: after the replies
    /// when lines are sent, else when the port closes.
    pub seconds: Option<f64>,
    /// Longest wait for the `boot` line before the first line is sent.
    pub settle_s: f64,
    /// Longest wait for the first reply to a sent line.
    pub reply_timeout_s: f64,
}

/// How one sent line was answered.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Answer {
    /// Reply lines came and all started with `ok`.
    Ok,
    /// A reply line started with `error`: the first such line.
    Refused(String),
    /// No reply line within the timeout.
    NoReply,
}

/// Lines from a byte stream.
struct LineReader<R> {
    input: R,
    buf: Vec<u8>,
}

impl<R: Read> LineReader<R> {
    /// The next complete line, or `None` when `until` passes first. A read
    /// error other than a timeout ends the session.
    fn next(&mut self, until: Option<Instant>) -> Result<Option<String>, std::io::Error> {
        let mut chunk = [0u8; 256];
        loop {
            if let Some(i) = self.buf.iter().position(|&b| b == b'\n') {
                let mut line: Vec<u8> = self.buf.drain(..=i).collect();
                line.pop();
                if line.last() == Some(&b'\r') {
                    line.pop();
                }
                return Ok(Some(String::from_utf8_lossy(&line).into_owned()));
            }
            if self.buf.len() >= MAX_LINE {
                // Noise without line ends (a wrong baud rate): shown in
                // pieces rather than held without end.
                let piece: Vec<u8> = self.buf.drain(..MAX_LINE).collect();
                return Ok(Some(String::from_utf8_lossy(&piece).into_owned()));
            }
            if until.is_some_and(|t| Instant::now() >= t) {
                return Ok(None);
            }
            match self.input.read(&mut chunk) {
                Ok(0) => {
                    return Err(std::io::Error::new(
                        ErrorKind::UnexpectedEof,
                        "the port closed",
                    ))
                }
                Ok(n) => self.buf.extend_from_slice(&chunk[..n]),
                Err(e) if matches!(e.kind(), ErrorKind::TimedOut | ErrorKind::WouldBlock) => {}
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
    }
}

fn seconds(s: f64) -> Duration {
    Duration::from_secs_f64(s.clamp(0.0, 1e9))
}

/// How a session ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ended {
    /// How each sent line was answered, in order (fewer when the session
    /// was cut short).
    pub answers: Vec<Answer>,
    /// Why the session was cut short: the port failed or a line could not
    /// be handled (`None`: it ran to its end).
    pub error: Option<String>,
}

/// Runs a session on the port. `Err` when the port cannot be opened;
/// otherwise what was answered, and the error that cut the session short
/// if one did (what was read until then has been handled).
pub fn run(s: &Session, lines: &mut dyn Lines) -> Result<Ended, String> {
    let port = serialport::new(&s.path, s.baud)
        .data_bits(serialport::DataBits::Eight)
        .parity(serialport::Parity::None)
        .stop_bits(serialport::StopBits::One)
        .flow_control(serialport::FlowControl::None)
        .timeout(READ_POLL)
        .open()
        .map_err(|e| format!("--port {}: {e}", s.path))?;
    let mut writer = port
        .try_clone()
        .map_err(|e| format!("--port {}: {e}", s.path))?;
    let mut reader = LineReader {
        input: port,
        buf: Vec::new(),
    };
    let mut answers = Vec::new();
    let error = exchange(s, &mut reader, &mut writer, lines, &mut answers).err();
    Ok(Ended { answers, error })
}

/// The session after the port is open: settle, send, follow.
fn exchange(
    s: &Session,
    reader: &mut LineReader<Box<dyn serialport::SerialPort>>,
    writer: &mut Box<dyn serialport::SerialPort>,
    lines: &mut dyn Lines,
    answers: &mut Vec<Answer>,
) -> Result<(), String> {
    let start = Instant::now();
    let end = s.seconds.map(|x| start + seconds(x));
    let read_err = |e: std::io::Error| format!("--port {}: read: {e}", s.path);
    if !s.send.is_empty() {
        // Wait for the board to start (or the settle time to pass).
        let settle = start + seconds(s.settle_s);
        while let Some(text) = reader.next(Some(settle)).map_err(read_err)? {
            if matches!(lines.line(&text)?, Line::Boot { .. }) {
                break;
            }
        }
    }
    for cmd in &s.send {
        writer
            .write_all(format!("{cmd}\n").as_bytes())
            .and_then(|()| writer.flush())
            .map_err(|e| format!("--port {}: write: {e}", s.path))?;
        lines.sent(cmd)?;
        let mut answer = Answer::NoReply;
        let mut until = Instant::now() + seconds(s.reply_timeout_s);
        while let Some(text) = reader.next(Some(until)).map_err(read_err)? {
            let line = lines.line(&text)?;
            if board_log::is_reply(&line) {
                match (&answer, line) {
                    (Answer::Refused(_), _) => {}
                    (_, Line::Reply { ok: false, .. }) => answer = Answer::Refused(text),
                    _ => answer = Answer::Ok,
                }
                until = Instant::now() + REPLY_GAP;
            }
        }
        answers.push(answer);
    }
    if s.send.is_empty() || end.is_some() {
        // Follow the log until the end time, or until the port fails.
        while let Some(text) = reader.next(end).map_err(read_err)? {
            lines.line(&text)?;
        }
    }
    Ok(())
}
