//! The batch logic of `examples/solar_position.rs`: arguments, CSV in, CSV
//! out, on all cores. Kept apart so that `tests/solar_position_cli.rs` can
//! include it.
//!
//! # Pipeline
//!
//! `std::thread::scope` with channels, no scheduler crate: one reader, N
//! workers, and the calling thread as the writer.
//! - The reader cuts the input into chunks of about [`CHUNK_BYTES`] that end
//!   on a record boundary: a line end outside quotes, found by [`Scanner`]
//!   with the CSV reader's own quoting rules (csv-core's state machine), so
//!   each chunk parses exactly as it would inside the whole stream.
//! - A worker parses a chunk with the `csv` crate, computes each row and
//!   formats the chunk's output rows into the chunk's output buffer.
//! - The writer puts the chunks' outputs in input order and writes them.
//!
//! A fixed pool of [`SLOTS_PER_WORKER`] × workers chunk buffers goes round
//! (reader → worker → writer → reader): the reader waits for a free one, so
//! memory stays bounded whatever the input size (only a single record
//! longer than a chunk makes its chunk grow). `rayon` was not used: its
//! order-keeping `collect` works on a batch held in memory, so the reading
//! and writing of a batch would wait for its computation, and `par_bridge`
//! loses the order; the pipeline overlaps all three.

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::num::NonZeroUsize;
use std::sync::mpsc::{channel, sync_channel, Receiver, Sender, SyncSender};
use std::sync::{LazyLock, Mutex};

use sun_algos::{Algorithm, Atmosphere, Float, Options, Site, UtcTime};

#[path = "../common/cli.rs"]
pub mod cli;
#[path = "decimal.rs"]
mod decimal;

use cli::Parsed;

/// Floating-point type to compute in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FloatKind {
    /// Single precision.
    F32,
    /// Double precision.
    F64,
}

/// Parsed command line.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    pub algorithm: Algorithm,
    pub float: FloatKind,
    /// Pressure (hPa) and temperature (°C): apparent positions when given.
    pub atmosphere: Option<(f64, f64)>,
    /// Compute rows outside the algorithm's validity range instead of
    /// reporting an error for them.
    pub allow_out_of_range: bool,
    /// Worker threads; `None`: one per core.
    pub threads: Option<NonZeroUsize>,
}

/// The program name in messages.
pub const TOOL: &str = "solar_position";

/// The synopsis of `--help`.
pub const SYNOPSIS: &str = "--algorithm NAME --float f32|f64 [--pressure HPA --temperature C] \
[--allow-out-of-range] [--threads N] < in.csv > out.csv";

/// The text of `--help`: every option with its default, every algorithm
/// with its validity years (from `sun_algos::Algorithm`).
pub fn help() -> cli::Help {
    use cli::opt;
    cli::Help {
        tool: TOOL,
        synopsis: SYNOPSIS,
        about: "\
Sun positions (zenith and azimuth) for the rows of a CSV file, read from stdin and written to
stdout, computed on all cores.",
        options: vec![
            opt(
                "--algorithm NAME",
                "solar position algorithm (list below); required",
                "",
            ),
            opt(
                "--float f32|f64",
                "floating-point type of the computation; required",
                "",
            ),
            opt(
                "--pressure HPA",
                "air pressure for apparent (refracted) positions; with --temperature",
                "none (geometric positions)",
            ),
            opt(
                "--temperature C",
                "air temperature for apparent positions; with --pressure",
                "none",
            ),
            opt(
                "--allow-out-of-range",
                "also compute instants outside the algorithm's validity years \
                 instead of giving those rows an error",
                "off",
            ),
            opt(
                "--threads N",
                "worker threads (the output is the same for any N)",
                "one per core",
            ),
        ],
        algorithms: true,
        notes: "\
input: CSV (RFC 4180: quoted fields, a UTF-8 BOM, CRLF line ends) whose header contains
utc,latitude,longitude and optionally delta_t (seconds; the built-in model when absent or empty);
other columns are ignored, in any order. utc like 2031-04-05T06:07:08Z.
output: utc,latitude,longitude,zenith,azimuth,error, degrees with 9 decimals, one row per input
row in input order; a row that cannot be decoded or computed gets an error text (zenith and
azimuth empty) and the run goes on.
exit status: 0 done (error rows included), 1 read or write error or no usable header, 2 usage
error.",
    }
}

/// The help text, as `--help` prints it.
pub static USAGE: LazyLock<String> = LazyLock::new(|| help().render());

