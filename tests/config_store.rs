//! Configuration storage: CRC, versions, two slots, torn writes.

use suntracker::config::{Config, LAYOUT_VERSION, PAYLOAD_LEN, RECORD_LEN};
use suntracker::persist::{
    crc32, ConfigStore, MemError, MemStorage, SaveError, SaveStatus, SlotState, SLOT_LEN,
};
use suntracker::ports::Storage;
use suntracker::safety::OperatorHold;

#[test]
fn crc32_check_value() {
    // The standard check value of CRC-32/ISO-HDLC ("123456789").
    assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
    assert_eq!(crc32(b""), 0);
    // "The quick brown fox jumps over the lazy dog" → 0x414FA339 (zlib.crc32).
    assert_eq!(
        crc32(b"The quick brown fox jumps over the lazy dog"),
        0x414F_A339
    );
}

fn tromso() -> Config {
    let mut c = Config::default();
    c.site.latitude_deg = 69.65;
    c.site.longitude_deg = 18.96;
    c.site.elevation_m = 10.0;
    c.schedule.table_step_s = 60;
    c.axes[1].backlash_deg = 0.35;
    c.calibration.declination_deg = 9.5;
    c
}

#[test]
fn encode_decode_round_trip() {
    let c = tromso();
    let mut buf = [0u8; PAYLOAD_LEN];
    let n = c.encode(&mut buf).unwrap();
    assert_eq!(n, PAYLOAD_LEN);
    assert_eq!(Config::decode(&buf[..n]), Some(c));
    // The operator's hold is byte 143, after the fields of layout version
    // 3: bit 0 stow, 1 manual, 2 service; the Modbus settings (11 bytes)
    // the weather stows' (22 bytes), the supply watch's (4 bytes) and the
    // overcast mode's (13 bytes), the C axis's `continuous` (1 byte), the
    // site's UTC offset (4), the anemometer's factor (4) and the Modbus
    // silence's stow (1), each axis's drive kind, current limit and
    // overcurrent time (1 + 2 + 2), each axis's backward speed (4), the
    // timed axes' calibration supply (2) and each axis's linear actuator
    // (six `f32`, two `u16`) follow it.
    const HOLD_AT: usize = 143;
    assert_eq!(
        n,
        HOLD_AT + 1 + 11 + 22 + 4 + 13 + 1 + 9 + 2 * 5 + 2 * 4 + 2 + 2 * (6 * 4 + 2 * 2)
    );
    // The drive fields away from their defaults come back too.
    let mut dc = c;
    dc.axes[1].drive = 2;
    dc.axes[1].max_current_ma = 4_500;
    dc.axes[0].overcurrent_ms = 250;
    dc.axes[0].back_speed_deg_s = 0.75;
    dc.axes[1].back_speed_deg_s = 12.5;
    dc.supply.calibration_mv = 12_000;
    dc.axes[1].linear.pivot_a_mm = 412.5;
    dc.axes[0].linear.pot_extended_counts = 3_900;
    let mut db = [0u8; PAYLOAD_LEN];
    assert_eq!(dc.encode(&mut db), Some(PAYLOAD_LEN));
    assert_eq!(Config::decode(&db[..n]), Some(dc));
    let mut held = c;
    held.hold = OperatorHold {
        stow: true,
        manual: false,
        service: true,
    };
    let mut hb = [0u8; PAYLOAD_LEN];
    assert_eq!(held.encode(&mut hb), Some(PAYLOAD_LEN));
    assert_eq!(hb[HOLD_AT], 0b101);
    assert_eq!(hb[..HOLD_AT], buf[..HOLD_AT]);
    assert_eq!(hb[HOLD_AT + 1..n], buf[HOLD_AT + 1..n]);
    assert_eq!(Config::decode(&hb[..n]), Some(held));
    // A flag this firmware does not know: the payload is refused.
    hb[HOLD_AT] = 0b1000;
    assert_eq!(Config::decode(&hb[..n]), None);
    // Layout version 3's payload (no Modbus or stow settings, 144 bytes)
    // reads with their defaults, version 2's (no hold byte either, 143 bytes)
    // with no hold in force.
    let mut on_bus = held;
    on_bus.modbus.address = 17;
    on_bus.modbus.write = 1;
    on_bus.stow.snow_release_s = 60;
    let mut mb = [0u8; PAYLOAD_LEN];
    assert_eq!(on_bus.encode(&mut mb), Some(PAYLOAD_LEN));
    assert_eq!(Config::decode(&mb[..HOLD_AT + 1]), Some(held));
    assert_eq!(Config::decode(&mb[..HOLD_AT]), Some(c));
    // Other lengths are rejected.
    assert_eq!(Config::decode(&buf[..HOLD_AT - 1]), None);
    assert_eq!(Config::decode(&buf[..HOLD_AT + 2]), None);
    // Layout version 9's payload (without the linear actuators: their
    // defaults).
    let v9 = n - 2 * (6 * 4 + 2 * 2);
    let mut dc_v9 = dc;
    dc_v9.axes[0].linear = c.axes[0].linear;
    dc_v9.axes[1].linear = c.axes[1].linear;
    assert_eq!(Config::decode(&db[..v9]), Some(dc_v9));
    assert_eq!(Config::decode(&buf[..v9 - 1]), None);
    // Layout version 8's payload (without the calibration supply: 0),
    // version 7's (also without the backward speeds: the defaults),
    // version 6's (also without the drive fields: steppers, the
    // current watch's defaults), version 5's (also without the UTC offset,
    // the anemometer's factor and the silence's stow) and version 4's
    // (also without `axis.c.continuous`) read with them at 0.
    let mut dc_v8 = dc_v9;
    dc_v8.supply.calibration_mv = 0;
    assert_eq!(Config::decode(&db[..v9 - 2]), Some(dc_v8));
    let mut dc_v7 = dc_v8;
    dc_v7.axes[0].back_speed_deg_s = c.axes[0].back_speed_deg_s;
    dc_v7.axes[1].back_speed_deg_s = c.axes[1].back_speed_deg_s;
    assert_eq!(Config::decode(&db[..v9 - 10]), Some(dc_v7));
    assert_eq!(Config::decode(&buf[..v9 - 20]), Some(c));
    assert_eq!(Config::decode(&db[..v9 - 20]), Some(c));
    assert_eq!(Config::decode(&buf[..v9 - 29]), Some(c));
    assert_eq!(Config::decode(&buf[..v9 - 30]), Some(c));
    assert_eq!(Config::decode(&buf[..v9 - 1]), None);
    assert_eq!(Config::decode(&buf[..v9 - 3]), None);
    assert_eq!(Config::decode(&buf[..v9 - 6]), None);
    assert_eq!(Config::decode(&buf[..v9 - 15]), None);
    assert_eq!(Config::decode(&buf[..v9 - 31]), None);
    assert_eq!(Config::decode(&buf[..n - 55]), None);
    // Too small a buffer to encode into.
    assert_eq!(c.encode(&mut [0u8; 10]), None);
}

