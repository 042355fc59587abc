//! The board's serial log read back: one parser for every line shape the
//! images write, and the state a reader of the log follows (mode, active
//! faults, board time, site) with the set-points in the order they came.
//!
//! The shapes and where they are written:
//!
//! | line | written by |
//! |---|---|
//! | `boot suntracker <version> board=<name>` | `suntracker::log::boot` |
//! | `time source=gps\|rtc utc=YYYY-MM-DDTHH:MM:SSZ` | `suntracker::log::time` |
//! | `site source=gps\|config lat=<deg> lon=<deg>` | `suntracker::log::site` |
//! | `setpoint utc=… zenith=… azimuth=… c=… a=…` [` panel_mv=<int>`] | `suntracker::log::setpoint`, `setpoint_with_panel` |
//! | `mode <name>` | `suntracker::log::mode` |
//! | `fault <name> raised\|cleared` | `suntracker::log::fault` |
//! | `day_energy vh=<V·h>` | `suntracker::panel::log_day_energy` |
//! | `clock jump from=[utc] to=<utc> source=gps\|rtc\|none: …` | the application's tick (`src/firmware.rs`) |
//! | `ok …`, `error …` | the console's replies (`src/console/reply.rs`) |
//! | `ok mode=… utc=… time=… lat=… lon=… site=… c=… a=… faults=… wind_hz=…` | `suntracker::console::write_status` |
//! | `status mode=…` with the same fields | the periodic status line |
//! | `status mode=… utc=… faults=… target_el=… target_az=… el=… az=…` | the monitor's own `--modbus` poll (`sunspec_client.rs`) |
//!
//! Anything else is an other line: passed through, counted, never an
//! error. A line that starts with one of the words above but does not have
//! its shape (a line cut short by a reset, noise on the wire) is counted as
//! malformed and passed through too.
//!
//! A status line with `target_el=`/`target_az=` (the monitor's `--modbus`
//! poll: model 601's `ElTrgt`/`AzTrgt`, and `el=`/`az=` its
//! `ElPos`/`AzPos`) in tracking mode is also a row of the CSV: the target
//! is the set-point in force, its zenith 90° − `target_el`; its time is the
//! poll's, and it has no axis angles c and a.
//!
//! Numbers are read as the board writes them (`suntracker::log::Sink::fixed`:
//! an optional `-`, digits, an optional fraction; `nan` for a value out of
//! the fixed-point range), times as `YYYY-MM-DDTHH:MM:SSZ` exactly; the
//! CSV keeps the texts as the board sent them.
//!
//! The emulator harness (`suntracker-emu --log`) writes each line of the
//! Mega's log after `<emulated utc> c=<deg> a=<deg> | `: that prefix is
//! recognised and skipped ([`strip_emulator_prefix`]).
//!
//! # Which mode and faults a set-point belongs to
//!
//! The images log a tick's lines in one of two orders. The ones built on
//! `src/firmware.rs` (Mega, Black Pill, QEMU) log the set-point first and the
//! tick's fault and mode changes after it (`log_setpoint`, then
//! `ChangeLog::update`: cleared faults, raised faults, the mode); the Uno
//! (`boards/uno/src/lib.rs`, `Tracker::tick`) logs the fault and mode changes
//! first and the set-point last. Both log set-points in tracking mode only.
//! So a set-point is given the mode and faults in force when it arrives
//! (right for the Uno's order, and for the app's when nothing changed),
//! unless the lines right after it (only `fault` lines between) end in
//! `mode tracking` while the mode before it was another: that is the app's
//! first tick of a tracking stretch, and the set-point gets the state after
//! those lines. A `mode` line other than `tracking` after a set-point
//! belongs to a later tick (the set-point's own tick was in tracking mode)
//! and leaves the set-point's state alone.
//!
//! # Time of the lines without a time
//!
//! `mode`, `fault`, `boot` and `day_energy` lines carry no time: they are
//! given the board time of the last line that carries one (`time`,
//! `setpoint`, `clock jump`, a status line), the time at or after which
//! they were written. One exception, for the Uno's order: a `mode tracking`
//! line that is the last mode line before a set-point, with no line with a
//! time between them, is that set-point's tick, and it and the lines after
//! it take the set-point's time (else a tracking stretch would seem to
//! start at the last time line before dawn). Lines before any time are
//! placed at the first time the log gives.

use sun_algos::UtcTime;

