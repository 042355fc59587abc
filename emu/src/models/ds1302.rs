//! Maxim DS1302 trickle-charge timekeeping chip on its three-wire interface
//! (CE, SCLK, I/O), at pin level, after the Maxim *DS1302 Trickle-Charge
//! Timekeeping Chip* datasheet (19-5420):
//!
//! - "CE and Clock Control": driving CE high starts a transfer, CE low ends
//!   it and puts I/O in high impedance; SCLK must be low when CE rises.
//! - "Command Byte" (Figure 3): bit 7 must be 1 ("if it is 0, writes to the
//!   DS1302 will be disabled": the model then ignores the transfer), bit 6
//!   RAM (1) or clock/calendar (0), bits 5..1 the address, bit 0 read (1)
//!   or write (0); input LSB first.
//! - "Data Input": after the eight command clocks a data byte is input on
//!   the next eight rising SCLK edges, LSB first; further clocks are
//!   ignored.
//! - "Data Output": after a read command the chip outputs a byte on the
//!   next eight falling edges, the first bit "on the first falling edge
//!   after the last bit of the command byte is written"; further clocks
//!   retransmit (a single register read repeats its byte; a burst goes
//!   on to the next register and the model starts the burst again after its
//!   last); "the I/O pin is tri-stated upon each rising edge of SCLK".
//! - "Burst Mode", "Clock/Calendar Burst Mode", "RAM Burst Mode": address
//!   31 reads or writes the eight clock registers (seconds … control) or the
//!   31 RAM bytes from address 0; a clock burst write transfers only when
//!   all eight bytes are written, and not at all (the control register
//!   included) when WP is set as the burst is specified; a clock burst read
//!   copies the time at its start ("secondary registers"), so the clock
//!   runs on during the read; RAM burst writes transfer byte by byte.
//! - Table 3 ("Register Address/Definition"): seconds (bit 7 CH), minutes,
//!   hours (bit 7 12-hour mode, bit 5 PM there or the 20-hour digit),
//!   date, month, day 1–7, year 00–99, all BCD; control (bit 7 WP, bits 0–6
//!   read 0); trickle charger; RAM 0–30. Locations 9–30 of the clock space
//!   hold nothing: the model ignores writes there and reads 0.
//! - "Clock Halt Flag": CH = 1 stops the oscillator; written 0, the clock
//!   starts. "Write-Protect Bit": while WP = 1 writes to every other
//!   register are ignored; a write to the control register always goes
//!   through. The power-on state of both is undefined.
//! - "AC Electrical Characteristics": the timing the model checks
//!   ([`Supply`]) and the worst-case delays it applies (tCDD, the data
//!   delay after a falling edge; tCCZ and tCDZ, at most 70 ns at 5 V, are
//!   taken as immediate).
//!
//! The clock counts whole seconds on emulated time (as the DS3231 model;
//! [`crate::twi::EmuClock`]); the interface runs on CPU time, in ns. The
//! datasheet does not say that writing the seconds restarts the second's
//! countdown (as the DS3231's does), so a running clock keeps its phase
//! when written; a clock that starts (CH written 0) counts from the write.
//!
//! **The I/O line** ([`McuIo`], [`Ds1302::line_high`]): the MCU's pin is
//! open-drain (`boards/avr/src/gpio.rs` `OpenDrainPin`: DDR 1 with PORT 0
//! drives low, DDR 0 releases), a 10 kΩ pull-up holds the line high against
//! the chip's internal 40 kΩ pull-down (4 V, above VIH = 2.0 V), and the
//! chip drives it (push-pull) only while it outputs a bit. The MCU driving
//! (DDR 1) while the chip drives is contention, recorded
//! ([`Ds1302::contentions`]) for the tests to fail on.

use crate::models::bcd_clock::{bcd, hour_of_register, hours_register, unbcd, Civil, SecondsClock};

/// Command byte bit 7: must be 1.
const CMD_VALID: u8 = 0x80;
/// Command byte bit 6: RAM (1) or clock/calendar (0).
const CMD_RAM: u8 = 0x40;
/// Command byte bit 0: read (1) or write (0).
const CMD_READ: u8 = 0x01;
/// The burst address (bits 5..1 all 1).
const BURST: u8 = 31;
/// Clock registers: seconds, minutes, hours, date, month, day, year,
/// control; then the trickle charger at 8.
const CLOCK_BURST_LEN: usize = 8;
const REG_SECONDS: u8 = 0;
const REG_CONTROL: u8 = 7;
const REG_TRICKLE: u8 = 8;
/// Seconds bit 7: clock halt.
pub const CH: u8 = 0x80;
/// Control bit 7: write protect.
pub const WP: u8 = 0x80;
/// Hours bit 7: 12-hour mode.
const HOURS_12H: u8 = 0x80;
/// RAM bytes.
pub const RAM_LEN: usize = 31;
/// 1 = Sunday, as `drivers::rtc::Ds1302` writes it: 1970-01-01 was a
/// Thursday (5).
const DOW_OFFSET_SUNDAY_1: i64 = 4;
/// Unix seconds of 2000-01-01T00:00:00Z.
const Y2000_UNIX_S: i64 = 946_684_800;
/// Violations and contentions kept in full (all are counted).
const KEEP: usize = 32;

/// The column of "AC Electrical Characteristics" the chip is held to:
/// minimum times the MCU must give it and the chip's worst-case data
/// delay, ns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Supply {
    /// VCC = 2.0 V (what `drivers::rtc::Ds1302` says it meets).
    V2_0,
    /// VCC = 5 V (an Uno).
    V5_0,
}

/// One timing rule of the AC table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Rule {
    /// tCC, CE high to the first SCLK rising edge.
    CeToClkSetup,
    /// tCWH, CE low time between transfers.
    CeInactive,
    /// tCH, SCLK high time.
    ClkHigh,
    /// tCL, SCLK low time (within a transfer).
    ClkLow,
    /// tCCH, the last rising SCLK edge (the one that latched) to CE low.
    ClkToCeHold,
    /// tDC, I/O settled before a rising SCLK edge that samples it.
    DataToClkSetup,
    /// tCDH, I/O held after a rising SCLK edge that sampled it.
    ClkToDataHold,
    /// SCLK low when CE rises ("CE and Clock Control").
    ClkLowAtCeRise,
}