/// The payload of layout version 10 byte by byte, built here field by
/// field in the order `src/config/codec.rs` documents (the configuration's
/// declaration order, little-endian, the derived counts per degree left
/// out, the hold after the fields of version 3, the Modbus and stow
/// settings after it, the C axis's `continuous`, the UTC offset, the
/// anemometer's factor, the Modbus silence's stow, the drives, the
/// backward speeds, the calibration supply and the linear actuators last), so that a change of the key table that would move a stored
/// field fails here: every field gets a value of its own.
#[test]
fn payload_is_the_documented_layout() {
    let mut c = tromso();
    c.schedule.hold_s = 30;
    c.schedule.recheck_s = 7;
    c.schedule.max_tick_gap_s = 90;
    c.schedule.max_backward_s = 120;
    c.axes[0].counts_per_motor_rev = 400;
    c.axes[0].microsteps = 8;
    c.axes[1].counts_per_motor_rev = 200;
    c.axes[1].microsteps = 4;
    c.wind.hold_s = 3;
    c.wind.release_s = 600;
    c.safety.max_retries = 5;
    c.safety.stall_timeout_s = 11;
    c.safety.sensor_timeout_s = 13;
    c.calibration.heading_offset_deg = -1.5;
    c.calibration.tilt_x_offset_deg = 0.25;
    c.calibration.tilt_y_offset_deg = -0.75;
    c.log.status_every_min = 15;
    c.hold.manual = true;
    c.modbus.address = 23;
    c.modbus.baud = 9_600;
    c.modbus.parity = 1;
    c.modbus.write = 1;
    c.modbus.timeout_s = 300;
    c.stow.snow_slope_deg = 75.0;
    c.stow.snow_release_s = 7_200;
    c.stow.hail_slope_deg = 55.5;
    c.stow.hail_release_s = 900;
    c.stow.external_slope_deg = 10.0;
    c.stow.external_active = 1;
    c.stow.on_sensor_fault = 1;
    c.supply.stow_mv = 11_500;
    c.supply.resume_mv = 12_200;
    c.overcast.ratio = 0.45;
    c.overcast.enter_s = 900;
    c.overcast.leave_s = 1_200;
    c.overcast.max_moves_per_hour = 3;
    c.axes[0].continuous = 1;
    c.site.utc_offset_h = 5.75;
    c.wind.m_s_per_hz = 0.667;
    c.modbus.timeout_stow = 1;
    c.supply.calibration_mv = 12_600;
    c.axes[1].linear.pivot_b_mm = 140.0;
    c.axes[1].linear.pulses_per_mm = 5.25;
    c.axes[0].linear.pot_retracted_counts = 3_000;
    let mut expected = Vec::new();
    let f = |v: &mut Vec<u8>, x: f32| v.extend_from_slice(&x.to_le_bytes());
    let u = |v: &mut Vec<u8>, x: u32| v.extend_from_slice(&x.to_le_bytes());
    f(&mut expected, c.site.latitude_deg);
    f(&mut expected, c.site.longitude_deg);
    f(&mut expected, c.site.elevation_m);
    let s = &c.schedule;
    for x in [
        s.table_step_s,
        s.hold_s,
        s.recheck_s,
        s.max_tick_gap_s,
        s.max_backward_s,
    ] {
        u(&mut expected, x);
    }
    for a in &c.axes {
        u(&mut expected, a.counts_per_motor_rev);
        expected.extend_from_slice(&a.microsteps.to_le_bytes());
        for x in [
            a.gear_ratio,
            a.min_deg,
            a.max_deg,
            a.home_deg,
            a.backlash_deg,
            a.max_speed_deg_s,
            a.deadband_deg,
        ] {
            f(&mut expected, x);
        }
    }
    f(&mut expected, c.wind.threshold_hz);
    u(&mut expected, c.wind.hold_s);
    u(&mut expected, c.wind.release_s);
    f(&mut expected, c.safety.max_deviation_deg);
    u(&mut expected, c.safety.stall_timeout_s);
    u(&mut expected, c.safety.sensor_timeout_s);
    expected.push(c.safety.max_retries);
    let k = &c.calibration;
    for x in [
        k.declination_deg,
        k.heading_offset_deg,
        k.tilt_x_offset_deg,
        k.tilt_y_offset_deg,
    ] {
        f(&mut expected, x);
    }
    expected.extend_from_slice(&c.log.status_every_min.to_le_bytes());
    // The hold: bit 0 stow, 1 manual, 2 service.
    expected.push(0b010);
    expected.push(c.modbus.address);
    u(&mut expected, c.modbus.baud);
    expected.push(c.modbus.parity);
    expected.push(c.modbus.write);
    u(&mut expected, c.modbus.timeout_s);
    let w = &c.stow;
    f(&mut expected, w.snow_slope_deg);
    u(&mut expected, w.snow_release_s);
    f(&mut expected, w.hail_slope_deg);
    u(&mut expected, w.hail_release_s);
    f(&mut expected, w.external_slope_deg);
    expected.push(w.external_active);
    expected.push(w.on_sensor_fault);
    expected.extend_from_slice(&c.supply.stow_mv.to_le_bytes());
    expected.extend_from_slice(&c.supply.resume_mv.to_le_bytes());
    f(&mut expected, c.overcast.ratio);
    u(&mut expected, c.overcast.enter_s);
    u(&mut expected, c.overcast.leave_s);
    expected.push(c.overcast.max_moves_per_hour);
    expected.push(c.axes[0].continuous);
    f(&mut expected, c.site.utc_offset_h);
    f(&mut expected, c.wind.m_s_per_hz);
    expected.push(c.modbus.timeout_stow);
    for a in &c.axes {
        expected.push(a.drive);
        expected.extend_from_slice(&a.max_current_ma.to_le_bytes());
        expected.extend_from_slice(&a.overcurrent_ms.to_le_bytes());
    }
    for a in &c.axes {
        f(&mut expected, a.back_speed_deg_s);
    }
    expected.extend_from_slice(&c.supply.calibration_mv.to_le_bytes());
    for a in &c.axes {
        let m = &a.linear;
        for x in [
            m.pivot_a_mm,
            m.pivot_b_mm,
            m.pivot_offset_deg,
            m.retracted_mm,
            m.stroke_mm,
            m.pulses_per_mm,
        ] {
            f(&mut expected, x);
        }
        expected.extend_from_slice(&m.pot_retracted_counts.to_le_bytes());
        expected.extend_from_slice(&m.pot_extended_counts.to_le_bytes());
    }
    assert_eq!(expected.len(), PAYLOAD_LEN);
    let mut buf = [0u8; PAYLOAD_LEN];
    let n = c.encode(&mut buf).unwrap();
    assert_eq!(&buf[..n], &expected[..]);
    assert_eq!(Config::decode(&expected), Some(c));
}