/// A board time as the log wrote it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Utc {
    /// `YYYY-MM-DDTHH:MM:SSZ`.
    pub text: String,
    /// Seconds since 1970-01-01T00:00:00Z.
    pub unix_s: i64,
}

/// A number as the log wrote it.
#[derive(Debug, Clone, PartialEq)]
pub struct Number {
    /// As written (`-12.34`, `nan`).
    pub text: String,
    /// Its value (NaN for `nan`).
    pub value: f64,
}

/// A `setpoint` line.
#[derive(Debug, Clone, PartialEq)]
pub struct SetPoint {
    pub utc: Utc,
    pub zenith_deg: Number,
    pub azimuth_deg: Number,
    /// The axis angles (`None` from a `--modbus` poll: the map has none).
    pub c_deg: Option<Number>,
    pub a_deg: Option<Number>,
    /// ` panel_mv=<int>` when the image reads a panel voltage.
    pub panel_mv: Option<u32>,
    /// Where the panel points, elevation and azimuth (a `--modbus` poll's
    /// `ElPos`/`AzPos`; `None` from the board's log).
    pub position_deg: Option<(Number, Number)>,
}

/// The fields of a status line (`status …` or the `ok mode=…` reply); every
/// field but the mode may be missing.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Status {
    pub mode: String,
    /// `None` for `utc=none` or no `utc=` field.
    pub utc: Option<Utc>,
    /// `gps`, `rtc` or `none`.
    pub time_source: Option<String>,
    pub lat_deg: Option<Number>,
    pub lon_deg: Option<Number>,
    /// `gps` or `config`.
    pub site_source: Option<String>,
    /// `None` for `none` or no field.
    pub c_deg: Option<Number>,
    pub a_deg: Option<Number>,
    /// `None` when there is no `faults=` field; empty for `faults=none`.
    pub faults: Option<Vec<String>>,
    pub wind_hz: Option<Number>,
    /// `target_el=`, `target_az=` (a `--modbus` poll); `None` for `none`.
    pub target_deg: Option<(Number, Number)>,
    /// `el=`, `az=` (a `--modbus` poll); `None` for `none`.
    pub position_deg: Option<(Number, Number)>,
}

/// What a line is.
#[derive(Debug, Clone, PartialEq)]
pub enum Line {
    Boot {
        version: String,
        board: String,
    },
    Time {
        source: String,
        utc: Utc,
    },
    Site {
        source: String,
        lat_deg: Number,
        lon_deg: Number,
    },
    SetPoint(SetPoint),
    Mode(String),
    Fault {
        name: String,
        raised: bool,
    },
    DayEnergy {
        vh: Number,
    },
    ClockJump {
        from: Option<Utc>,
        to: Utc,
        source: String,
    },
    /// A periodic `status …` line.
    Status(Status),
    /// A console reply: `ok …` (with its fields when it is the status
    /// reply) or `error …`.
    Reply {
        ok: bool,
        status: Option<Status>,
    },
    /// Anything else; `malformed` when it starts like a log line.
    Other {
        malformed: bool,
    },
}

/// The words a log line of a known shape starts with.
const KEYWORDS: [&str; 8] = [
    "boot",
    "time",
    "site",
    "setpoint",
    "mode",
    "fault",
    "day_energy",
    "status",
];

/// `line` without the emulator harness's `<utc> c=<deg> a=<deg> | `
/// prefix, or `line` itself.
pub fn strip_emulator_prefix(line: &str) -> &str {
    let Some((head, rest)) = line.split_once(" | ") else {
        return line;
    };
    let mut words = head.split(' ');
    let shaped = matches!(
        (words.next(), words.next(), words.next(), words.next()),
        (Some(t), Some(c), Some(a), None)
            if utc(t).is_some()
                && c.strip_prefix("c=").and_then(number).is_some()
                && a.strip_prefix("a=").and_then(number).is_some()
    );
    if shaped {
        rest
    } else {
        line
    }
}

/// A time written as `YYYY-MM-DDTHH:MM:SSZ` (exactly: 20 characters,
/// digits where digits go, a real calendar instant).
pub fn utc(s: &str) -> Option<Utc> {
    let b = s.as_bytes();
    let shape = b.len() == 20
        && b.iter().enumerate().all(|(i, &c)| match i {
            4 | 7 => c == b'-',
            10 => c == b'T',
            13 | 16 => c == b':',
            19 => c == b'Z',
            _ => c.is_ascii_digit(),
        });
    if !shape {
        return None;
    }
    let t: UtcTime = s.parse().ok()?;
    // The parser checks ranges; also refuse what it would normalise.
    if t.to_string() != s {
        return None;
    }
    Some(Utc {
        text: s.to_string(),
        unix_s: t.unix_seconds(),
    })
}