/// Parses the arguments (without the program name): a run, or `--help`.
/// Errors name the unknown option, the bad value or the incomplete pair.
pub fn parse_command<S: AsRef<str>>(args: &[S]) -> Result<Parsed<Config>, String> {
    use cli::{Long, Short};
    let args: Vec<String> = args.iter().map(|a| a.as_ref().to_owned()).collect();
    let mut algorithm = None;
    let mut float = None;
    let mut pressure = None;
    let mut temperature = None;
    let mut allow_out_of_range = false;
    let mut threads = None;
    let mut p = cli::parser(&args);
    while let Some(arg) = p.next().map_err(cli::error)? {
        match arg {
            Short('h') | Long("help") => return Ok(Parsed::Help),
            Long("algorithm") => algorithm = Some(cli::algorithm(&mut p, "--algorithm")?),
            Long("float") => {
                float = Some(cli::choice(
                    &mut p,
                    "--float",
                    &[("f32", FloatKind::F32), ("f64", FloatKind::F64)],
                )?)
            }
            Long("pressure") => pressure = Some(cli::number(&mut p, "--pressure")?),
            Long("temperature") => temperature = Some(cli::number(&mut p, "--temperature")?),
            Long("allow-out-of-range") => allow_out_of_range = true,
            Long("threads") => {
                threads = Some(cli::value(
                    &mut p,
                    "--threads",
                    "a whole number from 1",
                    |v| v.parse::<NonZeroUsize>().ok(),
                )?)
            }
            other => return Err(cli::unexpected(other)),
        }
    }
    let atmosphere = match (pressure, temperature) {
        (None, None) => None,
        (Some(p), Some(t)) => {
            Atmosphere::new(p, t).map_err(|e| format!("--pressure/--temperature: {e}"))?;
            Some((p, t))
        }
        (Some(_), None) => return Err("--pressure needs --temperature (they go together)".into()),
        (None, Some(_)) => return Err("--temperature needs --pressure (they go together)".into()),
    };
    Ok(Parsed::Run(Config {
        algorithm: algorithm.ok_or("--algorithm is required (--help lists the algorithms)")?,
        float: float.ok_or("--float is required: f32 or f64")?,
        atmosphere,
        allow_out_of_range,
        threads,
    }))
}

/// Parses the arguments of a run (without the program name); `--help` is
/// an error here (see [`parse_command`]). Used by tests/solar_position_cli.rs.
#[allow(dead_code)]
pub fn parse_args<S: AsRef<str>>(args: &[S]) -> Result<Config, String> {
    match parse_command(args)? {
        Parsed::Run(cfg) => Ok(cfg),
        Parsed::Help => Err("--help asks for the help text, not a run".into()),
    }
}