#[test]
fn fresh_storage_gives_defaults() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    let l = st.load();
    assert!(l.defaults);
    assert_eq!(l.config, Config::default());
    assert_eq!(l.slots, [SlotState::Empty, SlotState::Empty]);
}

#[test]
fn save_alternates_slots_and_newest_wins() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    let mut c = tromso();
    st.save(&c).unwrap();
    c.wind.threshold_hz = 30.0;
    st.save(&c).unwrap();
    let mem = st.release();
    let mut st = ConfigStore::new(mem);
    let l = st.load();
    assert!(!l.defaults);
    assert_eq!(l.config, c);
    assert_eq!(l.slots, [SlotState::Good(1), SlotState::Good(2)]);
    // Third save goes to slot 0 with sequence 3.
    c.wind.threshold_hz = 31.0;
    st.save(&c).unwrap();
    let l = st.load();
    assert_eq!(l.slots, [SlotState::Good(3), SlotState::Good(2)]);
    assert_eq!(l.config.wind.threshold_hz, 31.0);
}

#[test]
fn torn_write_keeps_the_last_good_config() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    let good = tromso();
    st.save(&good).unwrap();
    let mut newer = good;
    newer.site.latitude_deg = 12.0;
    // Power fails after every possible number of bytes of the next write.
    for k in 0..(PAYLOAD_LEN + 16) {
        let mut mem = st.release();
        let saved = mem.clone();
        mem.tear_after = Some(k);
        let mut s2 = ConfigStore::new(mem);
        assert!(s2.save(&newer).is_err());
        let l = s2.load();
        assert!(!l.defaults, "k = {k}");
        assert_eq!(l.config, good, "k = {k}");
        // Restore for the next round.
        st = ConfigStore::new(saved);
        st.load();
    }
    // A complete write then wins.
    st.save(&newer).unwrap();
    assert_eq!(st.load().config, newer);
}

