//! Settings of Chowdhury et al.'s (2019) tracker ([`super`])
//! that an installer enters in the field — the site and the gears — kept in
//! the EEPROM's two slots, and the console that enters them.
//!
//! **Two images on the Uno.** The tracker image (`avr_tracker`) reads the
//! settings at power-on ([`load`]) and has no console: the library's
//! console, its parser and the store's save add 20–24 KB to it, and the
//! closed-loop tracker without them took 27.8 KB of the ATmega328P's
//! 32,256 B (with this module's console linked into it: 51,580 B). The settings
//! image (`avr_settings`) is this module's [`SettingsConsole`] alone, on
//! the same serial port: flash it, type the settings, `save`, flash the
//! tracker back. Flashing through the Uno's bootloader never erases the
//! EEPROM, so the tracker finds them; the stock bootloader cannot write the
//! EEPROM itself (avrdude's `-U eeprom:w` fails on it), which is why an
//! image does.
//!
//! The language is the library's ([`crate::console`]): the same parser
//! ([`console::parse_in`]) over the keys of [`KEYS`], the same line buffer,
//! number reader and replies. What the settings image offers of it:
//!
//! | command | here |
//! |---|---|
//! | `help` | the commands and keys |
//! | `get`, `get KEY`, `set KEY VALUE`, `set K1 V1 K2 V2 …` | the keys below; any other key is `error unknown key` |
//! | `save`, `load`, `defaults` | the [`Settings`] record, through the library's two-slot CRC-32 store ([`ConfigStore`]) |
//! | `set site.postal_code CC:CODE` | the site from the library's postal-code table ([`crate::site::postal`], Dahli & Cheggaga 2023), a numeric code also without its leading zeros: `ok site.lat_deg=<deg> site.lon_deg=<deg>` |
//! | `time set YYYY-MM-DDTHH:MM:SSZ` | sets the RTC (and clears its lost-power flag): the tracker image has no other way to be told the time |
//! | `status`, `stow`, `resume`, `home`, `jog`, `manual off`, `service on\|off`, `faults`, `clear` | `error <command>: not on this image` (they act on a running tracker) |
//!
//! | key | unit |
//! |---|---|
//! | `site.lat_deg` | ° north |
//! | `site.lon_deg` | ° east |
//! | `axis.c.gear_ratio`, `axis.a.gear_ratio` | servo turns per axis turn |
//!
//! The ranges and their refusal texts are the configuration's, written
//! there once ([`crate::config::ranges`]: `LAT_DEG`, `LON_DEG` and
//! `GEAR_RATIO`, which [`Settings::validate`] checks; [`crate::config::Reason`]):
//! `set axis.c.gear_ratio 20000` is `error axis.c.gear_ratio: 1...10,000
//! motor revolutions per axis revolution`, as on the other boards.
//!
//! A save runs in steps beside the loop (one EEPROM byte a pass, 3.4 ms
//! each by the hardware); its `ok save` comes when the last byte is
//! written. A power cut during it leaves the old settings or the new ones
//! ([`ConfigStore`]'s two slots; `tests/persist_powercut.rs` cuts at every
//! byte of a save of this record too).

use sun_algos::Site;

use crate::config::{check_f32, ranges, AxisConfig, ConfigError, Field, Reason};
use crate::console::{self, Command, Decimal, LineBuffer, SetError};
use crate::log::Sink;
use crate::persist::{record_len, ConfigStore, Loaded, Payload, Record, SaveStatus};
use crate::ports::Storage;
use crate::text::FlashStrs;
use drivers::rtc::Clock as RtcDriver;

crate::progmem! {
    /// The keys of the settings, in `get`'s order.
    pub static KEYS: [Field; 4] = [
        Field::SiteLatDeg,
        Field::SiteLonDeg,
        Field::AxisCGearRatio,
        Field::AxisAGearRatio,
    ];
}