/// The tool on `args` (without the program name), reading `input`: the
/// help, a usage error (`solar_position: message` on `err`, exit code 2),
/// or a run (exit code 0; 1 after a read or write error or without a
/// usable header, the reason on `err`). `main` passes stdin, stdout and
/// stderr.
pub fn command<R: Read + Send>(
    args: &[String],
    input: R,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> u8 {
    let cfg = match parse_command(args) {
        Ok(Parsed::Run(cfg)) => cfg,
        Ok(Parsed::Help) => {
            // As cli::print_help: a closed stdout is not an error.
            let _ = out.write_all(USAGE.as_bytes());
            let _ = out.flush();
            return 0;
        }
        Err(e) => return cli::usage_error(TOOL, &e, err),
    };
    match run(&cfg, input, out) {
        Ok(()) => 0,
        Err(e) => {
            // Best effort: nothing else can be done with a closed stderr.
            let _ = writeln!(err, "{TOOL}: {e}");
            1
        }
    }
}

/// Input bytes per chunk handed to a worker (a whole number of records;
/// about 5,000 rows of `utc,latitude,longitude,delta_t`).
pub const CHUNK_BYTES: usize = 256 * 1024;
/// Chunks in flight per worker: enough that no worker waits for the
/// reader or the writer, few enough for a bounded footprint (8 chunks of
/// input and output on 2 cores: about 5 MB).
pub const SLOTS_PER_WORKER: usize = 4;
/// Smallest read while a record is longer than the chunk.
const READ_MORE_BYTES: usize = 64 * 1024;

/// The roles of the used columns, in the order of [`Columns::used`].
const UTC: usize = 0;
const LATITUDE: usize = 1;
const LONGITUDE: usize = 2;
const DELTA_T: usize = 3;
const ROLE_NAMES: [&str; 4] = ["utc", "latitude", "longitude", "delta_t"];

/// Column positions of the input header.
struct Columns {
    utc: usize,
    latitude: usize,
    longitude: usize,
    /// Number of header fields; every data row must have as many.
    len: usize,
    /// (column, role) of the columns the tool reads, in column order: the
    /// order in which their UTF-8 is checked (the first bad one is named).
    used: Vec<(usize, usize)>,
}

fn columns(header: &csv::ByteRecord) -> Result<Columns, String> {
    let names: Vec<String> = header
        .iter()
        .map(|f| {
            String::from_utf8_lossy(f)
                .trim_start_matches('\u{feff}')
                .trim()
                .to_owned()
        })
        .collect();
    let find = |n: &str| names.iter().position(|h| h.eq_ignore_ascii_case(n));
    let need = |n: &str| find(n).ok_or_else(|| format!("input header has no {n} column"));
    let (utc, latitude, longitude) = (need("utc")?, need("latitude")?, need("longitude")?);
    let mut used = vec![(utc, UTC), (latitude, LATITUDE), (longitude, LONGITUDE)];
    used.extend(find("delta_t").map(|c| (c, DELTA_T)));
    used.sort_unstable();
    Ok(Columns {
        utc,
        latitude,
        longitude,
        len: names.len(),
        used,
    })
}

/// A line holding nothing but blanks: not a data row (as a blank line).
fn is_blank(record: &csv::ByteRecord) -> bool {
    record.len() <= 1 && record.iter().all(|f| f.trim_ascii().is_empty())
}

/// Where records end, by the rules of the `csv` reader's default
/// configuration (csv-core's state machine: `"` quotes, doubled inside
/// quotes, `,` separates, CR or LF ends a record outside quotes; a `"` that
/// does not open a field is an ordinary byte). Carries its state across
/// calls, so the input can be scanned as it arrives.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
enum Scanner {
    /// At the start of a record or field.
    #[default]
    FieldStart,
    /// In an unquoted field.
    Unquoted,
    /// In a quoted field.
    Quoted,
    /// Just after a `"` in a quoted field: a second `"` continues the
    /// field, anything else closes the quotes.
    QuoteInQuoted,
}

impl Scanner {
    /// Consumes one byte; true when it ends a record (a cut point after it
    /// leaves the parser at the start of a record).
    #[inline]
    fn step(&mut self, b: u8) -> bool {
        use Scanner::*;
        let (next, ends) = match (*self, b) {
            (Quoted, b'"') => (QuoteInQuoted, false),
            (Quoted, _) => (Quoted, false),
            (FieldStart, b'"') | (QuoteInQuoted, b'"') => (Quoted, false),
            (_, b',') => (FieldStart, false),
            (_, b'\n' | b'\r') => (FieldStart, true),
            _ => (Unquoted, false),
        };
        *self = next;
        ends
    }

    /// Consumes `bytes`; the position just after the first record end.
    fn first_end(&mut self, bytes: &[u8]) -> Option<usize> {
        bytes.iter().position(|&b| self.step(b)).map(|i| i + 1)
    }

    /// Consumes all of `bytes`; the position just after the last record
    /// end among them.
    fn last_end(&mut self, bytes: &[u8]) -> Option<usize> {
        if *self != Scanner::Quoted && !bytes.contains(&b'"') {
            // No quote: no quoted state to enter, every CR or LF ends a
            // record; only the bytes after the last one set the state.
            let last = bytes.iter().rposition(|&b| b == b'\n' || b == b'\r');
            let tail = match last {
                Some(i) => {
                    *self = Scanner::FieldStart;
                    &bytes[i + 1..]
                }
                None => bytes,
            };
            for &b in tail {
                self.step(b);
            }
            return last.map(|i| i + 1);
        }
        let mut last = None;
        for (i, &b) in bytes.iter().enumerate() {
            if self.step(b) {
                last = Some(i + 1);
            }
        }
        last
    }
}

/// A CSV reader (the tool's configuration) over whole records. The
/// leading line end is skipped by the parser (an empty line) but makes the
/// first read non-empty, so a BOM at the start of `bytes` is not taken as
/// the stream's BOM (csv-core drops a BOM only before the first byte of
/// the whole input, which the header reader saw).
fn records_reader(bytes: &[u8], trim: csv::Trim) -> csv::Reader<std::io::Chain<&[u8], &[u8]>> {
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(trim)
        .from_reader((&b"\n"[..]).chain(bytes))
}

/// Reads until `buf` holds `want` more bytes or the input ends; true at the
/// end of the input.
fn read_more<R: Read>(input: &mut R, buf: &mut Vec<u8>, want: usize) -> std::io::Result<bool> {
    let got = input.take(want as u64).read_to_end(buf)?;
    Ok(got < want)
}

/// The header: the first non-blank record. Returns it with the input bytes
/// read after it (not yet scanned) and whether the input has ended.
fn read_header<R: Read>(input: &mut R) -> Result<(csv::ByteRecord, Vec<u8>, bool), String> {
    let rd = |e: std::io::Error| format!("read: {e}");
    let mut buf = Vec::with_capacity(CHUNK_BYTES);
    let mut eof = read_more(input, &mut buf, CHUNK_BYTES).map_err(rd)?;
    while buf.len() < 3 && !eof {
        eof = read_more(input, &mut buf, CHUNK_BYTES).map_err(rd)?;
    }
    // The UTF-8 BOM before the first byte, dropped as csv-core does.
    let mut start = if buf.starts_with(b"\xef\xbb\xbf") {
        3
    } else {
        0
    };
    let mut scanner = Scanner::default();
    let mut scanned = start;
    loop {
        let end = match scanner.first_end(&buf[scanned..]) {
            Some(n) => scanned + n,
            None if eof => buf.len(),
            None => {
                // Keep only the record being read.
                buf.drain(..start);
                scanned = buf.len();
                start = 0;
                eof = read_more(input, &mut buf, CHUNK_BYTES).map_err(rd)?;
                continue;
            }
        };
        let mut record = csv::ByteRecord::new();
        let mut reader = records_reader(&buf[start..end], csv::Trim::All);
        let found = reader
            .read_byte_record(&mut record)
            .map_err(|e| format!("read: {e}"))?;
        if found && !is_blank(&record) {
            return Ok((record, buf.split_off(end), eof));
        }
        if end == buf.len() && eof {
            return Err("empty input: no header".into());
        }
        start = end;
        scanned = end;
    }
}

/// A chunk on its way round: input records, then their output rows.
#[derive(Default)]
struct Slot {
    input: Vec<u8>,
    output: Vec<u8>,
    /// A read error inside the chunk (reading from memory: not expected).
    error: Option<String>,
}

/// Reads CSV from `input` and writes one result row per data row to
/// `output`. RFC 4180 input: quoted fields (with commas, quotes, line
/// breaks), a UTF-8 BOM, LF or CRLF line ends; blank lines are skipped.
/// Errors only for I/O and a missing header; a row that cannot be decoded
/// (a used field not UTF-8, a field count unlike the header's, a bad number
/// or date) or computed gives an error row and the run goes on. After a
/// read error the rows read completely before it are written, then the
/// error is returned.
///
/// Parallel on `cfg.threads` workers (default: one per core); the output
/// is the same bytes whatever the number of threads.
pub fn run<R: Read + Send, W: Write>(
    cfg: &Config,
    mut input: R,
    mut output: W,
) -> Result<(), String> {
    let (header, rest, eof) = read_header(&mut input)?;
    let cols = columns(&header)?;
    let wr = |e: std::io::Error| format!("write: {e}");
    output
        .write_all(b"utc,latitude,longitude,zenith,azimuth,error\n")
        .map_err(wr)?;
    let workers = cfg
        .threads
        .or_else(|| std::thread::available_parallelism().ok())
        .map_or(1, NonZeroUsize::get);
    let slots = SLOTS_PER_WORKER * workers;
    let (free_tx, free_rx) = sync_channel::<Slot>(slots);
    for _ in 0..slots {
        // Capacity for every slot: never blocks.
        let _ = free_tx.send(Slot::default());
    }
    // Room for every slot too, so the reader never waits on it (it waits
    // for free slots instead, and stops when the writer stops).
    let (work_tx, work_rx) = sync_channel::<(u64, Slot)>(slots);
    let work_rx = Mutex::new(work_rx);
    let (done_tx, done_rx) = channel::<(u64, Slot)>();
    let result = std::thread::scope(|scope| {
        let reader = scope.spawn(move || read_chunks(input, rest, eof, free_rx, work_tx));
        for _ in 0..workers {
            let done_tx = done_tx.clone();
            let (work_rx, cols) = (&work_rx, &cols);
            scope.spawn(move || compute_chunks(cfg, cols, work_rx, done_tx));
        }
        drop(done_tx);
        // Moves the writer's ends of the channels in: on a write error they
        // close, and the reader and workers stop.
        let written = write_in_order(done_rx, free_tx, &mut output);
        let read = reader
            .join()
            .unwrap_or_else(|_| Err("read: the reader thread stopped".into()));
        written.and(read)
    });
    let flushed = output.flush().map_err(wr);
    result.and(flushed)
}

/// The reader: cuts the input into chunks of whole records and numbers
/// them. `rest` (input read after the header, not yet scanned) starts the
/// first chunk.
fn read_chunks<R: Read>(
    mut input: R,
    mut rest: Vec<u8>,
    mut eof: bool,
    free: Receiver<Slot>,
    work: SyncSender<(u64, Slot)>,
) -> Result<(), String> {
    let mut scanner = Scanner::default();
    // Bytes at the start of `rest` already scanned.
    let mut rest_scanned = 0;
    let mut seq = 0u64;
    while !(eof && rest.is_empty()) {
        let Ok(mut slot) = free.recv() else {
            // The writer stopped (a write error).
            return Ok(());
        };
        slot.input.clear();
        slot.input.append(&mut rest);
        let mut scanned = rest_scanned;
        let mut cut = None;
        let mut read_error = None;
        loop {
            if let Some(n) = scanner.last_end(&slot.input[scanned..]) {
                cut = Some(scanned + n);
            }
            scanned = slot.input.len();
            if eof || (cut.is_some() && slot.input.len() >= CHUNK_BYTES) {
                break;
            }
            let want = CHUNK_BYTES
                .saturating_sub(slot.input.len())
                .max(READ_MORE_BYTES);
            match read_more(&mut input, &mut slot.input, want) {
                Ok(end) => eof = end,
                Err(e) => {
                    read_error = Some(format!("read: {e}"));
                    break;
                }
            }
        }
        if !eof {
            // Whole records only (after a read error, the last one may be
            // cut short: it is dropped with the rest).
            let cut = cut.unwrap_or(0);
            rest.extend_from_slice(&slot.input[cut..]);
            rest_scanned = rest.len();
            slot.input.truncate(cut);
        }
        if !slot.input.is_empty() {
            if work.send((seq, slot)).is_err() {
                return Ok(());
            }
            seq += 1;
        }
        if let Some(e) = read_error {
            return Err(e);
        }
    }
    Ok(())
}

/// A worker: takes chunks, computes their rows, hands them to the writer.
fn compute_chunks(
    cfg: &Config,
    cols: &Columns,
    work: &Mutex<Receiver<(u64, Slot)>>,
    done: Sender<(u64, Slot)>,
) {
    loop {
        // A poisoned lock only means another worker stopped; the receiver
        // is still sound.
        let next = work.lock().unwrap_or_else(|e| e.into_inner()).recv();
        let Ok((seq, mut slot)) = next else {
            return;
        };
        slot.output.clear();
        slot.error = compute_chunk(cfg, cols, &slot.input, &mut slot.output).err();
        if done.send((seq, slot)).is_err() {
            return;
        }
    }
}

/// The writer: outputs in input order, slots back to the reader. Ends when
/// every worker has ended.
fn write_in_order<W: Write>(
    done: Receiver<(u64, Slot)>,
    free: SyncSender<Slot>,
    output: &mut W,
) -> Result<(), String> {
    let mut waiting = BTreeMap::new();
    let mut next = 0u64;
    for (seq, slot) in &done {
        waiting.insert(seq, slot);
        while let Some(mut slot) = waiting.remove(&next) {
            output
                .write_all(&slot.output)
                .map_err(|e| format!("write: {e}"))?;
            if let Some(e) = slot.error.take() {
                return Err(e);
            }
            next += 1;
            // The reader may have finished: then the slot is not needed.
            let _ = free.send(slot);
        }
    }
    Ok(())
}

/// Parses the whole records of `input` and appends one output row per
/// data row to `out`.
fn compute_chunk(
    cfg: &Config,
    cols: &Columns,
    input: &[u8],
    out: &mut Vec<u8>,
) -> Result<(), String> {
    // Untrimmed records: the fields are trimmed as they are used (the
    // reader's own trimming copies every record).
    let mut reader = records_reader(input, csv::Trim::None);
    let mut record = csv::ByteRecord::new();
    while reader
        .read_byte_record(&mut record)
        .map_err(|e| format!("read: {e}"))?
    {
        if !is_blank(&record) {
            push_row(cfg, cols, &record, out);
        }
    }
    Ok(())
}

/// Appends the output row of one data row.
fn push_row(cfg: &Config, cols: &Columns, record: &csv::ByteRecord, out: &mut Vec<u8>) {
    let fields = used_fields(cols, record);
    match &fields {
        // Known to be UTF-8: echoed as they are.
        Ok(f) => {
            for text in [f[UTC], f[LATITUDE], f[LONGITUDE]] {
                push_field(out, text.as_bytes());
                out.push(b',');
            }
        }
        Err(_) => {
            for i in [cols.utc, cols.latitude, cols.longitude] {
                let bytes = record.get(i).map_or(&b""[..], <[u8]>::trim_ascii);
                push_field(out, String::from_utf8_lossy(bytes).as_bytes());
                out.push(b',');
            }
        }
    }
    let result = fields.and_then(|fields| match cfg.float {
        FloatKind::F32 => row::<f32>(cfg, &fields),
        FloatKind::F64 => row::<f64>(cfg, &fields),
    });
    match result {
        Ok((zenith, azimuth)) => {
            decimal::push_fixed9(out, zenith);
            out.push(b',');
            decimal::push_fixed9(out, azimuth);
            out.extend_from_slice(b",\n");
        }
        Err(e) => {
            out.extend_from_slice(b",,");
            push_field(out, e.replace(',', ";").as_bytes());
            out.push(b'\n');
        }
    }
}

/// Appends a field as the `csv` writer does: quoted when it holds a comma,
/// a quote, CR or LF, with quotes doubled.
fn push_field(out: &mut Vec<u8>, field: &[u8]) {
    if !field
        .iter()
        .any(|&b| matches!(b, b',' | b'"' | b'\r' | b'\n'))
    {
        out.extend_from_slice(field);
        return;
    }
    out.push(b'"');
    for &b in field {
        if b == b'"' {
            out.push(b'"');
        }
        out.push(b);
    }
    out.push(b'"');
}

/// The used fields of a data row as text, by role (utc, latitude,
/// longitude, delta_t; `""` when absent): the row must have the header's
/// number of fields, and the used fields must be UTF-8 (the first one, in
/// column order, that is not is named). Other fields are ignored, whatever
/// their bytes.
fn used_fields<'r>(cols: &Columns, record: &'r csv::ByteRecord) -> Result<[&'r str; 4], String> {
    if record.len() != cols.len {
        return Err(format!(
            "wrong number of fields: {} for {} header columns",
            record.len(),
            cols.len
        ));
    }
    let mut fields = [""; 4];
    for &(column, role) in &cols.used {
        let bytes = record.get(column).map_or(&b""[..], <[u8]>::trim_ascii);
        fields[role] = std::str::from_utf8(bytes)
            .map_err(|_| format!("bad {}: not UTF-8", ROLE_NAMES[role]))?;
    }
    Ok(fields)
}