impl Rule {
    /// Every rule.
    pub const ALL: [Rule; 8] = [
        Rule::CeToClkSetup,
        Rule::CeInactive,
        Rule::ClkHigh,
        Rule::ClkLow,
        Rule::ClkToCeHold,
        Rule::DataToClkSetup,
        Rule::ClkToDataHold,
        Rule::ClkLowAtCeRise,
    ];

    /// The datasheet's symbol.
    pub fn symbol(self) -> &'static str {
        match self {
            Rule::CeToClkSetup => "tCC",
            Rule::CeInactive => "tCWH",
            Rule::ClkHigh => "tCH",
            Rule::ClkLow => "tCL",
            Rule::ClkToCeHold => "tCCH",
            Rule::DataToClkSetup => "tDC",
            Rule::ClkToDataHold => "tCDH",
            Rule::ClkLowAtCeRise => "SCLK low at CE rise",
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

impl Supply {
    /// The rule's minimum, ns (0 for the level rule).
    pub fn min_ns(self, rule: Rule) -> f64 {
        let (v2, v5) = match rule {
            Rule::CeToClkSetup => (4_000.0, 1_000.0),
            Rule::CeInactive => (4_000.0, 1_000.0),
            Rule::ClkHigh => (1_000.0, 250.0),
            Rule::ClkLow => (1_000.0, 250.0),
            Rule::ClkToCeHold => (240.0, 60.0),
            Rule::DataToClkSetup => (200.0, 50.0),
            Rule::ClkToDataHold => (280.0, 70.0),
            Rule::ClkLowAtCeRise => (0.0, 0.0),
        };
        match self {
            Supply::V2_0 => v2,
            Supply::V5_0 => v5,
        }
    }

    /// tCDD, the chip's data delay after a falling SCLK edge (maximum), ns.
    pub fn data_delay_ns(self) -> f64 {
        match self {
            Supply::V2_0 => 800.0,
            Supply::V5_0 => 200.0,
        }
    }
}

/// A timing rule broken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Violation {
    /// Which.
    pub rule: Rule,
    /// When (CPU time), ns.
    pub at_ns: f64,
    /// The time the MCU gave, ns.
    pub measured_ns: f64,
}

/// The MCU's side of the I/O pin: its DDR and PORT bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct McuIo {
    /// DDR = 1: the MCU drives the line at `high`.
    pub output: bool,
    /// PORT bit (the level driven, or the internal pull-up while an input).
    pub high: bool,
}

impl McuIo {
    /// Released: an input without the internal pull-up.
    pub const RELEASED: McuIo = McuIo {
        output: false,
        high: false,
    };
    /// Driving low (open drain: DDR 1, PORT 0).
    pub const LOW: McuIo = McuIo {
        output: true,
        high: false,
    };
}

/// The I/O line's level when the MCU's pin is `mcu` and the chip drives
/// `chip` (`None`: high impedance, or no chip fitted): the MCU's level while
/// it drives (low wins against the chip: contention), else the chip's, else
/// high (the 10 kΩ pull-up; 4 V against the chip's 40 kΩ pull-down).
pub fn line_high(mcu: McuIo, chip: Option<bool>) -> bool {
    match (mcu.output, chip) {
        (true, Some(chip)) => mcu.high && chip,
        (true, None) => mcu.high,
        (false, Some(chip)) => chip,
        (false, None) => true,
    }
}

/// The three lines as the MCU drives them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Pins {
    /// CE level.
    pub ce: bool,
    /// SCLK level.
    pub sclk: bool,
    /// The MCU's I/O pin.
    pub io: McuIo,
}

/// What became of a transfer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// A read: the chip output `bytes`.
    Read,
    /// A write that reached the registers or RAM.
    Written,
    /// A write refused: WP set.
    WriteProtected,
    /// A clock burst write ended before its eighth byte: nothing transferred.
    BurstIncomplete,
    /// A write command with no complete data byte.
    NoData,
    /// Command bit 7 was 0: ignored.
    NotACommand,
    /// CE fell before the eighth command bit.
    NoCommand,
}

/// One transfer, CE high to CE low.
#[derive(Debug, Clone, PartialEq)]
pub struct Transfer {
    /// Emulated time CE rose, s.
    pub at_emu_s: f64,
    /// The command byte (as far as it came).
    pub command: u8,
    /// Complete data bytes: written by the MCU, or output by the chip and
    /// clocked past (the MCU sampled them).
    pub bytes: Vec<u8>,
    /// What became of it.
    pub outcome: Outcome,
}

impl Transfer {
    /// Whether this is a write of `command` with `bytes` that went through.
    pub fn is_write(&self, command: u8, bytes: &[u8]) -> bool {
        self.command == command && self.bytes == bytes && self.outcome == Outcome::Written
    }
}

/// Where a transfer is.
#[derive(Debug, Clone, PartialEq)]
enum Phase {
    /// CE low.
    Idle,
    /// Shifting in the command byte.
    Command { value: u8, bits: u8 },
    /// Bit 7 was 0: ignored until CE falls.
    Ignored,
    /// Shifting in data bytes.
    Write {
        byte: u8,
        bits: u8,
        /// WP as the command came (for a clock burst).
        protected_at_command: bool,
    },
    /// Shifting out `data`: `falls` falling edges so far (bit `falls − 1`
    /// is out), `rises` rising edges (bits the MCU sampled).
    Read {
        data: Vec<u8>,
        falls: u32,
        rises: u32,
    },
}