#[test]
fn corrupt_byte_anywhere_falls_back() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    let c = tromso();
    st.save(&c).unwrap();
    let clean = st.release();
    for i in 0..(PAYLOAD_LEN + 16) {
        let mut mem = clone(&clean);
        mem.bytes[i] ^= 0x10;
        let mut s = ConfigStore::new(mem);
        let l = s.load();
        // Only one slot was written: any flipped bit gives the defaults.
        assert!(l.defaults, "byte {i}");
        assert_eq!(l.config, Config::default());
    }
}

#[test]
fn one_corrupt_slot_uses_the_other() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    let a = tromso();
    let mut b = a;
    b.safety.max_retries = 7;
    st.save(&a).unwrap(); // slot 0, seq 1
    st.save(&b).unwrap(); // slot 1, seq 2
    let mut mem = st.release();
    mem.bytes[SLOT_LEN + 40] ^= 0xFF;
    let mut st = ConfigStore::new(mem);
    let l = st.load();
    assert_eq!(l.slots[1], SlotState::Corrupt);
    assert_eq!(l.config, a);
}

#[test]
fn old_version_and_bad_values_are_rejected_whole() {
    // Build a slot by hand: layout version 0 with a valid CRC.
    let c = tromso();
    let mut payload = [0u8; PAYLOAD_LEN];
    let n = c.encode(&mut payload).unwrap();
    let slot = |version: u16, body: &[u8]| record(version, 9, body);
    let mut mem = MemStorage::<1024>::new();
    mem.write(0, &slot(0, &payload[..n])).unwrap();
    let l = ConfigStore::new(mem).load();
    assert!(l.defaults);
    assert_eq!(l.slots[0], SlotState::OldVersion(0));

    // Layouts 2 (written before the operator's hold existed: the fields
    // before it), 3 (before the Modbus settings: up to the hold) and 4
    // (before `axis.c.continuous`) and 5 (before the UTC offset, the
    // anemometer's factor and the silence's stow), 6 (before the axes'
    // drive kinds and current watch), 7 (before the axes' backward
    // speeds), 8 (before the timed axes' calibration supply) and 9
    // (before the axes' linear actuators) are still read, so an update
    // keeps the saved configuration; version 3 with version 2's length is
    // not.
    let v9 = n - 2 * (6 * 4 + 2 * 2);
    let (v2, v3, v4, v5, v6, v7, v8) =
        (v9 - 81, v9 - 80, v9 - 30, v9 - 29, v9 - 20, v9 - 10, v9 - 2);
    let mut mem = MemStorage::<1024>::new();
    mem.write(0, &slot(2, &payload[..v2])).unwrap();
    mem.write(SLOT_LEN, &slot(3, &payload[..v2])).unwrap();
    let l = ConfigStore::new(mem).load();
    assert!(!l.defaults);
    assert_eq!(l.config, c);
    assert_eq!(l.slots, [SlotState::Good(9), SlotState::Corrupt]);
    let mut mem = MemStorage::<1024>::new();
    mem.write(0, &slot(3, &payload[..v3])).unwrap();
    let l = ConfigStore::new(mem).load();
    assert_eq!((l.defaults, l.config), (false, c));
    for (version, len) in [(4, v4), (5, v5), (6, v6), (7, v7), (8, v8), (9, v9)] {
        let mut mem = MemStorage::<1024>::new();
        mem.write(0, &slot(version, &payload[..len])).unwrap();
        let l = ConfigStore::new(mem).load();
        assert_eq!((l.defaults, l.config), (false, c));
    }
    // Version 2 with version 3's length is not either, nor version 3 with
    // version 4's, nor 4 with 5's, nor 5 with 6's, nor 6 with 7's, nor 7
    // with 8's, nor 8 with 9's, nor 9 with 10's.
    for (version, len) in [
        (2, v3),
        (3, v4),
        (4, v5),
        (5, v6),
        (6, v7),
        (7, v8),
        (8, v9),
        (9, n),
    ] {
        let mut mem = MemStorage::<1024>::new();
        mem.write(0, &slot(version, &payload[..len])).unwrap();
        let l = ConfigStore::new(mem).load();
        assert!(l.defaults);
        assert_eq!(l.slots[0], SlotState::Corrupt);
    }

    // Current version, valid CRC, but a latitude of 95°: not applied in part.
    let mut bad = c;
    bad.site.latitude_deg = 95.0;
    let n = bad.encode(&mut payload).unwrap();
    let mut mem = MemStorage::<1024>::new();
    mem.write(0, &slot(LAYOUT_VERSION, &payload[..n])).unwrap();
    let l = ConfigStore::new(mem).load();
    assert!(l.defaults);
    assert_eq!(l.slots[0], SlotState::Corrupt);
    assert_eq!(l.config, Config::default());

    // And save refuses it.
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    assert!(st.save(&bad).is_err());
    // Storage too small for two slots.
    let mut st = ConfigStore::new(MemStorage::<300>::new());
    assert!(st.save(&c).is_err());
}