/// `YYYY-MM-DDTHH:MM:SSZ`, the usual form, without the general parser's
/// splitting; anything else goes to `UtcTime::from_str`. The same instant
/// or error either way: for these 20 bytes `from_str` reads the same six
/// numbers and calls the same constructor with 0 ms.
fn parse_utc(s: &str) -> Result<UtcTime, sun_algos::Error> {
    let b = s.as_bytes();
    let digits = |r: std::ops::Range<usize>| {
        b[r].iter().try_fold(0u32, |n, &d| {
            d.is_ascii_digit().then(|| n * 10 + u32::from(d - b'0'))
        })
    };
    if b.len() == 20
        && (b[4], b[7], b[10], b[13], b[16], b[19]) == (b'-', b'-', b'T', b':', b':', b'Z')
    {
        if let (Some(y), Some(mo), Some(d), Some(h), Some(mi), Some(sec)) = (
            digits(0..4),
            digits(5..7),
            digits(8..10),
            digits(11..13),
            digits(14..16),
            digits(17..19),
        ) {
            // Four digits fit an i32 and two a u8.
            return UtcTime::from_ymd_hms_milli(
                y as i32, mo as u8, d as u8, h as u8, mi as u8, sec as u8, 0,
            );
        }
    }
    s.parse()
}

