//! A Modbus RTU master on the ATmega2560's RS-485 port (USART2: RXD2 PH0,
//! TXD2 PH1; the transceiver's driver enable DE, /RE tied to it, on PH3).
//!
//! It writes request frames onto the bus at scheduled emulated instants,
//! collects the reply bytes with the CPU cycle each left the image at, and
//! watches DE; at the end of each transaction it checks what the pins did
//! against the serial line specification (Modbus over Serial Line V1.02,
//! §2.5.1.1: frames separated by a silence of at least 3.5 characters, the
//! characters of a frame back to back; §2.3/§3.3.2: half duplex, the
//! slave's driver on only while it sends).
//!
//! CRC-16 (§6.2.2, Appendix B): polynomial 0xA001 (0x8005 reflected),
//! initial value 0xFFFF, no final XOR, low byte first on the wire; written
//! here from the spec, independent of the firmware's `suntracker-modbus`.
//!
//! **simavr's line.** A byte the image writes to UDR2 is raised on the
//! USART's output IRQ at the write ([`crate::sim::Sim::uart_take_timed`]);
//! simavr has no transmit double buffer: a "pump" ticks every character
//! time (`cycles_per_byte`, 11 bits at 8E1: 9,152 cycles at 19,200 baud,
//! 16 MHz) from the first write of a burst, and raises UDRE (and TXC) at a
//! tick when nothing is left. So a frame sent from the UDRE interrupt
//! occupies slots `[w0 + k·C, w0 + (k+1)·C)` from its first write `w0`:
//! byte `k` is on time (no gap) when written before its slot ends, and the
//! last byte has left the shift register at `w0 + n·C`, the instant simavr
//! raises TXC. A request's bytes are handed to simavr's receive FIFO at
//! one cycle `t0`; it raises RXC for byte `k` at `t0 + (k+1)·C`: the
//! request's last byte has arrived at `t0 + n·C`.

use crate::sim::Sim;

/// The USART of the bus.
pub const UART: char = '2';
/// DE (and /RE) of the transceiver: PH3 (Mega D6), active high.
pub const DE_PIN: (char, u8) = ('H', 3);
/// UCSR2A's data address (RXC2, TXC2, UDRE2, U2X2; datasheet §33).
pub const UCSR2A: u16 = 0xD0;
/// CPU cycles a transaction waits for the first byte of a reply (1 s at
/// 16 MHz: the order of a SCADA's response time-out).
pub const REPLY_TIMEOUT_CYCLES: u64 = 16_000_000;
/// Characters of silence after a reply's last byte that end it (the spec's
/// 3.5, rounded up).
pub const END_OF_FRAME_CHARS: u64 = 4;
/// The longest SunSpec model chain a walk follows.
const WALK_MAX_MODELS: usize = 16;

/// CRC-16 of Modbus RTU over `bytes` (see the module notes): the value
/// whose low byte goes first on the wire.
pub fn crc16(bytes: &[u8]) -> u16 {
    let mut crc = 0xFFFFu16;
    for &b in bytes {
        crc ^= u16::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    crc
}

/// `unit`, `pdu` and the CRC, low byte first.
pub fn frame(unit: u8, pdu: &[u8]) -> Vec<u8> {
    let mut f = Vec::with_capacity(pdu.len() + 3);
    f.push(unit);
    f.extend_from_slice(pdu);
    let crc = crc16(&f);
    f.extend_from_slice(&crc.to_le_bytes());
    f
}

/// Whether `f` (address, PDU, CRC) carries a correct CRC.
pub fn crc_ok(f: &[u8]) -> bool {
    f.len() >= 4 && {
        let (body, crc) = f.split_at(f.len() - 2);
        crc16(body).to_le_bytes() == [crc[0], crc[1]]
    }
}

/// Read Holding Registers (03): `qty` registers from `addr`.
pub fn read_holding(unit: u8, addr: u16, qty: u16) -> Vec<u8> {
    let [ah, al] = addr.to_be_bytes();
    let [qh, ql] = qty.to_be_bytes();
    frame(unit, &[0x03, ah, al, qh, ql])
}

/// Write Single Register (06).
pub fn write_single(unit: u8, addr: u16, value: u16) -> Vec<u8> {
    let [ah, al] = addr.to_be_bytes();
    let [vh, vl] = value.to_be_bytes();
    frame(unit, &[0x06, ah, al, vh, vl])
}

/// Write Multiple Registers (16): `values` from `addr`.
pub fn write_multiple(unit: u8, addr: u16, values: &[u16]) -> Vec<u8> {
    let [ah, al] = addr.to_be_bytes();
    let qty = values.len() as u16;
    let [qh, ql] = qty.to_be_bytes();
    let mut pdu = vec![0x10, ah, al, qh, ql, (values.len() * 2) as u8];
    for v in values {
        pdu.extend_from_slice(&v.to_be_bytes());
    }
    frame(unit, &pdu)
}

/// An int32 as two registers, high word first (SunSpec's order).
pub fn i32_registers(v: i32) -> [u16; 2] {
    let u = v as u32;
    [(u >> 16) as u16, u as u16]
}

/// What a reply says, read against its request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Reply {
    /// 03: the registers read.
    Registers(Vec<u16>),
    /// 06, 16: the echo (address, value or quantity), as the request's.
    Written,
    /// The function code with bit 7 set: the exception code.
    Exception(u8),
    /// Anything else: why it does not fit the request.
    Malformed(String),
}