/// A number as `Sink::fixed` writes it: `-?digits(.digits)?`, or `nan`.
pub fn number(s: &str) -> Option<Number> {
    let value = if s == "nan" {
        f64::NAN
    } else {
        let body = s.strip_prefix('-').unwrap_or(s);
        let (int, frac) = match body.split_once('.') {
            Some((i, f)) => (i, Some(f)),
            None => (body, None),
        };
        let digits = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
        if !digits(int) || frac.is_some_and(|f| !digits(f)) {
            return None;
        }
        s.parse::<f64>().ok()?
    };
    Some(Number {
        text: s.to_string(),
        value,
    })
}

/// A name of a mode or fault: lower-case letters, digits and `_`.
fn name(s: &str) -> Option<String> {
    let ok = !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_');
    ok.then(|| s.to_string())
}

/// `key=value` words; `None` when a word has no `=` or a key repeats.
fn fields(words: &[&str]) -> Option<Vec<(String, String)>> {
    let mut out: Vec<(String, String)> = Vec::new();
    for w in words {
        let (k, v) = w.split_once('=')?;
        if k.is_empty() || out.iter().any(|(key, _)| key == k) {
            return None;
        }
        out.push((k.to_string(), v.to_string()));
    }
    Some(out)
}

fn get<'a>(f: &'a [(String, String)], key: &str) -> Option<&'a str> {
    f.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// One of `choices`.
fn one_of(v: &str, choices: &[&str]) -> Option<String> {
    choices.contains(&v).then(|| v.to_string())
}

/// A number or `none`: `Some(None)` for `none`.
fn opt_number(v: &str) -> Option<Option<Number>> {
    if v == "none" {
        Some(None)
    } else {
        number(v).map(Some)
    }
}

/// The zenith of an elevation, with as many decimals.
fn zenith_of(el: &Number) -> Number {
    let decimals = el.text.split_once('.').map_or(0, |(_, f)| f.len());
    let text = format!("{:.decimals$}", 90.0 - el.value);
    Number {
        value: text.parse().unwrap_or(f64::NAN),
        text,
    }
}

/// The fields of a status line after its first word (`status` or `ok`).
fn status(words: &[&str]) -> Option<Status> {
    let f = fields(words)?;
    let mut s = Status {
        mode: name(get(&f, "mode")?)?,
        ..Status::default()
    };
    if let Some(v) = get(&f, "utc") {
        s.utc = if v == "none" { None } else { Some(utc(v)?) };
    }
    if let Some(v) = get(&f, "time") {
        s.time_source = Some(one_of(v, &["gps", "rtc", "none"])?);
    }
    if let Some(v) = get(&f, "lat") {
        s.lat_deg = Some(number(v)?);
    }
    if let Some(v) = get(&f, "lon") {
        s.lon_deg = Some(number(v)?);
    }
    if let Some(v) = get(&f, "site") {
        s.site_source = Some(one_of(v, &["gps", "config"])?);
    }
    if let Some(v) = get(&f, "c") {
        s.c_deg = opt_number(v)?;
    }
    if let Some(v) = get(&f, "a") {
        s.a_deg = opt_number(v)?;
    }
    if let Some(v) = get(&f, "faults") {
        s.faults = Some(if v == "none" {
            Vec::new()
        } else {
            v.split(',').map(name).collect::<Option<Vec<_>>>()?
        });
    }
    if let Some(v) = get(&f, "wind_hz") {
        s.wind_hz = opt_number(v)?;
    }
    // Both of a pair or neither.
    let pair = |a: &str, b: &str| -> Option<Option<(Number, Number)>> {
        match (get(&f, a), get(&f, b)) {
            (None, None) => Some(None),
            (Some(x), Some(y)) => Some(opt_number(x)?.zip(opt_number(y)?)),
            _ => None,
        }
    };
    s.target_deg = pair("target_el", "target_az")?;
    s.position_deg = pair("el", "az")?;
    Some(s)
}