/// Zenith and azimuth (degrees) of one row, or a short reason.
fn row<T: Float>(cfg: &Config, fields: &[&str; 4]) -> Result<(f64, f64), String> {
    let get = |role: usize| {
        Some(fields[role])
            .filter(|s| !s.is_empty())
            .ok_or_else(|| format!("missing {}", ROLE_NAMES[role]))
    };
    let time = parse_utc(get(UTC)?).map_err(|e| format!("bad utc: {e}"))?;
    let number = |role: usize| -> Result<T, String> {
        get(role)?
            .parse::<f64>()
            .map(T::from_f64)
            .map_err(|_| format!("bad {}", ROLE_NAMES[role]))
    };
    let site = Site::new(number(LATITUDE)?, number(LONGITUDE)?).map_err(|e| e.to_string())?;
    let delta_t_s = match fields[DELTA_T] {
        "" => None,
        _ => Some(number(DELTA_T)?),
    };
    let atmosphere = match cfg.atmosphere {
        None => None,
        Some((p, t)) => {
            Some(Atmosphere::new(T::from_f64(p), T::from_f64(t)).map_err(|e| e.to_string())?)
        }
    };
    let options = Options {
        delta_t_s,
        atmosphere,
        allow_out_of_range: cfg.allow_out_of_range,
    };
    let p = cfg
        .algorithm
        .position(&time, &site, &options)
        .map_err(|e| e.to_string())?;
    Ok((p.zenith_deg.to_f64(), p.azimuth_deg.to_f64()))
}