/// Reads `reply` (address to CRC) against `request`.
pub fn parse_reply(request: &[u8], reply: &[u8]) -> Reply {
    if !crc_ok(reply) {
        return Reply::Malformed(format!("bad CRC or too short: {}", hex(reply)));
    }
    if request.len() < 6 || reply[0] != request[0] {
        return Reply::Malformed(format!(
            "address {} to a request to {}",
            reply[0], request[0]
        ));
    }
    let body = &reply[1..reply.len() - 2];
    let fc = request[1];
    match body {
        [f, code] if *f == fc | 0x80 => Reply::Exception(*code),
        [f, n, data @ ..] if *f == 0x03 && fc == 0x03 => {
            let qty = usize::from(u16::from_be_bytes([request[4], request[5]]));
            if usize::from(*n) != data.len() || data.len() != 2 * qty {
                return Reply::Malformed(format!("byte count {n} for {qty} registers"));
            }
            Reply::Registers(
                data.chunks_exact(2)
                    .map(|c| u16::from_be_bytes([c[0], c[1]]))
                    .collect(),
            )
        }
        [f, rest @ ..] if *f == fc && (fc == 0x06 || fc == 0x10) => {
            if rest.len() == 4 && rest == &request[2..6] {
                Reply::Written
            } else {
                Reply::Malformed(format!("echo {} to {}", hex(rest), hex(&request[2..6])))
            }
        }
        _ => Reply::Malformed(format!("unexpected {}", hex(reply))),
    }
}

/// Bytes as `01 03 9C 40`.
pub fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// What the master puts on the bus at a scheduled instant.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A frame (any bytes: a bad CRC, another address, a broadcast); when
    /// `expect_reply` is false, the transaction checks that none comes
    /// within [`REPLY_TIMEOUT_CYCLES`].
    Frame {
        /// The bytes, CRC included.
        bytes: Vec<u8>,
        /// Whether the slave must answer.
        expect_reply: bool,
    },
    /// A SunSpec client's walk of the model chain: read ID and L (two
    /// registers) at `from`, then at `from + 2 + L`, until ID 0xFFFF (or
    /// an error), one transaction each.
    Walk {
        /// The slave.
        unit: u8,
        /// The first model's ID register (40002 after `SunS`).
        from: u16,
    },
    /// Bytes at the line's rate with no silence in them (a babbling
    /// device); no reply may come.
    Noise(Vec<u8>),
}

/// One request and what came back.
#[derive(Debug, Clone, PartialEq)]
pub struct Transaction {
    /// The schedule's label (walks: `walk <register>`).
    pub label: String,
    /// Emulated seconds since power-on when the request went out.
    pub sent_emu_s: f64,
    /// The request.
    pub request: Vec<u8>,
    /// Whether a reply was expected.
    pub expect_reply: bool,
    /// Cycle the request was handed to the USART (its first byte starts).
    pub start_cycle: u64,
    /// Cycle its last byte has arrived (`start + n·C`).
    pub end_cycle: u64,
    /// CPU cycles of one character on the line (from UBRR2 and UCSR2C).
    pub char_cycles: u64,
    /// Reply bytes with the cycle each was written to UDR2.
    pub reply: Vec<(u64, u8)>,
    /// DE changes during the transaction: (cycle, high).
    pub de_edges: Vec<(u64, bool)>,
    /// DE's level when the request went out.
    pub de_at_start: bool,
    /// What the pins did against the spec; empty when all was right.
    pub violations: Vec<String>,
}