#[test]
fn a_newer_slot_with_a_bad_value_leaves_the_older_copy_in_the_callers_place() {
    // Slot 0: Tromsø, sequence 9. Slot 1: newer (10), its CRC good, but a
    // latitude of 95°: decoded into the caller's place over the older
    // copy, it is refused, and the older copy is read again: that is what
    // the caller gets.
    let c = tromso();
    let mut bad = c;
    bad.site.latitude_deg = 95.0;
    let mut payload = [0u8; PAYLOAD_LEN];
    let mut mem = MemStorage::<1024>::new();
    let n = c.encode(&mut payload).unwrap();
    mem.write(0, &record(LAYOUT_VERSION, 9, &payload[..n]))
        .unwrap();
    let n = bad.encode(&mut payload).unwrap();
    mem.write(SLOT_LEN, &record(LAYOUT_VERSION, 10, &payload[..n]))
        .unwrap();
    let mut store = ConfigStore::new(mem);
    let mut into = Config::default();
    let report = store.load_into(&mut into);
    assert_eq!(report.slots, [SlotState::Good(9), SlotState::Corrupt]);
    assert!(!report.defaults);
    assert_eq!(into, c);
    // The next save goes to the slot not holding that copy, after it.
    store.save(&c).unwrap();
    let mut into = bad;
    let report = store.load_into(&mut into);
    assert_eq!(report.slots, [SlotState::Good(9), SlotState::Good(10)]);
    assert_eq!(into, c);

    // No good slot: the caller's copy becomes the defaults.
    let mut store = ConfigStore::new(MemStorage::<1024>::new());
    let mut into = c;
    let report = store.load_into(&mut into);
    assert!(report.defaults);
    assert_eq!(report.slots, [SlotState::Empty, SlotState::Empty]);
    assert_eq!(into, Config::default());
}