#[cfg(test)]
mod tests {
    //! The pipeline's own rules; the tool's behaviour is tested through
    //! `run` in tests/solar_position_cli.rs.

    use super::*;

    /// The records of `input` by the `csv` reader over the whole stream.
    fn whole_stream(input: &[u8]) -> Vec<csv::ByteRecord> {
        csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(input)
            .byte_records()
            .map(|r| r.expect("in-memory read"))
            .collect()
    }

    /// The same records from pieces cut after every record end the
    /// scanner reports, each parsed by its own reader.
    fn cut_at_every_end(input: &[u8]) -> Vec<csv::ByteRecord> {
        let body = input.strip_prefix(b"\xef\xbb\xbf").unwrap_or(input);
        let mut scanner = Scanner::default();
        let mut records = Vec::new();
        let mut start = 0;
        while start < body.len() {
            let end = scanner
                .first_end(&body[start..])
                .map_or(body.len(), |n| start + n);
            let mut reader = records_reader(&body[start..end], csv::Trim::None);
            records.extend(reader.byte_records().map(|r| r.expect("in-memory read")));
            start = end;
        }
        records
    }

    /// Cutting at the scanner's record ends never changes a record: quoted
    /// separators and line breaks, doubled quotes, quotes that do not open
    /// a field, text after a closing quote, CR, LF and CRLF, empty lines,
    /// a BOM at the start and one later.
    #[test]
    fn record_ends_agree_with_the_csv_reader() {
        let cases: [&[u8]; 10] = [
            b"a,b\nc,d\n",
            b"\xef\xbb\xbf\"a\nb\",c\r\n\"x\"\"y\",\"\r\"\r\nlast",
            b"a\"b,c\n\"d\"e\"f\ng\n",
            b"\n\n\r\n,\n\"\"\n\r\r\n a , \"b\" \n",
            b"\"unterminated,\nquote\n",
            b"x\r\ny\rz\n\xef\xbb\xbfw,v\n",
            b"\"\"\"\",\"a\"\"\nb\"\"\"\n",
            b"a,\"b\"\"\"c\n\"\nd\n",
            b"",
            b"\"",
        ];
        for case in cases {
            assert_eq!(
                whole_stream(case),
                cut_at_every_end(case),
                "{:?}",
                String::from_utf8_lossy(case)
            );
        }
        // Every 5-byte string over the bytes that matter.
        let alphabet = b"a\",\r\n";
        for i in 0..alphabet.len().pow(5) {
            let mut case = Vec::new();
            let mut k = i;
            for _ in 0..5 {
                case.push(alphabet[k % alphabet.len()]);
                k /= alphabet.len();
            }
            assert_eq!(whole_stream(&case), cut_at_every_end(&case), "{case:?}");
        }
    }

