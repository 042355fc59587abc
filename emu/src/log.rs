//! The board's log on USART0 (115200 8N1): line assembly and the parsed
//! shapes the harness checks. Other lines are kept as text.

/// A parsed log line.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// `boot suntracker <version> board=<name>`
    Boot {
        /// Firmware version.
        version: String,
        /// Board name.
        board: String,
    },
    /// `timescale <N>`
    Timescale(f64),
    /// `time source=gps|rtc utc=YYYY-MM-DDTHH:MM:SSZ`
    Time {
        /// "gps" or "rtc".
        source: String,
        /// Unix seconds.
        unix_s: i64,
    },
    /// `site source=gps|config lat=<4 dp> lon=<4 dp>`
    Site {
        /// "gps" or "config".
        source: String,
        /// Degrees north.
        lat_deg: f64,
        /// Degrees east.
        lon_deg: f64,
    },
    /// `setpoint utc=… zenith=… azimuth=… c=… a=…`
    SetPoint {
        /// Unix seconds.
        unix_s: i64,
        /// Sun topocentric zenith, degrees.
        zenith_deg: f64,
        /// Sun azimuth east of north, degrees.
        azimuth_deg: f64,
        /// Commanded C axis angle, degrees.
        c_deg: f64,
        /// Commanded A axis angle, degrees.
        a_deg: f64,
    },
    /// `mode <name>`
    Mode(String),
    /// `fault <name> raised|cleared`
    Fault {
        /// Fault name (`Fault::name`).
        name: String,
        /// True for raised.
        raised: bool,
    },
    /// Anything else.
    Other,
}

/// `YYYY-MM-DDTHH:MM:SSZ` → Unix seconds.
pub fn parse_utc(s: &str) -> Option<i64> {
    let b = s.as_bytes();
    if b.len() != 20 || b[4] != b'-' || b[7] != b'-' || b[10] != b'T' || b[19] != b'Z' {
        return None;
    }
    let n = |r: std::ops::Range<usize>| s.get(r)?.parse::<u32>().ok();
    let (y, mo, d) = (n(0..4)?, n(5..7)?, n(8..10)?);
    let (h, mi, se) = (n(11..13)?, n(14..16)?, n(17..19)?);
    let dt = drivers::time::DateTime::new(y as u16, mo as u8, d as u8, h as u8, mi as u8, se as u8)
        .ok()?;
    Some(dt.unix_seconds())
}

/// Unix seconds → `YYYY-MM-DDTHH:MM:SSZ`.
pub fn format_utc(unix_s: i64) -> String {
    match drivers::time::DateTime::from_unix_seconds(unix_s) {
        Ok(d) => format!(
            "{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z",
            d.year(),
            d.month(),
            d.day(),
            d.hour(),
            d.minute(),
            d.second()
        ),
        Err(_) => format!("@{unix_s}"),
    }
}

fn kv<'a>(words: &[&'a str], key: &str) -> Option<&'a str> {
    words
        .iter()
        .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
}

/// Parses one line (without its line end).
pub fn parse_line(line: &str) -> Event {
    let words: Vec<&str> = line.split_whitespace().collect();
    let f = |k: &str| kv(&words, k).and_then(|v| v.parse::<f64>().ok());
    let parsed = match words.as_slice() {
        ["boot", "suntracker", version, rest @ ..] => kv(rest, "board").map(|b| Event::Boot {
            version: version.to_string(),
            board: b.to_string(),
        }),
        ["timescale", n] => n.parse().ok().map(Event::Timescale),
        ["time", ..] => (|| {
            Some(Event::Time {
                source: kv(&words, "source")?.to_string(),
                unix_s: parse_utc(kv(&words, "utc")?)?,
            })
        })(),
        ["site", ..] => (|| {
            Some(Event::Site {
                source: kv(&words, "source")?.to_string(),
                lat_deg: f("lat")?,
                lon_deg: f("lon")?,
            })
        })(),
        ["setpoint", ..] => (|| {
            Some(Event::SetPoint {
                unix_s: parse_utc(kv(&words, "utc")?)?,
                zenith_deg: f("zenith")?,
                azimuth_deg: f("azimuth")?,
                c_deg: f("c")?,
                a_deg: f("a")?,
            })
        })(),
        ["mode", name] => Some(Event::Mode(name.to_string())),
        ["fault", name, state @ ("raised" | "cleared")] => Some(Event::Fault {
            name: name.to_string(),
            raised: *state == "raised",
        }),
        _ => None,
    };
    parsed.unwrap_or(Event::Other)
}

/// Assembles bytes into lines (LF ends a line; CR is dropped).
#[derive(Debug, Default, Clone)]
pub struct LineAssembler {
    partial: Vec<u8>,
}

impl LineAssembler {
    /// Whether an unfinished line is pending.
    pub fn has_partial(&self) -> bool {
        !self.partial.is_empty()
    }

    /// Feeds bytes; returns the completed lines.
    pub fn push(&mut self, bytes: &[u8]) -> Vec<String> {
        let mut out = Vec::new();
        for &b in bytes {
            match b {
                b'\n' => out
                    .push(String::from_utf8_lossy(&std::mem::take(&mut self.partial)).into_owned()),
                b'\r' => {}
                _ => self.partial.push(b),
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes() {
        assert_eq!(
            parse_line("boot suntracker 0.1.0 board=mega2560"),
            Event::Boot {
                version: "0.1.0".into(),
                board: "mega2560".into()
            }
        );
        assert_eq!(parse_line("timescale 60"), Event::Timescale(60.0));
        assert_eq!(
            parse_line("time source=gps utc=2026-06-21T05:00:02Z"),
            Event::Time {
                source: "gps".into(),
                unix_s: 1_782_018_002
            }
        );
        assert_eq!(
            parse_line("site source=config lat=11.9683 lon=8.4261"),
            Event::Site {
                source: "config".into(),
                lat_deg: 11.9683,
                lon_deg: 8.4261
            }
        );
        assert_eq!(
            parse_line(
                "setpoint utc=2026-06-21T06:00:00Z zenith=80.125 azimuth=65.500 c=-114.50 a=-80.13"
            ),
            Event::SetPoint {
                unix_s: 1_782_021_600,
                zenith_deg: 80.125,
                azimuth_deg: 65.5,
                c_deg: -114.5,
                a_deg: -80.13
            }
        );
        assert_eq!(
            parse_line("mode wind_stow"),
            Event::Mode("wind_stow".into())
        );
        assert_eq!(
            parse_line("fault rtc_invalid raised"),
            Event::Fault {
                name: "rtc_invalid".into(),
                raised: true
            }
        );
        assert_eq!(parse_line("setpoint utc=bad"), Event::Other);
        assert_eq!(format_utc(1_782_018_000), "2026-06-21T05:00:00Z");
        let mut a = LineAssembler::default();
        assert_eq!(a.push(b"ab\r\ncd"), vec!["ab".to_string()]);
        assert_eq!(a.push(b"\n"), vec!["cd".to_string()]);
    }
}