/// The `setpoint` fields (after the word).
fn setpoint(words: &[&str]) -> Option<SetPoint> {
    let f = fields(words)?;
    let known = ["utc", "zenith", "azimuth", "c", "a", "panel_mv"];
    if f.iter().any(|(k, _)| !known.contains(&k.as_str())) {
        return None;
    }
    let panel_mv = match get(&f, "panel_mv") {
        None => None,
        Some(v) if !v.is_empty() && v.bytes().all(|b| b.is_ascii_digit()) => Some(v.parse().ok()?),
        Some(_) => return None,
    };
    Some(SetPoint {
        utc: utc(get(&f, "utc")?)?,
        zenith_deg: number(get(&f, "zenith")?)?,
        azimuth_deg: number(get(&f, "azimuth")?)?,
        c_deg: Some(number(get(&f, "c")?)?),
        a_deg: Some(number(get(&f, "a")?)?),
        panel_mv,
        position_deg: None,
    })
}

/// `clock jump from=[utc] to=<utc> source=…[: reason]` (after `clock jump`).
fn clock_jump(rest: &str) -> Option<Line> {
    let head = rest.split_once(": ").map_or(rest, |(h, _)| h);
    let words: Vec<&str> = head.split(' ').collect();
    let f = fields(&words)?;
    if f.len() != 3 {
        return None;
    }
    let from = match get(&f, "from")? {
        "" => None,
        t => Some(utc(t)?),
    };
    Some(Line::ClockJump {
        from,
        to: utc(get(&f, "to")?)?,
        source: one_of(get(&f, "source")?, &["gps", "rtc", "none"])?,
    })
}

/// What `line` (without its line end) is.
pub fn parse(line: &str) -> Line {
    let line = strip_emulator_prefix(line);
    let words: Vec<&str> = line.split(' ').collect();
    let first = words.first().copied().unwrap_or("");
    let rest = &words[1..];
    let parsed = match first {
        "boot" => boot(rest),
        "time" => fields(rest).and_then(|f| {
            (f.len() == 2).then_some(())?;
            Some(Line::Time {
                source: one_of(get(&f, "source")?, &["gps", "rtc"])?,
                utc: utc(get(&f, "utc")?)?,
            })
        }),
        "site" => fields(rest).and_then(|f| {
            (f.len() == 3).then_some(())?;
            Some(Line::Site {
                source: one_of(get(&f, "source")?, &["gps", "config"])?,
                lat_deg: number(get(&f, "lat")?)?,
                lon_deg: number(get(&f, "lon")?)?,
            })
        }),
        "setpoint" => setpoint(rest).map(Line::SetPoint),
        "mode" => match rest {
            [m] => name(m).map(Line::Mode),
            _ => None,
        },
        "fault" => match rest {
            [n, state @ ("raised" | "cleared")] => name(n).map(|name| Line::Fault {
                name,
                raised: *state == "raised",
            }),
            _ => None,
        },
        "day_energy" => match rest {
            [v] => v
                .strip_prefix("vh=")
                .and_then(number)
                .map(|vh| Line::DayEnergy { vh }),
            _ => None,
        },
        "status" => status(rest).map(Line::Status),
        "clock" if rest.first() == Some(&"jump") => Some(
            clock_jump(line.get("clock jump ".len()..).unwrap_or(""))
                .unwrap_or(Line::Other { malformed: true }),
        ),
        "ok" => Some(Line::Reply {
            ok: true,
            status: if rest.first().is_some_and(|w| w.starts_with("mode=")) {
                status(rest)
            } else {
                None
            },
        }),
        "error" => Some(Line::Reply {
            ok: false,
            status: None,
        }),
        _ => None,
    };
    parsed.unwrap_or(Line::Other {
        malformed: KEYWORDS.contains(&first),
    })
}

/// `boot <banner words> board=<name>` (after `boot`).
fn boot(rest: &[&str]) -> Option<Line> {
    let (last, banner) = rest.split_last()?;
    let board = last.strip_prefix("board=").and_then(|b| {
        (!b.is_empty() && b.bytes().all(|c| c.is_ascii_graphic())).then(|| b.to_string())
    })?;
    if banner.is_empty() {
        return None;
    }
    Some(Line::Boot {
        version: banner.join(" "),
        board,
    })
}

/// Does the line answer a console command (`ok …`, `error …`)?
pub fn is_reply(line: &Line) -> bool {
    matches!(line, Line::Reply { .. })
}

/// One set-point with the state it belongs to: a row of the CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub setpoint: SetPoint,
    /// The mode in force (`None` before the first `mode` line).
    pub mode: Option<String>,
    /// The active faults, in the order they were raised.
    pub faults: Vec<String>,
}