impl Transaction {
    /// The reply's bytes.
    pub fn reply_bytes(&self) -> Vec<u8> {
        self.reply.iter().map(|(_, b)| *b).collect()
    }

    /// The reply read against the request; `None` without one.
    pub fn parsed(&self) -> Option<Reply> {
        (!self.reply.is_empty()).then(|| parse_reply(&self.request, &self.reply_bytes()))
    }

    /// Characters of silence between the request's end and the reply's
    /// first byte.
    pub fn turnaround_chars(&self) -> Option<f64> {
        self.reply
            .first()
            .map(|(c, _)| (*c as f64 - self.end_cycle as f64) / self.char_cycles as f64)
    }

    /// One line: label, request, reply, turnaround.
    pub fn summary(&self) -> String {
        format!(
            "{} [{}] -> [{}]{}",
            self.label,
            hex(&self.request),
            hex(&self.reply_bytes()),
            self.turnaround_chars()
                .map_or(String::new(), |t| format!(" after {t:.2} chars"))
        )
    }

    /// Checks timing and DE (see the module notes); fills `violations`.
    fn check(&mut self) {
        let c = self.char_cycles;
        let mut v = Vec::new();
        let highs = self.de_edges.iter().filter(|(_, h)| *h).count();
        if self.de_at_start {
            v.push("DE high when the request went out".to_string());
        }
        if !self.expect_reply {
            if !self.reply.is_empty() {
                v.push(format!(
                    "a reply where none is due: {}",
                    hex(&self.reply_bytes())
                ));
            }
            if highs > 0 {
                v.push(format!("DE raised with no reply due: {:?}", self.de_edges));
            }
            self.violations = v;
            return;
        }
        let Some(&(w0, _)) = self.reply.first() else {
            v.push("no reply".to_string());
            self.violations = v;
            return;
        };
        let n = self.reply.len() as u64;
        // 3.5 characters of silence, in cycles: 7·C/2.
        if 2 * w0 < 2 * self.end_cycle + 7 * c {
            v.push(format!(
                "reply's first byte {:.2} characters after the request's last (3.5 due)",
                (w0 as f64 - self.end_cycle as f64) / c as f64
            ));
        }
        for (k, (w, _)) in self.reply.iter().enumerate() {
            if *w >= w0 + (k as u64 + 1) * c {
                v.push(format!(
                    "gap before reply byte {k}: written {} cycles into its slot's successor",
                    w - (w0 + (k as u64 + 1) * c)
                ));
            }
        }
        let wire_end = w0 + n * c;
        // DE: exactly one high interval, [rise, fall], covering the reply
        // from at most a character before its first byte to at most a
        // character after its last has left, and low during the request.
        let rise = self.de_edges.iter().find(|(_, h)| *h).map(|(t, _)| *t);
        let fall = self.de_edges.iter().rfind(|(_, h)| !*h).map(|(t, _)| *t);
        match (rise, fall) {
            (Some(r), Some(f)) if highs == 1 && f > r => {
                if r > w0 {
                    v.push(format!(
                        "DE rose {} cycles after the reply's first byte",
                        r - w0
                    ));
                }
                if r + c < w0 {
                    v.push(format!(
                        "DE rose {:.2} characters before the reply's first byte",
                        (w0 - r) as f64 / c as f64
                    ));
                }
                if r < self.end_cycle {
                    v.push("DE rose during the request".to_string());
                }
                if f < wire_end {
                    v.push(format!(
                        "DE fell {} cycles before the last byte left the shift register",
                        wire_end - f
                    ));
                }
                if f > wire_end + c {
                    v.push(format!(
                        "DE fell {:.2} characters after the last byte left",
                        (f - wire_end) as f64 / c as f64
                    ));
                }
            }
            _ => v.push(format!("DE not one high pulse: {:?}", self.de_edges)),
        }
        if !crc_ok(&self.reply_bytes()) {
            v.push(format!("reply CRC wrong: {}", hex(&self.reply_bytes())));
        }
        self.violations = v;
    }
}