/// The DS1302 model.
#[derive(Debug, Clone)]
pub struct Ds1302 {
    supply: Supply,
    clock: SecondsClock,
    /// Hours register's 12-hour mode as last written.
    mode_12h: bool,
    /// Control (WP) and trickle charger.
    control: u8,
    trickle: u8,
    ram: [u8; RAM_LEN],
    // The interface.
    pins: Pins,
    phase: Phase,
    /// The transfer under way: its start, command, bytes.
    current: Option<Transfer>,
    /// What the chip drives on I/O: `None` high impedance.
    drive: Option<bool>,
    /// A bit the chip will drive at this CPU time (after tCDD).
    pending: Option<(f64, bool)>,
    // Edge times for the timing rules, ns.
    ce_rise_ns: f64,
    ce_fall_ns: Option<f64>,
    sclk_rise_ns: Option<f64>,
    sclk_fall_ns: Option<f64>,
    /// Whether this transfer saw a rising SCLK edge yet.
    clocked: bool,
    /// Whether the last rising SCLK edge sampled I/O (a command or write
    /// bit): tCDH runs from it.
    rise_sampled: bool,
    /// Last change of the line level the MCU made, ns.
    line_change_ns: f64,
    /// Every transfer, in order.
    pub transfers: Vec<Transfer>,
    /// Times the MCU drove I/O while the chip drove it.
    pub contentions: u64,
    /// The first 32 contentions: CPU time, ns.
    pub contention_at_ns: Vec<f64>,
    /// Timing rules broken (the first 32; all counted in
    /// `violation_count`).
    pub violations: Vec<Violation>,
    /// Timing rules broken.
    pub violation_count: u64,
    /// Per [`Rule`] (in [`Rule::ALL`]'s order) the shortest time the MCU
    /// gave, ns (`None`: never measured): [`Ds1302::shortest`].
    shortest_ns: [Option<f64>; 8],
    /// Times the seconds register was written and taken (a set clock).
    pub time_writes: u32,
}

impl Ds1302 {
    /// A chip that kept time on its battery: showing `unix_s` at emulated
    /// time 0, CH = 0, 24-hour mode, day 1 = Sunday, WP = 1 (as
    /// `drivers::rtc::Ds1302::set_datetime` leaves it), RAM zero.
    pub fn running(unix_s: i64) -> Self {
        Ds1302 {
            supply: Supply::V5_0,
            clock: SecondsClock::new(unix_s, DOW_OFFSET_SUNDAY_1),
            mode_12h: false,
            control: WP,
            trickle: 0,
            ram: [0; RAM_LEN],
            pins: Pins::default(),
            phase: Phase::Idle,
            current: None,
            drive: None,
            pending: None,
            ce_rise_ns: f64::NEG_INFINITY,
            ce_fall_ns: None,
            sclk_rise_ns: None,
            sclk_fall_ns: None,
            clocked: false,
            rise_sampled: false,
            line_change_ns: f64::NEG_INFINITY,
            transfers: Vec::new(),
            contentions: 0,
            contention_at_ns: Vec::new(),
            violations: Vec::new(),
            violation_count: 0,
            shortest_ns: [None; 8],
            time_writes: 0,
        }
    }

    /// A chip whose supply and battery both failed: CH = 1 (the oscillator
    /// stopped) at 2000-01-01 00:00:00, WP = 1. Both bits' power-on states
    /// are undefined; these are the ones a driver must cope with (detect
    /// the halt, clear WP before writing).
    pub fn lost_power() -> Self {
        let mut d = Self::running(Y2000_UNIX_S);
        let civil = d.clock.civil_at(0.0);
        d.clock.set(&civil, 0.0, false, true);
        d
    }

    /// The AC table column to hold the MCU to (default 5 V, an Uno's).
    pub fn supply(mut self, supply: Supply) -> Self {
        self.supply = supply;
        self
    }

    /// The column in force.
    pub fn supply_column(&self) -> Supply {
        self.supply
    }

    /// The time shown at emulated time `now_s`, Unix seconds.
    pub fn unix_at(&self, now_s: f64) -> i64 {
        self.clock.unix_at(now_s)
    }

    /// Whether CH is set (the oscillator stopped).
    pub fn halted(&self) -> bool {
        !self.clock.running()
    }

    /// Whether WP is set.
    pub fn write_protected(&self) -> bool {
        self.control & WP != 0
    }

    /// RAM byte `i`.
    pub fn ram(&self, i: usize) -> Option<u8> {
        self.ram.get(i).copied()
    }

    /// Clock register `reg` (0–8; 0 elsewhere) as a read at emulated time
    /// `now_s` would give it.
    pub fn register(&self, reg: u8, now_s: f64) -> u8 {
        let c = self.clock.civil_at(now_s);
        match reg {
            0 => bcd(c.second) | if self.halted() { CH } else { 0 },
            1 => bcd(c.minute),
            2 => hours_register(c.hour, self.mode_12h, HOURS_12H),
            3 => bcd(u32::from(c.day)),
            4 => bcd(u32::from(c.month)),
            5 => c.dow,
            6 => bcd(u32::from(c.year) % 100),
            REG_CONTROL => self.control,
            REG_TRICKLE => self.trickle,
            _ => 0,
        }
    }

    /// The eight registers of a clock burst at emulated time `now_s`.
    pub fn clock_burst(&self, now_s: f64) -> [u8; CLOCK_BURST_LEN] {
        core::array::from_fn(|r| self.register(r as u8, now_s))
    }

    /// The shortest time the MCU gave for `rule`, ns (`None`: never
    /// measured).
    pub fn shortest(&self, rule: Rule) -> Option<f64> {
        self.shortest_ns[rule.index()]
    }

