//! `monitor --modbus`: the tracker read as a SunSpec client reads it, over
//! the RTU client of `modbus_client.rs`.
//!
//! The map is found, not assumed (SunSpec Alliance, *SunSpec Device
//! Information Model Specification*: the `SunS` marker at 40000, else
//! 50000, else 0; then the models one after the other, each an ID and a
//! length L, the next at the ID's register + 2 + L, up to the end marker's
//! ID 0xFFFF): model 305 is there only on a board with a GPS, so the
//! addresses of the models after it move. Each poll then reads model 601
//! (the fixed block and the first tracker), the vendor model 64201 and,
//! when present, model 305, and decodes them with the point offsets and
//! "not implemented" values of the `suntracker-modbus` crate
//! (`modbus/src/sunspec.rs`, `docs/src/modbus.md`): the angles with 601's
//! `Dgr_SF`, the UTC of the local date and time in `DtLoc`/`TmLoc` (less
//! the tracker's UTC offset, `--utc-offset-h`), the vendor
//! model's `Mode` code and `Flt`/`Flt2` bits by the core crate's names
//! (`suntracker::sunspec::mode_of_code`, `fault_of_bit`, `Mode::name`,
//! `Fault::name`).
//!
//! A poll becomes one line in the shape of the board's status line
//! (`board_log.rs`), which the monitor reads as it reads the board's:
//!
//! ```text
//! status mode=tracking utc=2026-03-20T09:07:10Z lat=11.9683 lon=8.4261 site=gps faults=none target_el=57.99 target_az=96.78 el=58.00 az=96.79
//! ```
//!
//! `target_el`/`target_az` are 601's `ElTrgt`/`AzTrgt`, `el`/`az` its
//! `ElPos`/`AzPos` (`none` when not implemented: not homed, no time); the
//! site is model 305's fix. Missed polls (a time-out, a CRC error, an
//! exception, a reply that does not fit) are reported and counted, and the
//! next poll comes at its time.

use std::fmt;
use std::time::{Duration, Instant};

use sun_algos::UtcTime;
use suntracker::sunspec::{fault_of_bit, mode_of_code};
use suntracker_modbus::sunspec::{
    m1, m305, m601, m64201, END_MODEL_ID, NOT_IMPL_INT32, PAD, SUNS_MARKER,
};

use super::modbus_client::{self, Client};

/// Where a SunSpec map may start, in the order a client tries them.
pub const BASES: [u16; 3] = [40000, 50000, 0];
/// The most models followed before the chain is taken as broken.
const MAX_MODELS: usize = 64;

/// A model of the map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Model {
    pub id: u16,
    /// Register of its ID.
    pub addr: u16,
    /// Its length L (registers after ID and L).
    pub len: u16,
}

/// The map as found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Map {
    /// Register of the `SunS` marker.
    pub base: u16,
    pub models: Vec<Model>,
    /// Register of the end marker.
    pub end: u16,
}

impl Map {
    pub fn find(&self, id: u16) -> Option<Model> {
        self.models.iter().copied().find(|m| m.id == id)
    }
}

impl fmt::Display for Map {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "SunS at {}", self.base)?;
        for m in &self.models {
            write!(f, ", model {} at {} (L {})", m.id, m.addr, m.len)?;
        }
        write!(f, ", end at {}", self.end)
    }
}

/// Why a poll failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PollError {
    /// The request got no usable reply.
    Modbus(modbus_client::Error),
    /// The replies do not make a SunSpec tracker map.
    Map(String),
}

impl fmt::Display for PollError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PollError::Modbus(e) => e.fmt(f),
            PollError::Map(e) => write!(f, "map: {e}"),
        }
    }
}

impl From<modbus_client::Error> for PollError {
    fn from(e: modbus_client::Error) -> Self {
        PollError::Modbus(e)
    }
}

/// Finds the `SunS` marker and walks the model chain to the end marker.
pub fn discover(c: &mut Client) -> Result<Map, PollError> {
    use modbus_client::Error;
    let mut base = None;
    for b in BASES {
        match c.read_holding(b, 2) {
            Ok(r) if r == SUNS_MARKER => {
                base = Some(b);
                break;
            }
            // Not there (an exception 02 or other values): the next base.
            Ok(_) | Err(Error::Exception { code: 2, .. }) => {}
            Err(e) => return Err(e.into()),
        }
    }
    let base = base.ok_or_else(|| PollError::Map(format!("no SunS marker at {BASES:?}")))?;
    let mut models = Vec::new();
    let mut addr = base + 2;
    for _ in 0..MAX_MODELS {
        let r = c.read_holding(addr, 2)?;
        let (id, len) = (r[0], r[1]);
        if id == END_MODEL_ID {
            return Ok(Map {
                base,
                models,
                end: addr,
            });
        }
        models.push(Model { id, addr, len });
        addr = len
            .checked_add(2)
            .and_then(|l| addr.checked_add(l))
            .ok_or_else(|| {
                PollError::Map(format!(
                    "model {id} at {addr} (L {len}) runs past register 65535"
                ))
            })?;
    }
    Err(PollError::Map(format!(
        "no end marker after {MAX_MODELS} models"
    )))
}