/// A change of state on the time axis.
#[derive(Debug, Clone, PartialEq)]
pub enum Change {
    /// The mode became this (`None`: unknown, after a boot).
    Mode(Option<String>),
    /// A fault was raised (true) or cleared.
    Fault(String, bool),
    /// The board started.
    Boot,
}

/// A [`Change`] at a board time (`None` before the log gave any time).
#[derive(Debug, Clone, PartialEq)]
pub struct Event {
    pub unix_s: Option<i64>,
    pub change: Change,
}

/// Lines counted by kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counts {
    pub lines: u64,
    pub boots: u64,
    pub times: u64,
    pub sites: u64,
    pub setpoints: u64,
    pub modes: u64,
    pub faults: u64,
    pub day_energy: u64,
    pub clock_jumps: u64,
    pub status: u64,
    pub replies_ok: u64,
    pub replies_error: u64,
    pub other: u64,
    pub malformed: u64,
}

/// The site the log last gave.
#[derive(Debug, Clone, PartialEq)]
pub struct SiteSeen {
    pub source: String,
    pub lat_deg: Number,
    pub lon_deg: Number,
}

/// A set-point whose state is not settled yet (see the module docs).
#[derive(Debug, Clone)]
struct Pending {
    setpoint: SetPoint,
    mode_before: Option<String>,
    faults_before: Vec<String>,
}

/// The state a reader of the log follows, and what it has seen.
#[derive(Debug, Clone, Default)]
pub struct Monitor {
    pub counts: Counts,
    /// Board name and firmware banner of the last `boot` line.
    pub board: Option<(String, String)>,
    pub mode: Option<String>,
    /// Active faults, in the order raised.
    pub faults: Vec<String>,
    /// The board time of the last line that carries one.
    pub now_s: Option<i64>,
    pub site: Option<SiteSeen>,
    /// Settled set-points, in log order.
    pub rows: Vec<Row>,
    /// Mode, fault and boot changes, in log order.
    pub events: Vec<Event>,
    /// `day_energy` values (V·h) with their board time.
    pub day_energy: Vec<(Option<i64>, Number)>,
    pending: Option<Pending>,
    /// `events.len()` when the last line with a time came.
    timed_at: usize,
}

impl Monitor {
    pub fn new() -> Self {
        Self::default()
    }

    /// Reads one line (without its line end); returns what it is.
    pub fn feed(&mut self, text: &str) -> Line {
        let line = parse(text);
        self.counts.lines += 1;
        self.apply(&line);
        line
    }

    /// Settles the last set-point (at the end of the log).
    pub fn finish(&mut self) {
        self.settle(false);
    }

    /// Are the rows a `--modbus` session's polls (no axis angles), not
    /// the board's set-point lines?
    pub fn rows_are_polls(&self) -> bool {
        self.rows
            .first()
            .is_some_and(|r| r.setpoint.c_deg.is_none())
    }

    /// The first board time in the log, if any.
    pub fn first_time_s(&self) -> Option<i64> {
        self.events
            .iter()
            .filter_map(|e| e.unix_s)
            .chain(self.rows.iter().map(|r| r.setpoint.utc.unix_s))
            .min()
    }

    fn settle(&mut self, same_tick: bool) {
        if let Some(p) = self.pending.take() {
            let (mode, faults) = if same_tick {
                (self.mode.clone(), self.faults.clone())
            } else {
                (p.mode_before, p.faults_before)
            };
            self.rows.push(Row {
                setpoint: p.setpoint,
                mode,
                faults,
            });
        }
    }

    /// A line with the board time `t` came.
    fn timed(&mut self, t: i64) {
        self.now_s = Some(t);
        self.timed_at = self.events.len();
    }

    fn event(&mut self, change: Change) {
        self.events.push(Event {
            unix_s: self.now_s,
            change,
        });
    }

    fn set_mode(&mut self, mode: Option<String>) {
        if self.mode != mode {
            self.mode = mode.clone();
            self.event(Change::Mode(mode));
        }
    }

    fn set_fault(&mut self, name: &str, raised: bool) {
        let active = self.faults.iter().any(|f| f == name);
        if raised && !active {
            self.faults.push(name.to_string());
            self.event(Change::Fault(name.to_string(), true));
        } else if !raised && active {
            self.faults.retain(|f| f != name);
            self.event(Change::Fault(name.to_string(), false));
        }
    }