    /// `tCC 5000 ns (min 1000), …`: the shortest time the MCU gave for each
    /// rule measured, against the column's minimum.
    pub fn shortest_summary(&self) -> String {
        Rule::ALL
            .iter()
            .filter_map(|&r| {
                self.shortest_ns[r.index()].map(|t| {
                    format!(
                        "{} {t:.1} ns (min {:.0})",
                        r.symbol(),
                        self.supply.min_ns(r)
                    )
                })
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// What the chip drives on I/O now (`None`: high impedance).
    pub fn driving(&self) -> Option<bool> {
        self.drive
    }

    /// The I/O line's level with the MCU's pin as last seen ([`line_high`]).
    pub fn line_high(&self) -> bool {
        line_high(self.pins.io, self.drive)
    }

    /// CPU time of the next change the chip makes on its own (a data bit
    /// appearing tCDD after a falling edge), ns.
    pub fn next_change_ns(&self) -> Option<f64> {
        self.pending.map(|(t, _)| t)
    }

    /// Applies what is due by CPU time `t_ns` (a pending data bit).
    pub fn advance(&mut self, t_ns: f64) {
        if let Some((t, bit)) = self.pending {
            if t <= t_ns {
                self.pending = None;
                self.drive = Some(bit);
                self.check_contention(t);
            }
        }
    }

    /// The MCU's pins at CPU time `t_ns` (ns) and emulated time `emu_s`:
    /// call at every change (and at any time: unchanged pins do nothing).
    pub fn pins(&mut self, t_ns: f64, emu_s: f64, pins: Pins) {
        self.advance(t_ns);
        let old = self.pins;
        // The line as the MCU leaves it (the chip aside): what a rising
        // edge samples in the input phases.
        let old_line = self.mcu_line();
        self.pins.io = pins.io;
        if self.mcu_line() != old_line {
            self.line_change_ns = t_ns;
            if self.ce_high() {
                if let Some(r) = self
                    .sclk_rise_ns
                    .filter(|_| self.pins.sclk && self.rise_sampled)
                {
                    self.measure(Rule::ClkToDataHold, t_ns, t_ns - r);
                }
            }
        }
        if pins.io.output && !old.io.output {
            self.check_contention(t_ns);
        }
        if pins.ce != old.ce {
            self.pins.ce = pins.ce;
            if pins.ce {
                self.ce_rises(t_ns, emu_s);
            } else {
                self.ce_falls(t_ns);
            }
        }
        if pins.sclk != old.sclk {
            self.pins.sclk = pins.sclk;
            if pins.sclk {
                self.sclk_rises(t_ns, emu_s);
            } else {
                self.sclk_falls(t_ns);
            }
        }
    }

    /// Power to the MCU cut: its pins float, CE and SCLK pulled down by the
    /// chip's 40 kΩ (the chip itself runs on its battery).
    pub fn mcu_reset(&mut self, t_ns: f64, emu_s: f64) {
        self.pins(t_ns, emu_s, Pins::default());
    }

    fn ce_high(&self) -> bool {
        self.pins.ce
    }

    /// The line without the chip: the MCU's level, or the pull-up.
    fn mcu_line(&self) -> bool {
        !self.pins.io.output || self.pins.io.high
    }

    /// Shifting a command or data byte in.
    fn input_phase(&self) -> bool {
        matches!(self.phase, Phase::Command { .. } | Phase::Write { .. })
    }

    fn measure(&mut self, rule: Rule, at_ns: f64, measured_ns: f64) {
        let s = &mut self.shortest_ns[rule.index()];
        *s = Some(s.map_or(measured_ns, |m| m.min(measured_ns)));
        if measured_ns < self.supply.min_ns(rule) {
            self.violation(rule, at_ns, measured_ns);
        }
    }

    fn violation(&mut self, rule: Rule, at_ns: f64, measured_ns: f64) {
        self.violation_count += 1;
        if self.violations.len() < KEEP {
            self.violations.push(Violation {
                rule,
                at_ns,
                measured_ns,
            });
        }
    }

    fn check_contention(&mut self, t_ns: f64) {
        if self.pins.io.output && self.drive.is_some() {
            self.contentions += 1;
            if self.contention_at_ns.len() < KEEP {
                self.contention_at_ns.push(t_ns);
            }
        }
    }

    fn release(&mut self) {
        self.drive = None;
        self.pending = None;
    }

    fn ce_rises(&mut self, t_ns: f64, emu_s: f64) {
        if let Some(f) = self.ce_fall_ns {
            self.measure(Rule::CeInactive, t_ns, t_ns - f);
        }
        if self.pins.sclk {
            self.violation(Rule::ClkLowAtCeRise, t_ns, 0.0);
        }
        self.ce_rise_ns = t_ns;
        self.clocked = false;
        self.rise_sampled = false;
        self.phase = Phase::Command { value: 0, bits: 0 };
        self.current = Some(Transfer {
            at_emu_s: emu_s,
            command: 0,
            bytes: Vec::new(),
            outcome: Outcome::NoCommand,
        });
    }

    fn ce_falls(&mut self, t_ns: f64) {
        self.ce_fall_ns = Some(t_ns);
        if let Some(e) = self
            .sclk_rise_ns
            .filter(|&e| self.clocked && e >= self.ce_rise_ns)
        {
            self.measure(Rule::ClkToCeHold, t_ns, t_ns - e);
        }
        self.release();
        let phase = std::mem::replace(&mut self.phase, Phase::Idle);
        if let Some(mut t) = self.current.take() {
            if let Phase::Read { data, rises, .. } = phase {
                let n = rises as usize / 8;
                t.bytes = (0..n).map(|i| data[i % data.len()]).collect();
            }
            self.transfers.push(t);
        }
    }

    fn sclk_rises(&mut self, t_ns: f64, emu_s: f64) {
        if !self.ce_high() {
            return;
        }
        if self.clocked {
            if let Some(f) = self.sclk_fall_ns {
                self.measure(Rule::ClkLow, t_ns, t_ns - f);
            }
        } else {
            self.measure(Rule::CeToClkSetup, t_ns, t_ns - self.ce_rise_ns);
        }
        self.clocked = true;
        self.sclk_rise_ns = Some(t_ns);
        // "The I/O pin is tri-stated upon each rising edge of SCLK".
        self.release();
        let bit = self.line_high();
        self.rise_sampled = self.input_phase();
        if self.rise_sampled {
            self.measure(Rule::DataToClkSetup, t_ns, t_ns - self.line_change_ns);
        }
        // What the bit completes, if anything.
        let mut command = None;
        let mut data = None;
        match &mut self.phase {
            Phase::Command { value, bits } => {
                *value |= u8::from(bit) << *bits;
                *bits += 1;
                if *bits == 8 {
                    command = Some(*value);
                }
            }
            Phase::Write { byte, bits, .. } => {
                *byte |= u8::from(bit) << *bits;
                *bits += 1;
                if *bits == 8 {
                    data = Some(*byte);
                    *byte = 0;
                    *bits = 0;
                }
            }
            Phase::Read { rises, .. } => *rises += 1,
            Phase::Idle | Phase::Ignored => {}
        }
        if let Some(c) = command {
            self.command(c, emu_s);
        }
        if let Some(b) = data {
            self.data_byte(b, emu_s);
        }
    }

    fn sclk_falls(&mut self, t_ns: f64) {
        if !self.ce_high() {
            return;
        }
        if let Some(r) = self.sclk_rise_ns.filter(|_| self.clocked) {
            self.measure(Rule::ClkHigh, t_ns, t_ns - r);
        }
        self.sclk_fall_ns = Some(t_ns);
        if let Phase::Read { data, falls, .. } = &mut self.phase {
            let n = *falls as usize;
            let byte = data[(n / 8) % data.len()];
            let bit = byte >> (n % 8) & 1 != 0;
            *falls += 1;
            self.pending = Some((t_ns + self.supply.data_delay_ns(), bit));
        }
    }

    /// The eighth command bit is in.
    fn command(&mut self, command: u8, emu_s: f64) {
        if let Some(t) = self.current.as_mut() {
            t.command = command;
        }
        if command & CMD_VALID == 0 {
            self.phase = Phase::Ignored;
            if let Some(t) = self.current.as_mut() {
                t.outcome = Outcome::NotACommand;
            }
            return;
        }
        let ram = command & CMD_RAM != 0;
        let addr = (command >> 1) & 0x1F;
        if command & CMD_READ != 0 {
            let data = match (ram, addr) {
                (false, BURST) => self.clock_burst(emu_s).to_vec(),
                (false, a) => vec![self.register(a, emu_s)],
                (true, BURST) => self.ram.to_vec(),
                (true, a) => vec![self.ram[usize::from(a)]],
            };
            if let Some(t) = self.current.as_mut() {
                t.outcome = Outcome::Read;
            }
            self.phase = Phase::Read {
                data,
                falls: 0,
                rises: 0,
            };
        } else {
            if let Some(t) = self.current.as_mut() {
                t.outcome = Outcome::NoData;
            }
            self.phase = Phase::Write {
                byte: 0,
                bits: 0,
                protected_at_command: self.write_protected(),
            };
        }
    }

    /// A complete data byte of a write.
    fn data_byte(&mut self, byte: u8, emu_s: f64) {
        let Phase::Write {
            protected_at_command,
            ..
        } = self.phase
        else {
            return;
        };
        let Some(mut t) = self.current.take() else {
            return;
        };
        let ram = t.command & CMD_RAM != 0;
        let addr = (t.command >> 1) & 0x1F;
        let index = t.bytes.len();
        let limit = match (ram, addr) {
            (false, BURST) => CLOCK_BURST_LEN,
            (true, BURST) => RAM_LEN,
            _ => 1,
        };
        // "Additional SCLK cycles are ignored".
        if index < limit {
            t.bytes.push(byte);
            t.outcome = self.take(ram, addr, index, &t.bytes, protected_at_command, emu_s);
        }
        self.current = Some(t);
    }

    /// Byte `index` of a write to (`ram`, `addr`), `bytes` so far: where it
    /// goes and what became of the transfer.
    fn take(
        &mut self,
        ram: bool,
        addr: u8,
        index: usize,
        bytes: &[u8],
        protected_at_command: bool,
        emu_s: f64,
    ) -> Outcome {
        let byte = bytes[index];
        match (ram, addr) {
            (false, BURST) if protected_at_command => Outcome::WriteProtected,
            (false, BURST) if bytes.len() < CLOCK_BURST_LEN => Outcome::BurstIncomplete,
            (false, BURST) => {
                let regs: [u8; CLOCK_BURST_LEN] = core::array::from_fn(|i| bytes[i]);
                self.write_clock(&regs, emu_s);
                self.control = regs[usize::from(REG_CONTROL)] & WP;
                self.time_writes += 1;
                Outcome::Written
            }
            (true, _) if self.write_protected() => Outcome::WriteProtected,
            (true, a) => {
                let at = if a == BURST { index } else { usize::from(a) };
                if let Some(cell) = self.ram.get_mut(at) {
                    *cell = byte;
                }
                Outcome::Written
            }
            (false, REG_CONTROL) => {
                // Bits 0–6 "are forced to 0"; never write-protected.
                self.control = byte & WP;
                Outcome::Written
            }
            (false, _) if self.write_protected() => Outcome::WriteProtected,
            (false, REG_TRICKLE) => {
                self.trickle = byte;
                Outcome::Written
            }
            (false, a) if usize::from(a) < CLOCK_BURST_LEN => {
                let mut regs = self.clock_burst(emu_s);
                regs[usize::from(a)] = byte;
                self.write_clock(&regs, emu_s);
                if a == REG_SECONDS {
                    self.time_writes += 1;
                }
                Outcome::Written
            }
            // Locations 9–30: no storage.
            (false, _) => Outcome::Written,
        }
    }

    /// Takes seconds … year (registers 0–6 of `regs`) as the time.
    fn write_clock(&mut self, regs: &[u8; CLOCK_BURST_LEN], emu_s: f64) {
        let (hour, mode_12h) = hour_of_register(regs[2], HOURS_12H);
        self.mode_12h = mode_12h;
        let civil = Civil {
            year: 2000 + unbcd(regs[6]) as u16,
            month: unbcd(regs[4] & 0x1F) as u8,
            day: unbcd(regs[3] & 0x3F) as u8,
            hour,
            minute: unbcd(regs[1] & 0x7F),
            second: unbcd(regs[0] & 0x7F),
            dow: regs[5] & 0x07,
        };
        let running = regs[0] & CH == 0;
        let starts = running && !self.clock.running();
        self.clock.set(&civil, emu_s, running, starts);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use drivers::rtc::Clock as _;
    use drivers::time::DateTime;

    /// 2026-06-21T05:00:00Z, a Sunday.
    const T0: i64 = 1_782_018_000;
    /// The driver's half clock period and CE setup (4 µs), as a master
    /// that keeps the 2.0 V column would.
    const HALF_NS: f64 = 1_000.0;

    /// A master driving the model edge by edge, `HALF_NS` apart, as the
    /// datasheet's Figure 4 ("Data Transfer Summary") draws a transfer.
    struct Master {
        chip: Ds1302,
        t_ns: f64,
        emu_s: f64,
        pins: Pins,
    }

    impl Master {
        fn new(chip: Ds1302) -> Self {
            Master {
                chip,
                t_ns: 0.0,
                emu_s: 0.0,
                pins: Pins::default(),
            }
        }

        fn set(&mut self, f: impl FnOnce(&mut Pins), wait_ns: f64) {
            f(&mut self.pins);
            self.chip.pins(self.t_ns, self.emu_s, self.pins);
            self.t_ns += wait_ns;
            self.chip.advance(self.t_ns);
        }

        fn begin(&mut self) {
            self.set(|p| p.sclk = false, 0.0);
            self.set(|p| p.ce = true, 4_000.0);
        }

        fn end(&mut self) {
            self.set(|p| p.ce = false, 4_000.0);
        }

        /// One byte out, LSB first, each bit set while SCLK is low and
        /// sampled at the rise; `release_last` lets go of I/O after the last
        /// rise (before the falling edge the chip answers on).
        fn put(&mut self, byte: u8, release_last: bool) {
            for bit in 0..8 {
                let high = byte >> bit & 1 != 0;
                self.set(
                    |p| p.io = if high { McuIo::RELEASED } else { McuIo::LOW },
                    HALF_NS,
                );
                self.set(|p| p.sclk = true, HALF_NS);
                if bit == 7 && release_last {
                    self.set(|p| p.io = McuIo::RELEASED, 0.0);
                }
                self.set(|p| p.sclk = false, 0.0);
            }
        }

        /// One byte in, each bit sampled `HALF_NS` after the falling edge.
        fn get(&mut self) -> u8 {
            let mut b = 0;
            for bit in 0..8 {
                self.t_ns += HALF_NS;
                self.chip.advance(self.t_ns);
                b |= u8::from(self.chip.line_high()) << bit;
                self.set(|p| p.sclk = true, HALF_NS);
                self.set(|p| p.sclk = false, 0.0);
            }
            b
        }

        fn write(&mut self, command: u8, data: &[u8]) {
            self.begin();
            self.put(command, false);
            for &b in data {
                self.put(b, false);
            }
            self.set(|p| p.io = McuIo::RELEASED, HALF_NS);
            self.end();
        }

        fn read(&mut self, command: u8, n: usize) -> Vec<u8> {
            self.begin();
            self.put(command, true);
            let out = (0..n).map(|_| self.get()).collect();
            self.end();
            out
        }
    }

    fn clean(m: &Master) {
        assert_eq!(m.chip.contentions, 0, "contention");
        assert_eq!(m.chip.violation_count, 0, "{:?}", m.chip.violations);
    }

    #[test]
    fn command_byte_reads_one_register_lsb_first() {
        // Table 3: 81h reads the seconds; 85h the hours; 8Fh the control
        // (WP, bits 0–6 read 0); Figure 4 single-byte read. The clock
        // shows 05:00:00 + 3,723.9 s = 06:02:03, Sunday 21 June 2026.
        let mut m = Master::new(Ds1302::running(T0));
        m.emu_s = 3_723.9;
        assert_eq!(m.read(0x81, 1), [0x03]);
        assert_eq!(m.read(0x83, 1), [0x02]);
        assert_eq!(m.read(0x85, 1), [0x06]);
        assert_eq!(m.read(0x87, 1), [0x21]);
        assert_eq!(m.read(0x89, 1), [0x06]);
        assert_eq!(m.read(0x8B, 1), [0x01]); // Sunday = 1
        assert_eq!(m.read(0x8D, 1), [0x26]);
        assert_eq!(m.read(0x8F, 1), [0x80]);
        // "Additional SCLK cycles retransmit the data bytes".
        assert_eq!(m.read(0x81, 2), [0x03, 0x03]);
        let t = m.chip.transfers.last().unwrap();
        assert_eq!((t.command, t.outcome), (0x81, Outcome::Read));
        assert_eq!(t.bytes, [0x03, 0x03]);
        clean(&m);
    }

    #[test]
    fn the_first_data_bit_comes_on_the_falling_edge_after_the_command() {
        // "Data Output": the first data bit "occurs on the first falling
        // edge after the last bit of the command byte is written", tCDD
        // (200 ns at 5 V) after it; "the I/O pin is tri-stated upon each
        // rising edge of SCLK". Seconds 0x02 (bit 0 = 0, bit 1 = 1).
        let mut m = Master::new(Ds1302::running(T0 + 2));
        m.begin();
        m.put(0x81, true);
        // The last command bit's falling edge was just now: not yet out.
        assert_eq!(m.chip.driving(), None);
        assert!(m.chip.line_high(), "pulled up while the chip is silent");
        m.t_ns += 199.0;
        m.chip.advance(m.t_ns);
        assert_eq!(m.chip.driving(), None);
        m.t_ns += 1.0;
        m.chip.advance(m.t_ns);
        assert_eq!(m.chip.driving(), Some(false), "bit 0 of 0x02");
        assert!(!m.chip.line_high());
        m.set(|p| p.sclk = true, 0.0);
        assert_eq!(m.chip.driving(), None, "tri-stated at the rising edge");
        assert!(m.chip.line_high());
        m.set(|p| p.sclk = false, 200.0);
        assert_eq!(m.chip.driving(), Some(true), "bit 1 of 0x02");
        m.end();
        assert_eq!(m.chip.driving(), None, "high impedance with CE low");
    }

    #[test]
    fn clock_burst_reads_eight_registers_from_a_copy() {
        // "Clock/Calendar Burst Mode": BFh reads seconds … control; the
        // time is copied at the start, so a read across a second's end
        // reads the second it started in.
        let mut m = Master::new(Ds1302::running(T0 + 59));
        m.emu_s = 0.999_9;
        m.begin();
        m.put(0xBF, true);
        m.emu_s = 1.5;
        let got: Vec<u8> = (0..8).map(|_| m.get()).collect();
        m.end();
        assert_eq!(got, [0x59, 0x00, 0x05, 0x21, 0x06, 0x01, 0x26, 0x80]);
        clean(&m);
    }

    #[test]
    fn write_protect_refuses_all_but_the_control_register() {
        // "Write-Protect Bit" and "Clock/Calendar Burst Mode": WP = 1
        // refuses a minutes write (82h) and a clock burst write (BEh), the
        // control byte of the burst included; 8Eh ← 00h clears it.
        let mut m = Master::new(Ds1302::running(T0));
        m.write(0x82, &[0x30]);
        assert_eq!(m.chip.transfers[0].outcome, Outcome::WriteProtected);
        let burst = [0x56, 0x34, 0x12, 0x21, 0x06, 0x01, 0x26, 0x00];
        m.write(0xBE, &burst);
        assert_eq!(m.chip.transfers[1].outcome, Outcome::WriteProtected);
        assert!(m.chip.write_protected());
        assert_eq!(m.chip.unix_at(0.0), T0);
        m.write(0xC0, &[0x42]); // RAM 0
        assert_eq!(m.chip.ram(0), Some(0));
        m.write(0x8E, &[0x00]);
        assert!(!m.chip.write_protected());
        m.write(0x82, &[0x30]);
        assert_eq!(m.chip.unix_at(0.0), T0 + 30 * 60);
        m.write(0xC0, &[0x42]);
        assert_eq!(m.chip.ram(0), Some(0x42));
        // Control bits 0–6 "are forced to 0".
        m.write(0x8E, &[0xFF]);
        assert_eq!(m.read(0x8F, 1), [0x80]);
        clean(&m);
    }

    #[test]
    fn a_clock_burst_write_takes_all_eight_or_nothing() {
        // "Burst Mode": "the first eight registers must be written in
        // order for the data to be transferred". 2024-02-28 23:59:58
        // (Wednesday = 4), control WP = 1 again.
        let regs = [0x58, 0x59, 0x23, 0x28, 0x02, 0x04, 0x24, 0x80];
        let mut m = Master::new(Ds1302::running(T0));
        m.write(0x8E, &[0x00]);
        m.write(0xBE, &regs[..7]);
        assert_eq!(m.chip.transfers[1].outcome, Outcome::BurstIncomplete);
        assert_eq!(m.chip.unix_at(0.0), T0);
        assert!(!m.chip.write_protected());
        m.write(0xBE, &regs);
        assert!(m.chip.transfers[2].is_write(0xBE, &regs));
        assert!(m.chip.write_protected());
        assert_eq!(m.chip.time_writes, 1);
        // Leap year: 2 s later it is 29 February, 00:00:00, Thursday.
        m.emu_s += 2.0;
        assert_eq!(
            m.read(0xBF, 8)[..7],
            [0x00, 0x00, 0x00, 0x29, 0x02, 0x05, 0x24]
        );
        clean(&m);
    }

    #[test]
    fn clock_halt_stops_and_starts_the_clock() {
        // "Clock Halt Flag": CH = 1 stops the oscillator; written 0, the
        // clock starts.
        let mut m = Master::new(Ds1302::lost_power());
        assert!(m.chip.halted());
        m.emu_s = 100.0;
        assert_eq!(m.read(0x81, 1), [0x80]);
        assert_eq!(m.chip.unix_at(100.0), Y2000_UNIX_S);
        m.write(0x8E, &[0x00]);
        m.write(0x80, &[0x10]); // 10 s, CH = 0
        assert!(!m.chip.halted());
        m.emu_s = 105.5;
        assert_eq!(m.read(0x81, 1), [0x15]);
        m.write(0x80, &[0x80 | 0x20]); // halt at 20 s
        m.emu_s = 200.0;
        assert_eq!(m.read(0x81, 1), [0xA0]);
        assert_eq!(m.chip.unix_at(200.0), Y2000_UNIX_S + 20);
        clean(&m);
    }

    #[test]
    fn twelve_hour_mode_reads_back() {
        // "AM-PM/12-24 Mode": hours bit 7 = 12-hour mode, bit 5 = PM.
        let mut m = Master::new(Ds1302::running(T0));
        m.write(0x8E, &[0x00]);
        m.write(0x84, &[0x80 | 0x20 | 0x11]); // 11 PM
        assert_eq!(m.read(0x85, 1), [0xB1]);
        assert_eq!(m.chip.unix_at(0.0).rem_euclid(86_400), 23 * 3600);
        m.emu_s = 3_600.0; // midnight: 12 AM
        assert_eq!(m.read(0x85, 1), [0x92]);
        clean(&m);
    }

    #[test]
    fn a_command_without_bit_7_is_ignored() {
        // "Command Byte": "the MSB (bit 7) must be a logic 1. If it is
        // zero, writes to the DS1302 will be disabled."
        let mut m = Master::new(Ds1302::running(T0));
        m.write(0x8E, &[0x00]);
        m.write(0x02, &[0x30]);
        assert_eq!(m.chip.transfers[1].outcome, Outcome::NotACommand);
        assert_eq!(m.chip.unix_at(0.0), T0);
        assert_eq!(m.read(0x01, 1), [0xFF], "nothing driven: the pull-up");
    }

    #[test]
    fn ram_single_and_burst() {
        // Table 3: C0h/C1h RAM 0 … FCh/FDh RAM 30, FEh/FFh the RAM burst.
        let mut m = Master::new(Ds1302::running(T0));
        m.write(0x8E, &[0x00]);
        m.write(0xFC, &[0xA5]); // RAM 30
        let bytes: Vec<u8> = (1..=3).collect();
        m.write(0xFE, &bytes);
        assert_eq!(m.read(0xFD, 1), [0xA5]);
        let all = m.read(0xFF, RAM_LEN);
        assert_eq!(all[..4], [1, 2, 3, 0]);
        assert_eq!(all[30], 0xA5);
        clean(&m);
    }

    #[test]
    fn contention_and_timing_are_recorded() {
        // The MCU driving I/O low while the chip outputs a bit.
        let mut m = Master::new(Ds1302::running(T0));
        m.begin();
        m.put(0x81, true);
        m.t_ns += 500.0;
        m.chip.advance(m.t_ns);
        assert!(m.chip.driving().is_some());
        m.set(|p| p.io = McuIo::LOW, 0.0);
        assert_eq!(m.chip.contentions, 1);
        m.set(|p| p.io = McuIo::RELEASED, 0.0);
        m.end();
        // "SCLK must be at a logic 0 when CE is driven to a logic 1", and
        // tCC: SCLK rising 500 ns after CE (1 µs at 5 V).
        let mut m = Master::new(Ds1302::running(T0));
        m.set(|p| p.sclk = true, 1_000.0);
        m.set(|p| p.ce = true, 0.0);
        m.set(|p| p.sclk = false, 500.0);
        m.set(|p| p.sclk = true, 0.0);
        let rules: Vec<Rule> = m.chip.violations.iter().map(|v| v.rule).collect();
        assert_eq!(rules, [Rule::ClkLowAtCeRise, Rule::CeToClkSetup]);
        assert_eq!(m.chip.violations[1].measured_ns, 500.0);
        // tCDH: I/O let go 50 ns after the rising edge that sampled it (70
        // ns at 5 V).
        let mut m = Master::new(Ds1302::running(T0));
        m.begin();
        m.set(|p| p.io = McuIo::LOW, HALF_NS);
        m.set(|p| p.sclk = true, 50.0);
        m.set(|p| p.io = McuIo::RELEASED, HALF_NS);
        let last = m.chip.violations.last().map(|v| (v.rule, v.measured_ns));
        assert_eq!(last, Some((Rule::ClkToDataHold, 50.0)));
        // A master at HALF_NS keeps the 2.0 V column: its shortest times.
        let mut m = Master::new(Ds1302::running(T0).supply(Supply::V2_0));
        m.write(0x8E, &[0x00]);
        m.read(0xBF, 8);
        clean(&m);
        let short = |r: Rule| m.chip.shortest(r).unwrap();
        assert_eq!(short(Rule::CeToClkSetup), 5_000.0);
        assert_eq!(short(Rule::ClkHigh), 1_000.0);
        assert_eq!(short(Rule::ClkLow), 1_000.0);
        // I/O changes only while SCLK is low (the read command's bit 7 is
        // 1: letting go after its rising edge changes nothing).
        assert_eq!(m.chip.shortest(Rule::ClkToDataHold), None);
    }

    /// embedded-hal pins over the model, so that the repository's driver
    /// runs against it: each pin change goes to the model at the time the
    /// delays have added up.
    mod wire {
        use super::*;
        use std::cell::RefCell;
        use std::convert::Infallible;
        use std::rc::Rc;

        pub type Shared = Rc<RefCell<(Ds1302, f64, Pins, f64)>>;

        #[derive(Clone, Copy)]
        pub enum Which {
            Ce,
            Sclk,
            Io,
        }

        pub struct Pin(pub Shared, pub Which);
        pub struct Delay(pub Shared);

        fn apply(s: &Shared, f: impl FnOnce(&mut Pins)) {
            let mut g = s.borrow_mut();
            let (chip, t, pins, emu) = &mut *g;
            f(pins);
            chip.pins(*t, *emu, *pins);
            // The next instruction: one AVR cycle later.
            *t += 62.5;
        }

        impl embedded_hal::digital::ErrorType for Pin {
            type Error = Infallible;
        }
        impl embedded_hal::digital::OutputPin for Pin {
            fn set_low(&mut self) -> Result<(), Infallible> {
                match self.1 {
                    Which::Ce => apply(&self.0, |p| p.ce = false),
                    Which::Sclk => apply(&self.0, |p| p.sclk = false),
                    Which::Io => apply(&self.0, |p| p.io = McuIo::LOW),
                }
                Ok(())
            }
            fn set_high(&mut self) -> Result<(), Infallible> {
                match self.1 {
                    Which::Ce => apply(&self.0, |p| p.ce = true),
                    Which::Sclk => apply(&self.0, |p| p.sclk = true),
                    Which::Io => apply(&self.0, |p| p.io = McuIo::RELEASED),
                }
                Ok(())
            }
        }
        impl embedded_hal::digital::InputPin for Pin {
            fn is_high(&mut self) -> Result<bool, Infallible> {
                let mut g = self.0.borrow_mut();
                let t = g.1;
                g.0.advance(t);
                Ok(g.0.line_high())
            }
            fn is_low(&mut self) -> Result<bool, Infallible> {
                self.is_high().map(|h| !h)
            }
        }
        impl embedded_hal::delay::DelayNs for Delay {
            fn delay_ns(&mut self, ns: u32) {
                self.0.borrow_mut().1 += f64::from(ns);
            }
        }
    }

    #[test]
    fn the_repository_driver_sets_and_reads_it() {
        use wire::{Delay, Pin, Which};
        let shared: wire::Shared = std::rc::Rc::new(std::cell::RefCell::new((
            Ds1302::lost_power().supply(Supply::V2_0),
            0.0,
            Pins::default(),
            10.0,
        )));
        let mut rtc = drivers::rtc::Ds1302::new(
            Pin(shared.clone(), Which::Ce),
            Pin(shared.clone(), Which::Sclk),
            Pin(shared.clone(), Which::Io),
            Delay(shared.clone()),
        );
        assert!(rtc.lost_power().unwrap());
        let t = DateTime::new(2026, 3, 20, 4, 0, 0).unwrap();
        rtc.set_datetime(&t).unwrap();
        assert!(!rtc.lost_power().unwrap());
        shared.borrow_mut().3 = 71.5;
        assert_eq!(
            rtc.datetime().unwrap(),
            DateTime::new(2026, 3, 20, 4, 1, 1).unwrap()
        );
        let g = shared.borrow();
        let chip = &g.0;
        // Clear WP (8Eh ← 00h), then the clock burst (BEh): 00 s, 00 min,
        // 04 h, date 20, month 03, Friday (6 with Sunday = 1), year 26,
        // control WP = 1.
        let writes: Vec<&Transfer> = chip
            .transfers
            .iter()
            .filter(|t| t.command & CMD_READ == 0)
            .collect();
        assert_eq!(writes.len(), 2);
        assert!(writes[0].is_write(0x8E, &[0x00]));
        assert!(writes[1].is_write(0xBE, &[0x00, 0x00, 0x04, 0x20, 0x03, 0x06, 0x26, 0x80]));
        assert!(chip.write_protected());
        assert_eq!(chip.contentions, 0);
        assert_eq!(chip.violation_count, 0, "{:?}", chip.violations);
    }
}