#[test]
fn sequence_wraps_around() {
    // Slot 0 holds sequence u32::MAX, slot 1 sequence 0 (written after it).
    let c = tromso();
    let mut payload = [0u8; PAYLOAD_LEN];
    let n = c.encode(&mut payload).unwrap();
    let mut newer = c;
    newer.wind.release_s = 1234;
    let mut payload2 = [0u8; PAYLOAD_LEN];
    let n2 = newer.encode(&mut payload2).unwrap();
    let slot = |seq: u32, body: &[u8]| record(LAYOUT_VERSION, seq, body);
    let mut mem = MemStorage::<1024>::new();
    mem.write(0, &slot(u32::MAX, &payload[..n])).unwrap();
    mem.write(SLOT_LEN, &slot(0, &payload2[..n2])).unwrap();
    assert_eq!(ConfigStore::new(mem).load().config, newer);
}

fn clone(m: &MemStorage<1024>) -> MemStorage<1024> {
    m.clone()
}

#[test]
fn record_is_header_payload_and_crc() {
    // Slot layout table of src/persist/store.rs: 12 header bytes, the payload, 4 CRC
    // bytes; it fits a slot.
    assert_eq!(RECORD_LEN, 12 + PAYLOAD_LEN + 4);
    const { assert!(RECORD_LEN <= SLOT_LEN) };
}

#[test]
fn stepped_save_takes_one_storage_step_per_poll() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    assert_eq!(st.poll(), SaveStatus::Idle);
    st.begin_save(&tromso()).unwrap();
    assert!(st.is_saving());
    // RAM: nothing to erase, the whole record in one write, nothing
    // pending: erase step, write step, flush step.
    assert_eq!(st.poll(), SaveStatus::Busy);
    assert_eq!(st.poll(), SaveStatus::Busy);
    assert_eq!(st.poll(), SaveStatus::Done(Ok(())));
    // Reported once.
    assert_eq!(st.poll(), SaveStatus::Idle);
    assert!(!st.is_saving());
    let l = st.load();
    assert_eq!(l.config, tromso());
    assert_eq!(l.slots, [SlotState::Good(1), SlotState::Empty]);
}

#[test]
fn nothing_is_written_before_the_first_poll() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    st.begin_save(&tromso()).unwrap();
    assert!(st.storage().bytes.iter().all(|b| *b == 0xFF));
}

#[test]
fn begin_save_refuses_an_invalid_config_and_stages_nothing() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    let mut bad = tromso();
    bad.safety.max_deviation_deg = 90.0;
    assert_eq!(st.begin_save(&bad), Err(SaveError::Invalid));
    assert_eq!(st.poll(), SaveStatus::Idle);
    // A refused request leaves a save under way going on.
    st.begin_save(&tromso()).unwrap();
    assert_eq!(st.begin_save(&bad), Err(SaveError::Invalid));
    assert!(st.is_saving());
    assert_eq!(st.save(&tromso()), Ok(()));
}

#[test]
fn a_failed_write_keeps_the_newest_copy_and_the_next_save_retries_the_slot() {
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    let a = tromso();
    st.save(&a).unwrap(); // slot 0, seq 1
    let mut mem = st.release();
    mem.tear_after = Some(20);
    let mut st = ConfigStore::new(mem);
    let mut b = a;
    b.wind.hold_s = 9;
    assert_eq!(st.save(&b), Err(SaveError::Storage(MemError::Torn)));
    assert_eq!(st.load().config, a);
    // The same slot again, the same sequence number.
    st.save(&b).unwrap();
    assert_eq!(st.load().slots, [SlotState::Good(1), SlotState::Good(2)]);
}

/// RAM storage whose reads fail inside `bad`.
struct FailingReads {
    mem: MemStorage<1024>,
    bad: core::ops::Range<usize>,
}