/// CPU cycles of one character of USART2 as simavr times it: from UBRR2
/// (0xD4/0xD5), U2X2 (UCSR2A bit 1) and UCSR2C (0xD2: UCSZ21:0, USBS2),
/// `(UBRR + 1)·16` (8 with U2X) a bit, start + data + parity + stop bits
/// (simavr always counts a parity bit).
pub fn usart2_char_cycles(sim: &Sim) -> u64 {
    let ubrr = u64::from(sim.peek(0xD4)) | u64::from(sim.peek(0xD5) & 0x0F) << 8;
    let u2x = sim.peek(UCSR2A) & 0x02 != 0;
    let ucsrc = sim.peek(0xD2);
    let data_bits = 5 + u64::from((ucsrc >> 1) & 3);
    let stop_bits = 1 + u64::from((ucsrc >> 3) & 1);
    let bit = (ubrr + 1) * if u2x { 8 } else { 16 };
    bit * (1 + data_bits + 1 + stop_bits)
}

/// The master: its schedule, the transaction on the bus, those done.
#[derive(Debug, Clone, Default)]
pub struct ModbusMaster {
    /// (emulated minute, step, label), in time order.
    schedule: Vec<(f64, Step, String)>,
    next: usize,
    /// The next read of a walk under way: (unit, register, models so far).
    walk: Option<(u8, u16, usize)>,
    current: Option<Transaction>,
    /// Noise still being fed: no request until it has drained.
    noise_until_cycle: Option<u64>,
    /// Every transaction done, in order.
    pub transactions: Vec<Transaction>,
    /// Bytes the slave sent outside any transaction: (cycle, byte).
    pub unsolicited: Vec<(u64, u8)>,
    /// DE raised outside any transaction: the cycles.
    pub unsolicited_de: Vec<u64>,
    /// DE's level now.
    de_high: bool,
    /// Noise bursts sent: (emulated s, bytes).
    pub noise_sent: Vec<(f64, usize)>,
    /// The cycle each burst's last byte was handed to simavr's receive
    /// FIFO at (it is on the line 64 characters more at most).
    pub noise_fed_cycles: Vec<u64>,
}

impl ModbusMaster {
    /// Schedules `step` at emulated `minute`, shown as `label`.
    pub fn at(&mut self, minute: f64, step: Step, label: &str) {
        self.schedule.push((minute, step, label.to_string()));
        self.schedule.sort_by(|a, b| a.0.total_cmp(&b.0));
    }

    /// Nothing scheduled.
    pub fn is_empty(&self) -> bool {
        self.schedule.is_empty()
    }

    /// Whether the bench should run at real time now: a request is due (or
    /// a walk goes on) or a transaction is under way. (The image stamps
    /// the bytes it receives with its clock, which a compressed timescale
    /// would stretch 60-fold: a frame's bytes would then seem further apart
    /// than the 1.5 characters that end a frame.)
    pub fn wants_real_time(&self, now_emu_s: f64) -> bool {
        self.current.is_some()
            || self.walk.is_some()
            || self
                .schedule
                .get(self.next)
                .is_some_and(|(m, s, _)| now_emu_s >= m * 60.0 && !matches!(s, Step::Noise(_)))
    }