/// The text of a string point: ASCII up to the first NUL.
fn text(regs: &[u16]) -> String {
    regs.iter()
        .flat_map(|r| r.to_be_bytes())
        .take_while(|&b| b != 0)
        .map(|b| {
            if b.is_ascii_graphic() || b == b' ' {
                b as char
            } else {
                '?'
            }
        })
        .collect::<String>()
        .trim_end()
        .to_string()
}

/// The int32 point at `regs[i..i + 2]`, high word first; `None` when not
/// implemented.
fn int32(regs: &[u16], i: usize) -> Option<i32> {
    let v = ((u32::from(*regs.get(i)?) << 16) | u32::from(*regs.get(i + 1)?)) as i32;
    (v != NOT_IMPL_INT32).then_some(v)
}

/// `raw × 10^sf` as the board writes numbers (`-?digits(.digits)?`, `-sf`
/// decimals); `None` for a scale factor not implemented or out of reach.
pub fn scaled(raw: i32, sf: i16) -> Option<String> {
    if sf == PAD as i16 || !(-9..=9).contains(&sf) {
        return None;
    }
    let v = i64::from(raw);
    if sf >= 0 {
        return Some((v * 10_i64.pow(u32::from(sf.unsigned_abs()))).to_string());
    }
    let d = u32::from(sf.unsigned_abs());
    let p = 10_i64.pow(d);
    let sign = if v < 0 { "-" } else { "" };
    let (i, f) = (v.abs() / p, v.abs() % p);
    Some(format!("{sign}{i}.{f:0w$}", w = d as usize))
}

/// Degrees × 10⁻⁷ (model 305) without the trailing zeros of the fraction.
fn e7_degrees(raw: i32) -> Option<String> {
    let t = scaled(raw, -7)?;
    let t = t.trim_end_matches('0');
    Some(
        t.strip_suffix('.')
            .map_or(t.to_string(), |i| format!("{i}.0")),
    )
}

/// 601's `DtLoc` (`YYYYMMDD`) and `TmLoc` (`hhmmss`), the tracker's local
/// time `offset_s` east of UTC (its `site.utc_offset_h`), as the UTC
/// instant `YYYY-MM-DDTHH:MM:SSZ`; `None` when not set (NUL: the time is
/// unknown) or not a real instant.
pub fn utc_of_local(date: &[u16], time: &[u16], offset_s: i32) -> Option<String> {
    let (d, t) = (text(date), text(time));
    let digits = |s: &str, n: usize| s.len() == n && s.bytes().all(|b| b.is_ascii_digit());
    if !digits(&d, 8) || !digits(&t, 6) {
        return None;
    }
    let s = format!(
        "{}-{}-{}T{}:{}:{}Z",
        &d[..4],
        &d[4..6],
        &d[6..8],
        &t[..2],
        &t[2..4],
        &t[4..6]
    );
    let local = super::board_log::utc(&s)?;
    if offset_s == 0 {
        return Some(local.text);
    }
    let utc = UtcTime::from_unix_seconds(local.unix_s.checked_sub(i64::from(offset_s))?).ok()?;
    Some(utc.to_string())
}

/// The name of the vendor model's mode code.
pub fn mode_name(code: u16) -> String {
    mode_of_code(code).map_or_else(|| format!("code_{code}"), |m| m.name().to_string())
}

/// The names of the faults of the vendor model's `Flt` (bits 0 to 31) and
/// `Flt2` (bits 32 to 47 here), by number.
pub fn fault_names(bits: u64) -> Vec<String> {
    (0..48)
        .filter(|b| bits & (1 << b) != 0)
        .map(|b| fault_of_bit(b).map_or_else(|| format!("bit_{b}"), |f| f.name().to_string()))
        .collect()
}