/// `help`'s lines. The last names [`KEYS`] as text: written from the
/// table at run time it took 8 B more of the Uno's flash
/// (`help_lists_the_commands_and_keys` checks that it names each key).
fn help_lines() -> FlashStrs {
    crate::flash_strs!(
        "get [KEY] | set KEY VALUE [KEY VALUE] | save | load | defaults",
        "set site.postal_code CC:CODE | time set YYYY-MM-DDTHH:MM:SSZ",
        "keys: site.lat_deg site.lon_deg axis.c.gear_ratio axis.a.gear_ratio",
    )
}

/// The ATmega328P's EEPROM, bytes (datasheet §8.4): room for both slots.
pub const EEPROM_LEN: usize = 1024;

/// What an installer sets: the site and the gears.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Latitude, degrees north (`site.lat_deg`).
    pub lat_deg: f32,
    /// Longitude, degrees east (`site.lon_deg`).
    pub lon_deg: f32,
    /// Servo turns per axis turn, C then A (`axis.c.gear_ratio`,
    /// `axis.a.gear_ratio`): the encoders sit on the servo shafts.
    pub gear_ratio: [f32; 2],
}

/// The settings of a board never set: Kano, Nigeria (Jimoh & Aliyu's (2019)
/// site) and the direct drives of Chowdhury et al. (2019).
pub const DEFAULTS: Settings = Settings {
    lat_deg: 11.9683,
    lon_deg: 8.4261,
    gear_ratio: [super::GEAR_RATIO; 2],
};

/// Payload bytes: latitude, longitude and the two gears, `f32`
/// little-endian each.
const PAYLOAD_LEN: usize = 4 * 4;

/// Bytes of one stored copy (header, payload, CRC-32).
pub const RECORD_LEN: usize = record_len(PAYLOAD_LEN);

/// The settings' store.
pub type SettingsStore<S> = ConfigStore<S, Settings, RECORD_LEN>;

impl Settings {
    /// Checks every field against the configuration's range for it; the
    /// first out of range is named.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_f32(
            self.lat_deg,
            ranges::LAT_DEG,
            Field::SiteLatDeg,
            Reason::Latitude,
        )?;
        check_f32(
            self.lon_deg,
            ranges::LON_DEG,
            Field::SiteLonDeg,
            Reason::Deg180,
        )?;
        let [gear_c, gear_a] = self.gear_ratio;
        check_f32(
            gear_c,
            ranges::GEAR_RATIO,
            Field::AxisCGearRatio,
            Reason::GearRatio,
        )?;
        check_f32(
            gear_a,
            ranges::GEAR_RATIO,
            Field::AxisAGearRatio,
            Reason::GearRatio,
        )
    }

    /// The site.
    pub fn site(&self) -> Result<Site<f32>, sun_algos::Error> {
        Site::new(self.lat_deg, self.lon_deg)
    }

    /// The axes with these gears.
    pub fn axis_configs(&self) -> [AxisConfig; 2] {
        super::axis_configs_geared(self.gear_ratio)
    }

    /// The field of `key` (`None` for a key the settings do not hold).
    fn field(&mut self, key: Field) -> Option<&mut f32> {
        let [gear_c, gear_a] = &mut self.gear_ratio;
        match key {
            Field::SiteLatDeg => Some(&mut self.lat_deg),
            Field::SiteLonDeg => Some(&mut self.lon_deg),
            Field::AxisCGearRatio => Some(gear_c),
            Field::AxisAGearRatio => Some(gear_a),
            _ => None,
        }
    }

    /// The value of `key` (`None` for a key the settings do not hold).
    pub fn get(&self, key: Field) -> Option<f32> {
        let mut copy = *self;
        copy.field(key).map(|v| *v)
    }

    /// Sets the pairs in a copy, validates the copy and only then keeps
    /// it: all or nothing.
    pub fn apply(&mut self, pairs: impl Iterator<Item = (Field, Decimal)>) -> Result<(), SetError> {
        let mut copy = *self;
        for (key, value) in pairs {
            *copy.field(key).ok_or(SetError::OutOfRange(key))? = value.to_f32();
        }
        copy.validate().map_err(SetError::Invalid)?;
        *self = copy;
        Ok(())
    }
}