impl Storage for FailingReads {
    type Error = MemError;
    fn capacity(&self) -> usize {
        self.mem.capacity()
    }
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), MemError> {
        if offset < self.bad.end && offset + buf.len() > self.bad.start {
            return Err(MemError::OutOfRange);
        }
        self.mem.read(offset, buf)
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), MemError> {
        self.mem.write(offset, data)
    }
}

#[test]
fn no_save_while_a_slot_cannot_be_read() {
    // Slot 0 holds the only good copy but cannot be read just now: a save
    // must not guess a slot (it could overwrite that copy).
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    st.save(&tromso()).unwrap();
    let mem = st.release();
    let mut st = ConfigStore::new(FailingReads {
        mem,
        bad: 0..SLOT_LEN,
    });
    let l = st.load();
    assert!(l.defaults);
    assert_eq!(l.slots, [SlotState::Unreadable, SlotState::Empty]);
    let mut c = tromso();
    c.site.elevation_m = 99.0;
    assert_eq!(
        st.begin_save(&c),
        Err(SaveError::Storage(MemError::OutOfRange))
    );
    assert_eq!(st.poll(), SaveStatus::Idle);
    // Readable again: the copy is there.
    let FailingReads { mem, .. } = st.release();
    assert_eq!(ConfigStore::new(mem).load().config, tromso());
}

#[test]
fn a_read_failing_inside_a_newer_payload_leaves_the_older_copy() {
    // Two saves: slot 0 then slot 1 (newer). Slot 1's payload cannot be
    // read from its 100th byte on: the record decoded from the storage as
    // it is read is dropped, the slot is unreadable, and slot 0's copy,
    // read before it into the same place, is read again whole.
    let older = tromso();
    let mut newer = older;
    newer.site.elevation_m = 99.0;
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    st.save(&older).unwrap();
    st.save(&newer).unwrap();
    let mem = st.release();
    let mut st = ConfigStore::new(FailingReads {
        mem,
        bad: SLOT_LEN + 100..SLOT_LEN + 101,
    });
    let mut into = Config::default();
    let report = st.load_into(&mut into);
    assert_eq!(report.slots, [SlotState::Good(1), SlotState::Unreadable]);
    assert!(!report.defaults);
    assert_eq!(into, older);
    // Readable again: the newer copy wins.
    let FailingReads { mem, .. } = st.release();
    assert_eq!(ConfigStore::new(mem).load().config, newer);
}

/// RAM storage that returns byte `at` flipped on its `flip_on`th read
/// (a marginal cell read differently twice).
struct FlakyReads {
    mem: MemStorage<1024>,
    at: usize,
    reads: usize,
    flip_on: usize,
}

impl Storage for FlakyReads {
    type Error = MemError;
    fn capacity(&self) -> usize {
        self.mem.capacity()
    }
    fn read(&mut self, offset: usize, buf: &mut [u8]) -> Result<(), MemError> {
        self.mem.read(offset, buf)?;
        if (offset..offset + buf.len()).contains(&self.at) {
            self.reads += 1;
            if self.reads == self.flip_on {
                buf[self.at - offset] ^= 0x01;
            }
        }
        Ok(())
    }
    fn write(&mut self, offset: usize, data: &[u8]) -> Result<(), MemError> {
        self.mem.write(offset, data)
    }
}

#[test]
fn a_copy_that_reads_differently_the_second_time_is_not_taken_nor_overwritten() {
    // Slot 0 holds the only copy. The load reads it, then the slots after
    // it, then slot 0 again into the caller's place: that second read
    // differs (its CRC fails). No copy is taken, and the save after it
    // reads the slots again rather than take slot 0 for empty.
    let c = tromso();
    let mut st = ConfigStore::new(MemStorage::<1024>::new());
    st.save(&c).unwrap();
    let mem = st.release();
    let mut st = ConfigStore::new(FlakyReads {
        mem,
        at: 40,
        reads: 0,
        flip_on: 2,
    });
    let mut into = Config::default();
    let report = st.load_into(&mut into);
    assert!(report.defaults);
    assert_eq!(into, Config::default());
    // Read a third time, slot 0 is good again: the save goes to slot 1.
    let mut d = c;
    d.site.elevation_m = 99.0;
    st.save(&d).unwrap();
    let FlakyReads { mem, .. } = st.release();
    let mut st = ConfigStore::new(mem);
    let l = st.load();
    assert_eq!(l.slots, [SlotState::Good(1), SlotState::Good(2)]);
    assert_eq!(l.config, d);
}