    /// A status line's mode, faults, time and site.
    fn status(&mut self, s: &Status) {
        self.settle(false);
        if let Some(t) = &s.utc {
            self.timed(t.unix_s);
        }
        if let (Some(source), Some(lat), Some(lon)) = (&s.site_source, &s.lat_deg, &s.lon_deg) {
            self.site = Some(SiteSeen {
                source: source.clone(),
                lat_deg: lat.clone(),
                lon_deg: lon.clone(),
            });
        }
        if let Some(faults) = &s.faults {
            for f in self.faults.clone() {
                if !faults.contains(&f) {
                    self.set_fault(&f, false);
                }
            }
            for f in faults {
                self.set_fault(f, true);
            }
        }
        self.set_mode(Some(s.mode.clone()));
        // A `--modbus` poll while tracking: the set-point in force.
        if let (Some(utc), Some((el, az)), "tracking") = (&s.utc, &s.target_deg, s.mode.as_str()) {
            self.rows.push(Row {
                setpoint: SetPoint {
                    utc: utc.clone(),
                    zenith_deg: zenith_of(el),
                    azimuth_deg: az.clone(),
                    c_deg: None,
                    a_deg: None,
                    panel_mv: None,
                    position_deg: s.position_deg.clone(),
                },
                mode: self.mode.clone(),
                faults: self.faults.clone(),
            });
        }
    }

    fn apply(&mut self, line: &Line) {
        let c = &mut self.counts;
        match line {
            Line::Boot { version, board } => {
                c.boots += 1;
                self.settle(false);
                self.board = Some((board.clone(), version.clone()));
                self.event(Change::Boot);
                // A started board has no faults and no mode yet.
                for f in self.faults.clone() {
                    self.set_fault(&f, false);
                }
                self.set_mode(None);
            }
            Line::Time { utc, .. } => {
                c.times += 1;
                self.settle(false);
                self.timed(utc.unix_s);
            }
            Line::Site {
                source,
                lat_deg,
                lon_deg,
            } => {
                c.sites += 1;
                self.settle(false);
                self.site = Some(SiteSeen {
                    source: source.clone(),
                    lat_deg: lat_deg.clone(),
                    lon_deg: lon_deg.clone(),
                });
            }
            Line::SetPoint(sp) => {
                c.setpoints += 1;
                self.settle(false);
                // The entry's time, at most the board's time when logged:
                // it moves the clock on, never back (a step back comes
                // with its own `clock jump` or `time` line).
                let t = self.now_s.map_or(sp.utc.unix_s, |t| t.max(sp.utc.unix_s));
                // The Uno's order: `mode tracking` of this tick before it.
                let untimed = self.events.get_mut(self.timed_at..).unwrap_or(&mut []);
                let last_mode = untimed
                    .iter()
                    .rposition(|e| matches!(e.change, Change::Mode(_)));
                if let Some(i) = last_mode {
                    if untimed[i].change == Change::Mode(Some("tracking".into())) {
                        for e in &mut untimed[i..] {
                            e.unix_s = Some(t);
                        }
                    }
                }
                self.timed(t);
                self.pending = Some(Pending {
                    setpoint: sp.clone(),
                    mode_before: self.mode.clone(),
                    faults_before: self.faults.clone(),
                });
            }
            Line::Mode(m) => {
                c.modes += 1;
                self.set_mode(Some(m.clone()));
                if let Some(p) = &self.pending {
                    let same_tick = m == "tracking" && p.mode_before.as_deref() != Some("tracking");
                    self.settle(same_tick);
                }
            }
            Line::Fault { name, raised } => {
                c.faults += 1;
                self.set_fault(name, *raised);
            }
            Line::DayEnergy { vh } => {
                c.day_energy += 1;
                self.settle(false);
                self.day_energy.push((self.now_s, vh.clone()));
            }
            Line::ClockJump { to, .. } => {
                c.clock_jumps += 1;
                self.settle(false);
                self.timed(to.unix_s);
            }
            Line::Status(s) => {
                c.status += 1;
                self.status(s);
            }
            Line::Reply { ok, status } => {
                if *ok {
                    c.replies_ok += 1;
                } else {
                    c.replies_error += 1;
                }
                if let Some(s) = status {
                    self.status(s);
                }
            }
            Line::Other { malformed } => {
                c.other += 1;
                if *malformed {
                    c.malformed += 1;
                }
            }
        }
    }
}