impl Record for Settings {
    const MAGIC: [u8; 4] = *b"STUN";
    const VERSION: u16 = 1;
    const PAYLOAD_LEN: usize = PAYLOAD_LEN;

    fn encode(&self, buf: &mut [u8]) -> Option<usize> {
        let [gear_c, gear_a] = self.gear_ratio;
        let out = buf.get_mut(..PAYLOAD_LEN)?;
        for (chunk, v) in out
            .chunks_exact_mut(4)
            .zip([self.lat_deg, self.lon_deg, gear_c, gear_a])
        {
            crate::bytes::copy_prefix(chunk, &v.to_le_bytes());
        }
        Some(PAYLOAD_LEN)
    }

    fn decode_from(payload: &mut dyn Payload, out: &mut Self) -> bool {
        let mut buf = [0u8; PAYLOAD_LEN];
        if payload.length() != PAYLOAD_LEN || !payload.read(&mut buf) {
            return false;
        }
        let f = |at: usize| -> Option<f32> {
            let b: [u8; 4] = buf.get(at..at + 4)?.try_into().ok()?;
            Some(f32::from_le_bytes(b))
        };
        let (Some(lat_deg), Some(lon_deg), Some(gear_c), Some(gear_a)) = (f(0), f(4), f(8), f(12))
        else {
            return false;
        };
        let s = Settings {
            lat_deg,
            lon_deg,
            gear_ratio: [gear_c, gear_a],
        };
        if !s.is_valid() {
            return false;
        }
        *out = s;
        true
    }

    fn is_valid(&self) -> bool {
        self.validate().is_ok()
    }

    fn defaults() -> Self {
        DEFAULTS
    }
}

/// Reads the settings at power-on (the newest good slot, else
/// [`DEFAULTS`]) and logs where they came from: `config
/// source=stored|defaults`. Reads only.
#[inline(never)]
pub fn load<S: Storage>(storage: S, out: &mut dyn Sink) -> Settings {
    let loaded = SettingsStore::for_record(storage).load();
    log_source(out, &loaded);
    loaded.config
}

fn log_source(out: &mut dyn Sink, loaded: &Loaded<Settings>) {
    out.flash(if loaded.defaults {
        crate::flash_str!("config source=defaults\n")
    } else {
        crate::flash_str!("config source=stored\n")
    });
}

/// `KEY=VALUE`, without `ok` or end of line.
fn write_key_value(out: &mut dyn Sink, s: &Settings, key: Field) {
    if let Some(v) = s.get(key) {
        key.name().write(out);
        out.flash(crate::flash_str!("="));
        console::write_number(out, v);
    }
}

/// `ok KEY=VALUE`: the reply to `get KEY` and to a `set` of one key.
fn write_get(out: &mut dyn Sink, s: &Settings, key: Field) {
    out.flash(crate::flash_str!("ok "));
    write_key_value(out, s, key);
    out.flash(crate::flash_str!("\n"));
}

/// The settings console: the line being typed, the settings being edited,
/// their store.
pub struct SettingsConsole<S> {
    line: LineBuffer<{ console::LINE_LEN }>,
    settings: Settings,
    store: SettingsStore<S>,
}

impl<S: Storage> SettingsConsole<S> {
    /// The console at power-on, with the settings read from `storage` (the
    /// boot line says where they came from).
    pub fn boot(storage: S, out: &mut dyn Sink) -> Self {
        let mut store = SettingsStore::for_record(storage);
        let loaded = store.load();
        log_source(out, &loaded);
        SettingsConsole {
            line: LineBuffer::new(),
            settings: loaded.config,
            store,
        }
    }

    /// The settings being edited (saved or not).
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The store, and through it the storage.
    pub fn store(&self) -> &SettingsStore<S> {
        &self.store
    }

    /// Gives the storage back (a save under way is abandoned).
    pub fn release(self) -> S {
        self.store.release()
    }

