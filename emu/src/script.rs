//! What an operator does to the board from outside during a run, by
//! emulated minute: bytes typed on the console (USART0) and power cuts.
//! One script and one player, shared by the Mega bench
//! ([`crate::mega::MegaBench`]) and the Uno bench ([`crate::uno::UnoBench`]),
//! so that both type, pace and cut alike and show it alike in the run's
//! lines.
//!
//! **Pacing.** The player only queues the bytes ([`Sim::uart_send`]);
//! [`Sim::run_until`] hands them to simavr's USART one at a time while its
//! receive FIFO says XON (`UART_IRQ_OUT_XON`/`XOFF`, 64 bytes), and simavr
//! raises RXC for the next byte one frame time after the last one at the
//! baud rate the image programmed (`cycles_per_byte` from UBRRn and U2Xn:
//! 86.8 µs of CPU time a byte at 115,200 baud 8N1). So the image sees its
//! bytes back to back at the line's real rate, never faster, whatever the
//! emulated timescale: a ring that keeps up with a real terminal keeps up
//! with the harness. (simavr does not drop a byte the image reads late, as
//! a real USART's two-byte buffer would: the bench cannot show overruns
//! caused by interrupts held off too long.) Bytes sent while the receiver
//! is off (before the image enables RXENn) are lost, as on a board.
//!
//! **Power cuts.** [`Sim::power_cycle`]: CPU and peripherals reset, RAM
//! repainted with the stack-measurement pattern, bytes still queued for
//! the USARTs lost; the EEPROM and flash keep their contents. The bench
//! keeps its models (RTC, axes, switches) as they are and drives its
//! inputs again.

use crate::sim::Sim;

/// Console input and power cuts of a run, by emulated minute.
#[derive(Debug, Clone, Default)]
pub struct Script {
    /// Bytes for USART0: (emulated minute, bytes, what the run's lines
    /// show), in time order.
    typed: Vec<(f64, Vec<u8>, String)>,
    /// Emulated minutes of the power cuts, in order.
    resets: Vec<f64>,
}

impl Script {
    /// Types `line` and an end of line (`\n`) at emulated `minute`; the
    /// run's lines show `> line`.
    pub fn type_line(&mut self, minute: f64, line: &str) {
        let mut bytes = line.as_bytes().to_vec();
        bytes.push(b'\n');
        self.push(minute, bytes, format!("> {line}"));
    }

    /// Sends `bytes` as they are at emulated `minute` (noise, a flood); the
    /// run's lines show `> (N bytes)`.
    pub fn bytes(&mut self, minute: f64, bytes: Vec<u8>) {
        let shown = format!("> ({} bytes)", bytes.len());
        self.push(minute, bytes, shown);
    }

    /// Cuts the power at emulated `minute` and turns it on again; the run's
    /// lines show `# power cut`.
    pub fn reset(&mut self, minute: f64) {
        self.resets.push(minute);
        self.resets.sort_by(f64::total_cmp);
    }

    /// Nothing typed and no power cut.
    pub fn is_empty(&self) -> bool {
        self.typed.is_empty() && self.resets.is_empty()
    }

    fn push(&mut self, minute: f64, bytes: Vec<u8>, shown: String) {
        self.typed.push((minute, bytes, shown));
        // Stable: what is typed at the same minute goes in the order given.
        self.typed.sort_by(|a, b| a.0.total_cmp(&b.0));
    }

    /// A player for one run.
    pub fn player(&self) -> Player<'_> {
        Player {
            script: self,
            typed: 0,
            resets: 0,
        }
    }
}

/// `len` bytes of line noise for [`Script::bytes`]: the low byte of each
/// state of Marsaglia's (2003) xorshift32 (shifts 13, 17, 5) from `seed`
/// (not 0), so the same seed gives the same noise on every run and bench.
/// About one byte in 256 is a line end (0x0A): lines of garbage, and a last
/// partial one.
pub fn xorshift32_noise(seed: u32, len: usize) -> Vec<u8> {
    let mut x = seed;
    (0..len)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect()
}

/// What [`Player::service`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Due {
    /// The lines to show in the run's lines, in order: `> LINE`,
    /// `> (N bytes)`, `# power cut`.
    pub lines: Vec<String>,
    /// The power was cut and turned on again: the bench drops what it
    /// assembled of the image's output and drives its inputs again.
    pub power_cut: bool,
}

/// Plays a [`Script`] over a run.
#[derive(Debug, Clone)]
pub struct Player<'a> {
    script: &'a Script,
    typed: usize,
    resets: usize,
}

impl Player<'_> {
    /// At `now_emu` emulated seconds since power-on: queues on USART0 every
    /// input that is due (see the module notes on pacing), then cuts the
    /// power if a cut is due ([`Sim::power_cycle`] with the part's first
    /// RAM address `ram_start` and the stack-measurement `paint`). Input
    /// due at the same time as a cut is lost with the cut.
    pub fn service(&mut self, sim: &mut Sim, now_emu: f64, ram_start: u16, paint: u8) -> Due {
        let mut due = Due::default();
        while let Some((_, bytes, shown)) = self
            .script
            .typed
            .get(self.typed)
            .filter(|(m, ..)| now_emu >= m * 60.0)
        {
            sim.uart_send('0', bytes);
            due.lines.push(shown.clone());
            self.typed += 1;
        }
        if self
            .script
            .resets
            .get(self.resets)
            .is_some_and(|m| now_emu >= m * 60.0)
        {
            self.resets += 1;
            sim.power_cycle(ram_start, paint);
            due.lines.push("# power cut".to_string());
            due.power_cut = true;
        }
        due
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xorshift32_is_marsaglias() {
        // Marsaglia (2003), "Xorshift RNGs", the 32-bit generator with
        // shifts 13, 17, 5: from 1 the states are 270369, 67634689,
        // 2647435461 (the three shifts on 32-bit words, worked out
        // independently in Python).
        assert_eq!(
            xorshift32_noise(1, 3),
            [
                270_369u32 as u8,
                67_634_689u32 as u8,
                2_647_435_461u32 as u8
            ]
        );
        assert_eq!(xorshift32_noise(0x2545_f491, 10_240).len(), 10_240);
    }

    #[test]
    fn lines_in_time_order_and_as_shown() {
        let mut s = Script::default();
        assert!(s.is_empty());
        s.type_line(2.0, "save");
        s.bytes(1.0, vec![1, 2, 3]);
        s.type_line(1.0, "get x");
        s.reset(3.0);
        s.reset(0.5);
        let shown: Vec<&str> = s.typed.iter().map(|t| t.2.as_str()).collect();
        assert_eq!(shown, ["> (3 bytes)", "> get x", "> save"]);
        assert_eq!(s.typed[1].1, b"get x\n");
        assert_eq!(s.resets, [0.5, 3.0]);
    }
}