/// What one poll read.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Reading {
    /// 601's local date and time.
    pub utc: Option<String>,
    /// 601 `ElTrgt`, `AzTrgt`, degrees as text.
    pub target_deg: Option<(String, String)>,
    /// 601 `ElPos`, `AzPos`.
    pub position_deg: Option<(String, String)>,
    /// The vendor model's mode, by name.
    pub mode: String,
    /// The vendor model's faults, by name.
    pub faults: Vec<String>,
    /// Model 305's latitude and longitude, degrees.
    pub site_deg: Option<(String, String)>,
}

impl Reading {
    /// The poll as a status line (see the module's documentation).
    pub fn line(&self) -> String {
        let mut l = format!("status mode={}", self.mode);
        l.push_str(&format!(" utc={}", self.utc.as_deref().unwrap_or("none")));
        if let Some((lat, lon)) = &self.site_deg {
            l.push_str(&format!(" lat={lat} lon={lon} site=gps"));
        }
        let faults = if self.faults.is_empty() {
            "none".to_string()
        } else {
            self.faults.join(",")
        };
        l.push_str(&format!(" faults={faults}"));
        let pair = |p: &Option<(String, String)>| match p {
            Some((e, a)) => (e.clone(), a.clone()),
            None => ("none".into(), "none".into()),
        };
        let (te, ta) = pair(&self.target_deg);
        let (pe, pa) = pair(&self.position_deg);
        l.push_str(&format!(" target_el={te} target_az={ta} el={pe} az={pa}"));
        l
    }
}

/// Reads the whole of `model` up to `want` registers after ID and L.
fn read_model(c: &mut Client, model: Model, want: u16) -> Result<Vec<u16>, PollError> {
    let count = 2 + model.len.min(want);
    let regs = c.read_holding(model.addr, count)?;
    if regs.first() != Some(&model.id) {
        return Err(PollError::Map(format!(
            "register {} reads {:?}, not model {}'s ID",
            model.addr,
            regs.first(),
            model.id
        )));
    }
    Ok(regs)
}

/// Model 1's model (`Md`) and version (`Vr`).
pub fn identity(c: &mut Client, map: &Map) -> Result<Option<(String, String)>, PollError> {
    let Some(m) = map.find(m1::ID) else {
        return Ok(None);
    };
    let r = read_model(c, m, m1::LEN)?;
    let s = |at: u16, n: u16| text(r.get(usize::from(at)..usize::from(at + n)).unwrap_or(&[]));
    Ok(Some((s(m1::MD, 16), s(m1::VR, 8))))
}

/// One poll: models 601, 64201 and 305.
pub fn poll(c: &mut Client, map: &Map, utc_offset_s: i32) -> Result<Reading, PollError> {
    let tracker = map
        .find(m601::ID)
        .ok_or_else(|| PollError::Map("no model 601 in the map".into()))?;
    let vendor = map
        .find(m64201::ID)
        .ok_or_else(|| PollError::Map(format!("no model {} in the map", m64201::ID)))?;
    let t = read_model(c, tracker, m601::LEN)?;
    if t.len() < usize::from(2 + m601::LEN) {
        return Err(PollError::Map(format!(
            "model 601 of L {}: no tracker block",
            tracker.len
        )));
    }
    let at = |off: u16| usize::from(off);
    let sf = t[at(m601::DGR_SF)] as i16;
    let angles = |off: u16| -> Option<(String, String)> {
        let el = int32(&t, at(off))?;
        let az = int32(&t, at(off) + 2)?;
        Some((scaled(el, sf)?, scaled(az, sf)?))
    };
    let v = read_model(c, vendor, m64201::LEN)?;
    if v.len() < usize::from(2 + m64201::LEN) {
        return Err(PollError::Map(format!(
            "model {} of L {}: too short",
            m64201::ID,
            vendor.len
        )));
    }
    let flt = (u64::from(v[at(m64201::FLT2)]) << 32)
        | (u64::from(v[at(m64201::FLT)]) << 16)
        | u64::from(v[at(m64201::FLT) + 1]);
    let site_deg = match map.find(m305::ID) {
        Some(g) => {
            let r = read_model(c, g, m305::LEN)?;
            match (int32(&r, at(m305::LAT)), int32(&r, at(m305::LONG))) {
                (Some(lat), Some(lon)) => e7_degrees(lat).zip(e7_degrees(lon)),
                _ => None,
            }
        }
        None => None,
    };
    Ok(Reading {
        utc: utc_of_local(
            &t[at(m601::DT_LOC)..at(m601::DT_LOC + 5)],
            &t[at(m601::TM_LOC)..at(m601::TM_LOC + 3)],
            utc_offset_s,
        ),
        target_deg: angles(m601::EL_TRGT),
        position_deg: angles(m601::EL_POS),
        mode: mode_name(v[at(m64201::MODE)]),
        faults: fault_names(flt),
        site_deg,
    })
}