/// A record as the store writes it: header (magic, `version`, length,
/// `seq`), `body`, CRC-32.
fn record(version: u16, seq: u32, body: &[u8]) -> Vec<u8> {
    let mut s = Vec::new();
    s.extend_from_slice(b"STCF");
    s.extend_from_slice(&version.to_le_bytes());
    s.extend_from_slice(&(body.len() as u16).to_le_bytes());
    s.extend_from_slice(&seq.to_le_bytes());
    s.extend_from_slice(body);
    let crc = crc32(&s);
    s.extend_from_slice(&crc.to_le_bytes());
    s
}

#[test]
fn a_copy_in_slot_1_of_the_256_byte_slots_is_kept_across_the_update() {
    // Before layout 10 a slot was 256 bytes: an EEPROM held slot 0 at 0
    // and slot 1 at 256. Here slot 1 holds the newer copy (sequence 6)
    // and slot 0 an older one (5), both of layout 9.
    const { assert!(SLOT_LEN == 512) };
    let older = tromso();
    let mut newer = tromso();
    newer.site.latitude_deg = 12.5;
    let v9_len = PAYLOAD_LEN - 2 * (6 * 4 + 2 * 2);
    let mut body = [0u8; PAYLOAD_LEN];
    let n = older.encode(&mut body).unwrap();
    assert_eq!(n, PAYLOAD_LEN);
    let mut mem = MemStorage::<1024>::new();
    mem.write(0, &record(9, 5, &body[..v9_len])).unwrap();
    newer.encode(&mut body).unwrap();
    mem.write(256, &record(9, 6, &body[..v9_len])).unwrap();
    let mut st = ConfigStore::new(mem);
    let l = st.load();
    // The newer copy, not the older one in slot 0; the slots of 512 bytes
    // report slot 0's copy and an empty slot 1.
    assert_eq!((l.defaults, l.config), (false, newer));
    assert_eq!(l.slots, [SlotState::Good(5), SlotState::Empty]);

    // The next save goes to slot 1 (byte 512), past the old copy, which
    // stays as it was until then.
    let mut saved = newer;
    saved.wind.release_s = 4_321;
    st.save(&saved).unwrap();
    let mut mem = st.release();
    let mut header = [0u8; 12];
    mem.read(SLOT_LEN, &mut header).unwrap();
    assert_eq!(&header[..4], b"STCF");
    assert_eq!(u32::from_le_bytes(header[8..12].try_into().unwrap()), 7);
    let mut old_slot_1 = [0u8; 12];
    mem.read(256, &mut old_slot_1).unwrap();
    assert_eq!(u32::from_le_bytes(old_slot_1[8..12].try_into().unwrap()), 6);
    let mut st = ConfigStore::new(mem);
    assert_eq!(st.load().config, saved);
    // And the one after it to slot 0, which overwrites the old slot 1's
    // header: from then on only the two new slots count.
    let mut again = saved;
    again.wind.release_s = 1_234;
    st.save(&again).unwrap();
    let mem = st.release();
    let l = ConfigStore::new(mem).load();
    assert_eq!(l.config, again);
    assert_eq!(l.slots, [SlotState::Good(8), SlotState::Good(7)]);
}

#[test]
fn an_older_copy_at_byte_256_does_not_win_over_a_newer_slot() {
    // A stale copy of 256-byte slots (sequence 3) and a newer one in slot 1
    // of the 512-byte slots (sequence 4): the newer is taken, by its
    // sequence, though the stale one is good.
    let older = tromso();
    let mut newer = tromso();
    newer.site.longitude_deg = -3.25;
    let v9_len = PAYLOAD_LEN - 2 * (6 * 4 + 2 * 2);
    let mut body = [0u8; PAYLOAD_LEN];
    let mut mem = MemStorage::<1024>::new();
    older.encode(&mut body).unwrap();
    mem.write(256, &record(9, 3, &body[..v9_len])).unwrap();
    let n = newer.encode(&mut body).unwrap();
    mem.write(SLOT_LEN, &record(LAYOUT_VERSION, 4, &body[..n]))
        .unwrap();
    let l = ConfigStore::new(mem).load();
    assert_eq!(l.config, newer);
    assert_eq!(l.slots, [SlotState::Empty, SlotState::Good(4)]);
}