    /// Called once per service of the bench, after the run: collects the
    /// image's bytes and DE edges, ends a transaction when it is over, and
    /// puts the next due step on the bus. `real_time_for_cycles`: how long
    /// the bench has run at real time (a request goes out only after
    /// 2 ms of it, so that the image's clock runs 1:1 when it comes).
    pub fn service(&mut self, sim: &mut Sim, now_emu_s: f64, real_time_for_cycles: Option<u64>) {
        let now = sim.cycle();
        let bytes = sim.uart_take_timed(UART);
        let edges = sim.pin_changes(DE_PIN.0, DE_PIN.1);
        for &(c, h) in &edges {
            if h && !self.de_high && self.current.is_none() {
                self.unsolicited_de.push(c);
            }
            self.de_high = h;
        }
        match self.current.as_mut() {
            Some(t) => {
                t.reply.extend(bytes);
                t.de_edges.extend(edges);
            }
            None => self.unsolicited.extend(bytes),
        }
        if let Some(t) = &self.current {
            let c = t.char_cycles;
            let over = match t.reply.last() {
                // Over at a silence with DE low; a DE stuck high ends it a
                // time-out later (its check then says so).
                Some(&(last, _)) => {
                    (now >= last + (1 + END_OF_FRAME_CHARS) * c && !self.de_high)
                        || now >= last + REPLY_TIMEOUT_CYCLES
                }
                None => now >= t.end_cycle + REPLY_TIMEOUT_CYCLES,
            };
            if over {
                let mut t = self.current.take().expect("checked above");
                t.check();
                if let Some((unit, reg, n)) = self.walk.take() {
                    // The next model: ID and L read here.
                    if let Some(Reply::Registers(r)) = t.parsed() {
                        if r.len() == 2 && r[0] != 0xFFFF && n + 1 < WALK_MAX_MODELS {
                            let next = u32::from(reg) + 2 + u32::from(r[1]);
                            if let Ok(next) = u16::try_from(next) {
                                self.walk = Some((unit, next, n + 1));
                            }
                        }
                    }
                }
                self.transactions.push(t);
            }
        }
        if let Some(end) = self.noise_until_cycle {
            if sim.uart_pending(UART) > 0 {
                // 64 bytes in simavr's FIFO behind the queue, and a silence.
                self.noise_until_cycle = Some(now + 70 * usart2_char_cycles(sim));
            } else if self.noise_fed_cycles.len() < self.noise_sent.len() {
                self.noise_fed_cycles.push(now);
            } else if now >= end {
                self.noise_until_cycle = None;
            }
        }
        if self.current.is_some() || self.noise_until_cycle.is_some() {
            return;
        }
        let (label, bytes, expect_reply) = if let Some((unit, reg, _)) = self.walk {
            (format!("walk {reg}"), read_holding(unit, reg, 2), true)
        } else {
            let Some((m, step, label)) = self.schedule.get(self.next) else {
                return;
            };
            if now_emu_s < m * 60.0 {
                return;
            }
            match step {
                Step::Noise(bytes) => {
                    sim.uart_send(UART, bytes);
                    self.noise_sent.push((now_emu_s, bytes.len()));
                    self.noise_until_cycle = Some(now);
                    self.next += 1;
                    return;
                }
                _ if real_time_for_cycles.is_none_or(|c| c < 32_000) => return,
                Step::Walk { unit, from } => {
                    self.walk = Some((*unit, *from, 0));
                    self.next += 1;
                    (format!("walk {from}"), read_holding(*unit, *from, 2), true)
                }
                Step::Frame {
                    bytes,
                    expect_reply,
                } => {
                    self.next += 1;
                    (label.clone(), bytes.clone(), *expect_reply)
                }
            }
        };
        // The line at the rate the registers say (see
        // `Sim::retime_uart`), whatever order the image wrote UBRR2 and U2X2 in.
        sim.retime_uart(UART);
        let char_cycles = usart2_char_cycles(sim);
        // simavr's FIFO takes 64 bytes at once: a longer frame would be
        // fed in pieces, and its end not known here (a scenario's mistake).
        assert!(
            bytes.len() <= 64,
            "{label}: a frame of over 64 bytes (use Step::Noise)"
        );
        sim.uart_send(UART, &bytes);
        self.current = Some(Transaction {
            label,
            sent_emu_s: now_emu_s,
            end_cycle: now + bytes.len() as u64 * char_cycles,
            request: bytes,
            expect_reply,
            start_cycle: now,
            char_cycles,
            reply: Vec::new(),
            de_edges: Vec::new(),
            de_at_start: self.de_high,
            violations: Vec::new(),
        });
    }