/// The settings of a `--modbus` session.
#[derive(Debug, Clone, PartialEq)]
pub struct Session {
    pub path: String,
    pub baud: u32,
    pub parity: serialport::Parity,
    pub address: u8,
    /// Seconds between polls.
    pub every_s: f64,
    /// Stop this long after opening the port (`None`: never).
    pub seconds: Option<f64>,
    /// Longest wait for a reply.
    pub reply_timeout_s: f64,
    /// The tracker's `site.utc_offset_h` as seconds east of UTC
    /// (`suntracker::sunspec::utc_offset_s`): 601's local time less it is
    /// the UTC printed.
    pub utc_offset_s: i32,
}

/// Polls by outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counts {
    pub polls: u64,
    pub answered: u64,
    pub timeouts: u64,
    pub crc_errors: u64,
    pub exceptions: u64,
    /// Replies that do not answer the request, a map that is not a
    /// tracker's, port errors.
    pub other: u64,
}

impl Counts {
    pub fn missed(&self) -> u64 {
        self.polls - self.answered
    }

    fn count(&mut self, e: &PollError) {
        use modbus_client::Error;
        match e {
            PollError::Modbus(Error::Timeout { .. }) => self.timeouts += 1,
            PollError::Modbus(Error::Crc { .. }) => self.crc_errors += 1,
            PollError::Modbus(Error::Exception { .. }) => self.exceptions += 1,
            _ => self.other += 1,
        }
    }
}

impl fmt::Display for Counts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} polls: {} answered, {} missed ({} time-outs, {} CRC errors, {} exceptions, {} other)",
            self.polls,
            self.answered,
            self.missed(),
            self.timeouts,
            self.crc_errors,
            self.exceptions,
            self.other
        )
    }
}

/// Where a session's output goes.
pub trait Polls {
    /// A poll's line.
    fn line(&mut self, text: &str) -> Result<(), String>;
    /// The map was found: where, and model 1's model and version.
    fn found(&mut self, map: &Map, identity: Option<(String, String)>) -> Result<(), String>;
    /// A poll failed (`at_s`: seconds since the session started).
    fn missed(&mut self, at_s: f64, error: &PollError);
}

fn seconds(s: f64) -> Duration {
    Duration::from_secs_f64(s.clamp(0.0, 1e9))
}

/// Runs a session: `Err` when the port cannot be opened, else the counts
/// and the error that cut it short, if one did.
pub fn run(s: &Session, out: &mut dyn Polls) -> Result<(Counts, Option<String>), String> {
    let port = modbus_client::open(&s.path, s.baud, s.parity)?;
    let mut client = Client::new(port, s.address, s.baud, seconds(s.reply_timeout_s));
    let mut counts = Counts::default();
    let start = Instant::now();
    let end = s.seconds.map(|x| start + seconds(x));
    let every = seconds(s.every_s);
    let mut map: Option<Map> = None;
    let mut due = start;
    while end.is_none_or(|e| due <= e) {
        if let Some(wait) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        counts.polls += 1;
        let mut out_error = None;
        let result = (|| -> Result<Reading, PollError> {
            let m = match map.take() {
                Some(m) => m,
                None => {
                    let m = discover(&mut client)?;
                    let id = identity(&mut client, &m)?;
                    out_error = out.found(&m, id).err();
                    m
                }
            };
            let r = poll(&mut client, &m, s.utc_offset_s);
            // An exception or a map that no longer fits: find it again
            // (the board may have restarted with another map).
            if !matches!(
                r,
                Err(PollError::Map(_) | PollError::Modbus(modbus_client::Error::Exception { .. }))
            ) {
                map = Some(m);
            }
            r
        })();
        if out_error.is_some() {
            return Ok((counts, out_error));
        }
        match result {
            Ok(reading) => {
                counts.answered += 1;
                if let Err(e) = out.line(&reading.line()) {
                    return Ok((counts, Some(e)));
                }
            }
            Err(e) => {
                counts.count(&e);
                out.missed(start.elapsed().as_secs_f64(), &e);
            }
        }
        // The next poll at its time; a late one skips the times it missed.
        due += every;
        let now = Instant::now();
        if due < now && !every.is_zero() {
            let behind = (now - due).as_nanos() / every.as_nanos();
            due += every * u32::try_from(behind + 1).unwrap_or(u32::MAX);
        }
    }
    Ok((counts, None))
}