    /// `last_end`, with its shortcut for pieces without quotes, agrees
    /// with single steps from every state.
    #[test]
    fn last_end_agrees_with_single_steps() {
        let alphabet = b"a\",\r\n";
        for i in 0..alphabet.len().pow(6) {
            let case: Vec<u8> = (0..6)
                .map(|d| alphabet[i / alphabet.len().pow(d) % alphabet.len()])
                .collect();
            for start in [
                Scanner::FieldStart,
                Scanner::Unquoted,
                Scanner::Quoted,
                Scanner::QuoteInQuoted,
            ] {
                let mut fast = start;
                let got = fast.last_end(&case);
                let mut slow = start;
                let mut want = None;
                for (j, &b) in case.iter().enumerate() {
                    if slow.step(b) {
                        want = Some(j + 1);
                    }
                }
                assert_eq!((got, fast), (want, slow), "{start:?} {case:?}");
            }
        }
    }

    #[test]
    fn help_lists_every_algorithm_with_its_years_and_every_default() {
        for a in Algorithm::ALL {
            let (first, last) = a.validity_years();
            let line = USAGE
                .lines()
                .find(|l| l.split_whitespace().next() == Some(a.name()))
                .unwrap_or_else(|| panic!("{} missing", a.name()));
            assert!(line.ends_with(&format!(" {first} to {last}")), "{line}");
        }
        for o in help().options {
            assert!(
                !o.default.is_empty() || o.help.contains("required"),
                "{}",
                o.flag
            );
        }
    }