    /// True while a save is under way.
    pub fn is_saving(&self) -> bool {
        self.store.is_saving()
    }

    /// Takes received bytes: each line ended is carried out (`time set`
    /// on `rtc`) and answered on `out`. Never waits: a save is only
    /// started here, [`SettingsConsole::poll`] writes it.
    pub fn input<R: RtcDriver>(&mut self, bytes: &[u8], rtc: &mut R, out: &mut dyn Sink) {
        for &b in bytes {
            let SettingsConsole {
                line,
                settings,
                store,
            } = self;
            match line.push(b) {
                None => {}
                Some(Err(e)) => console::write_line_error(out, e),
                Some(Ok(text)) => execute(text, settings, store, rtc, out),
            }
        }
    }

    /// Every pass of the loop: one step of a save under way, and its
    /// reply when it ends.
    pub fn poll(&mut self, out: &mut dyn Sink) {
        if let SaveStatus::Done(r) = self.store.poll() {
            console::write_saved(out, &r);
        }
    }
}

/// Parses and carries out one line.
#[inline(never)]
fn execute<S: Storage, R: RtcDriver>(
    line: &str,
    settings: &mut Settings,
    store: &mut SettingsStore<S>,
    rtc: &mut R,
    out: &mut dyn Sink,
) {
    let cmd = match console::parse_in(line, KEYS.as_slice()) {
        Ok(cmd) => cmd,
        Err(e) => return console::write_parse_error(out, &e),
    };
    match cmd {
        Command::Help => {
            console::write_lines(out, help_lines());
        }
        Command::GetAll => {
            for k in KEYS.iter() {
                write_get(out, settings, k);
            }
        }
        Command::Get(k) => write_get(out, settings, k),
        Command::Set(k, v) => match settings.apply(core::iter::once((k, v))) {
            Ok(()) => write_get(out, settings, k),
            Err(e) => console::write_set_error(out, &e),
        },
        Command::SetMany(pairs) => match settings.apply(pairs.iter()) {
            Ok(()) => {
                out.flash(crate::flash_str!("ok"));
                for (k, _) in pairs.iter() {
                    out.flash(crate::flash_str!(" "));
                    write_key_value(out, settings, k);
                }
                out.flash(crate::flash_str!("\n"));
            }
            Err(e) => console::write_set_error(out, &e),
        },
        Command::Defaults => {
            *settings = DEFAULTS;
            console::write_ok(out, crate::flash_str!("defaults"));
        }
        Command::Load => {
            let mut loaded = *settings;
            let report = store.load_into(&mut loaded);
            if !report.defaults {
                *settings = loaded;
            }
            console::write_loaded(out, &report);
        }
        Command::Save => {
            if let Err(e) = store.begin_save(settings) {
                console::write_saved(out, &Err(e));
            }
        }
        Command::SetPostalCode(text) => {
            // The table's site, validated as a `set` of both keys is.
            let set = console::find_postal(text)
                .map_err(SetError::Postal)
                .and_then(|entry| {
                    let mut copy = *settings;
                    copy.lat_deg = entry.latitude_deg::<f32>();
                    copy.lon_deg = entry.longitude_deg::<f32>();
                    copy.validate().map_err(SetError::Invalid)?;
                    *settings = copy;
                    Ok(())
                });
            match set {
                Ok(()) => {
                    out.flash(crate::flash_str!("ok "));
                    write_key_value(out, settings, Field::SiteLatDeg);
                    out.flash(crate::flash_str!(" "));
                    write_key_value(out, settings, Field::SiteLonDeg);
                    out.flash(crate::flash_str!("\n"));
                }
                Err(e) => console::write_set_error(out, &e),
            }
        }
        Command::TimeSet(t) => match console::set_rtc_time(rtc, &t) {
            Ok(()) => console::write_time_set(out, &t),
            Err(e) => console::write_time_error(out, e),
        },
        other => {
            out.flash(crate::flash_str!("error "));
            out.flash(other.name());
            out.flash(crate::flash_str!(": not on this image\n"));
        }
    }
}