    /// Transactions whose label starts with `prefix`.
    pub fn labelled(&self, prefix: &str) -> Vec<&Transaction> {
        self.transactions
            .iter()
            .filter(|t| t.label.starts_with(prefix))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_matches_the_specs_vectors() {
        // Modbus over Serial Line V1.02, §6.2.2: the frame 02 07 has the
        // CRC 0x1241, sent 41 12.
        assert_eq!(crc16(&[0x02, 0x07]), 0x1241);
        assert_eq!(frame(0x02, &[0x07]), [0x02, 0x07, 0x41, 0x12]);
        // The CRC catalogue's check value of CRC-16/MODBUS ("123456789").
        assert_eq!(crc16(b"123456789"), 0x4B37);
        // The application protocol's read of ten registers from 0 (a frame
        // quoted widely: 01 03 00 00 00 0A C5 CD).
        assert_eq!(read_holding(1, 0, 10), [1, 3, 0, 0, 0, 0x0A, 0xC5, 0xCD]);
        assert!(crc_ok(&[1, 3, 0, 0, 0, 0x0A, 0xC5, 0xCD]));
        assert!(!crc_ok(&[1, 3, 0, 0, 0, 0x0A, 0xC5, 0xCE]));
    }

    #[test]
    fn frames_and_replies_read_back() {
        let w = write_multiple(1, 40090, &[0, 5000, 0, 9000, 1]);
        assert_eq!(&w[..7], &[1, 0x10, 0x9C, 0x9A, 0, 5, 10]);
        assert_eq!(w.len(), 7 + 10 + 2);
        assert!(crc_ok(&w));
        assert_eq!(i32_registers(-8000), [0xFFFF, 0xE0C0]);
        let r = read_holding(1, 40000, 2);
        assert_eq!(
            parse_reply(&r, &frame(1, &[3, 4, 0x53, 0x75, 0x6E, 0x53])),
            Reply::Registers(vec![0x5375, 0x6E53])
        );
        assert_eq!(parse_reply(&r, &frame(1, &[0x83, 2])), Reply::Exception(2));
        assert!(matches!(
            parse_reply(&r, &frame(1, &[3, 2, 0, 1])),
            Reply::Malformed(_)
        ));
        let s = write_single(1, 40094, 1);
        assert_eq!(parse_reply(&s, &s), Reply::Written);
        assert!(matches!(
            parse_reply(&s, &frame(2, &[0x86, 1])),
            Reply::Malformed(_)
        ));
    }

    fn transaction(reply: Vec<(u64, u8)>, de: Vec<(u64, bool)>) -> Transaction {
        Transaction {
            label: "t".into(),
            sent_emu_s: 0.0,
            request: read_holding(1, 40000, 2),
            expect_reply: true,
            start_cycle: 0,
            end_cycle: 8 * 100,
            char_cycles: 100,
            reply,
            de_edges: de,
            de_at_start: false,
            violations: Vec::new(),
        }
    }

    #[test]
    fn timing_and_de_are_checked() {
        // A good reply: 4 characters after the request, back to back, DE
        // from just before the first to the last's end.
        let bytes = frame(1, &[3, 4, 0x53, 0x75, 0x6E, 0x53]);
        let at = |k: u64| 1200 + k * 100 + 10;
        let good: Vec<(u64, u8)> = bytes
            .iter()
            .enumerate()
            .map(|(k, b)| (at(k as u64), *b))
            .collect();
        let end = 1200 + bytes.len() as u64 * 100;
        let mut t = transaction(good.clone(), vec![(1190, true), (end + 20, false)]);
        t.check();
        assert!(t.violations.is_empty(), "{:?}", t.violations);
        assert_eq!(t.parsed(), Some(Reply::Registers(vec![0x5375, 0x6E53])));
        // DE dropped before the last byte left.
        let mut t = transaction(good.clone(), vec![(1190, true), (end - 50, false)]);
        t.check();
        assert!(
            t.violations[0].contains("before the last byte left"),
            "{:?}",
            t.violations
        );
        // Too soon after the request (3 characters).
        let soon: Vec<(u64, u8)> = good.iter().map(|(c, b)| (c - 200, *b)).collect();
        let mut t = transaction(soon, vec![(990, true), (end - 180, false)]);
        t.check();
        assert!(t.violations[0].contains("3.5 due"), "{:?}", t.violations);
        // A gap before byte 3.
        let mut gap = good.clone();
        for (c, _) in gap.iter_mut().skip(3) {
            *c += 150;
        }
        let mut t = transaction(gap, vec![(1190, true), (end + 200, false)]);
        t.check();
        assert!(t
            .violations
            .iter()
            .any(|v| v.contains("gap before reply byte 3")));
        // No reply due, none came, DE stayed low.
        let mut t = transaction(Vec::new(), Vec::new());
        t.expect_reply = false;
        t.check();
        assert!(t.violations.is_empty());
        let mut t = transaction(Vec::new(), vec![(900, true), (950, false)]);
        t.expect_reply = false;
        t.check();
        assert_eq!(t.violations.len(), 1);
    }
}