    #[test]
    fn help_unknown_options_and_pairs() {
        assert_eq!(parse_command(&["--help"]), Ok(Parsed::Help));
        assert_eq!(parse_command(&["-h"]), Ok(Parsed::Help));
        let e = parse_command(&["--algorithm", "spa", "--float", "f64", "--fast"]).unwrap_err();
        assert!(e.contains("--fast"), "{e}");
        let e = parse_command(&["--float", "f64", "--algorithm", "spa", "--temperature", "9"])
            .unwrap_err();
        assert!(
            e.contains("--pressure") && e.contains("--temperature"),
            "{e}"
        );
        let e =
            parse_command(&["--algorithm", "spa", "--float", "f64", "--threads", "0"]).unwrap_err();
        assert!(e.contains("--threads"), "{e}");
        assert_eq!(
            parse_args(&["--algorithm=spa", "--float=f32", "--threads", "3"]).map(|c| (
                c.algorithm,
                c.float,
                c.threads.map(NonZeroUsize::get)
            )),
            Ok((Algorithm::Spa, FloatKind::F32, Some(3)))
        );
    }

    /// Exit codes and streams of the whole command.
    #[test]
    fn command_exit_codes_and_streams() {
        let call = |args: &[&str], input: &str| {
            let args: Vec<String> = args.iter().map(|a| a.to_string()).collect();
            let (mut out, mut err) = (Vec::new(), Vec::new());
            let code = command(&args, input.as_bytes(), &mut out, &mut err);
            let text = |b: Vec<u8>| String::from_utf8(b).expect("UTF-8");
            (code, text(out), text(err))
        };
        let (code, out, err) = call(&["--algorithm", "spa", "-h"], "");
        assert_eq!((code, out.as_str(), err.as_str()), (0, USAGE.as_str(), ""));
        let (code, out, err) = call(&["--algorithm", "spa", "--float", "f64", "--fast"], "");
        assert_eq!((code, out.as_str()), (2, ""));
        assert!(
            err.starts_with("solar_position: ") && err.contains("--fast"),
            "{err}"
        );
        let ok = "utc,latitude,longitude\n2034-09-01T21:58:29Z,44.28637,-92.64742\nx,1,2\n";
        let (code, out, err) = call(&["--algorithm", "spa", "--float", "f64"], ok);
        assert_eq!((code, out.lines().count(), err.as_str()), (0, 3, ""));
        let (code, out, err) = call(&["--algorithm", "spa", "--float", "f64"], "time,lat,lon\n");
        assert_eq!((code, out.as_str()), (1, ""));
        assert!(err.contains("no utc column"), "{err}");
    }

    /// The usual instant form and the general parser agree, on good and
    /// bad dates alike.
    #[test]
    fn fast_utc_form_is_the_general_parser() {
        for s in [
            "2031-04-05T06:07:08Z",
            "2000-02-29T23:59:59Z",
            "2100-02-29T00:00:00Z",
            "2030-13-01T00:00:00Z",
            "2030-00-10T00:00:00Z",
            "2030-06-31T00:00:00Z",
            "2030-06-01T24:00:00Z",
            "2030-06-01T23:60:00Z",
            "2030-06-01T23:59:60Z",
            "0000-01-01T00:00:00Z",
            "9999-12-31T23:59:59Z",
            "2030-06-01T12:00:0xZ",
            "2030-06-01 12:00:00Z",
        ] {
            assert_eq!(parse_utc(s), s.parse::<UtcTime>(), "{s}");
        }
    }

    /// One to eight workers, chunks much smaller than a record set: the
    /// same bytes, in input order.
    #[test]
    fn output_does_not_depend_on_the_thread_count() {
        let mut input = String::from("utc,latitude,longitude,delta_t,note\n");
        for i in 0..30_000u32 {
            let quoted = if i % 7 == 0 { "\"a,\nb\"" } else { "x" };
            input.push_str(&format!(
                "2030-{:02}-{:02}T{:02}:{:02}:00Z,{}.{},{},{},{quoted}\n",
                1 + i % 12,
                1 + i % 28,
                i % 24,
                i % 60,
                (i % 180) as i32 - 90,
                i % 1000,
                (i % 360) as i32 - 180,
                if i % 11 == 0 {
                    String::new()
                } else {
                    "69.5".into()
                }
            ));
        }
        let mut reference = None;
        for threads in 1..=8 {
            let cfg = Config {
                algorithm: Algorithm::Psa2020,
                float: FloatKind::F64,
                atmosphere: None,
                allow_out_of_range: false,
                threads: NonZeroUsize::new(threads),
            };
            let mut out = Vec::new();
            run(&cfg, input.as_bytes(), &mut out).expect("run");
            assert_eq!(out.iter().filter(|&&b| b == b'\n').count(), 30_001);
            match &reference {
                None => reference = Some(out),
                Some(r) => assert!(r == &out, "{threads} threads"),
            }
        }
    }
}
