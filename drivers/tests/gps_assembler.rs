//! Sentence framing: every rejection reason and its counter.
//! Checksums of the good sentences were computed with Python
//! (`functools.reduce(lambda a, c: a ^ ord(c), body, 0)`), see tests/data/make_golden.py.

use drivers::gps::{Reject, SentenceAssembler, MAX_SENTENCE_LEN};

fn feed(a: &mut SentenceAssembler, bytes: &[u8]) -> Vec<Result<String, Reject>> {
    let mut out = Vec::new();
    for &b in bytes {
        if let Some(r) = a.push(b) {
            out.push(r.map(str::to_owned));
        }
    }
    out
}

#[test]
fn accepts_a_known_sentence_without_cr_lf() {
    let mut a = SentenceAssembler::new();
    let out = feed(&mut a, b"$GPGGA,,,,,,0,00,99.99,,,,,,*48\r\n");
    assert_eq!(out, vec![Ok("$GPGGA,,,,,,0,00,99.99,,,,,,*48".to_owned())]);
    assert_eq!(a.stats().accepted, 1);
    assert_eq!(a.stats().sentences(), 1);
}

#[test]
fn lower_case_hex_and_bare_lf_are_accepted() {
    let mut a = SentenceAssembler::new();
    let out = feed(
        &mut a,
        b"$GNGSA,A,3,05,13,15,18,20,,,,,,,,1.85,1.02,1.54*1b\n",
    );
    assert_eq!(out.len(), 1);
    assert!(out[0].is_ok());
}

#[test]
fn bad_checksum_is_rejected_and_counted() {
    let mut a = SentenceAssembler::new();
    // Right checksum is 48.
    let out = feed(&mut a, b"$GPGGA,,,,,,0,00,99.99,,,,,,*49\r\n");
    assert_eq!(out, vec![Err(Reject::BadChecksum)]);
    assert_eq!(a.stats().bad_checksum, 1);
    assert_eq!(a.stats().rejected_other(), 0);
}

#[test]
fn missing_or_malformed_checksum() {
    let mut a = SentenceAssembler::new();
    let out = feed(
        &mut a,
        b"$GPGGA,,,,,,0,00,99.99,,,,,,\r\n$GPGGA,,,,,,0,00,99.99,,,,,,*4G\r\n$*\r\n$GP*GGA*48\r\n",
    );
    assert_eq!(out, vec![Err(Reject::MissingChecksum); 4]);
    assert_eq!(a.stats().missing_checksum, 4);
}

#[test]
fn missing_start_is_counted_per_line() {
    let mut a = SentenceAssembler::new();
    let out = feed(
        &mut a,
        b"GPGGA,,,,,,0,00,99.99,,,,,,*48\r\n\r\n\r\nhello\r\n",
    );
    assert_eq!(
        out,
        vec![Err(Reject::MissingStart), Err(Reject::MissingStart)]
    );
    assert_eq!(a.stats().missing_start, 2);
}

#[test]
fn overflow_at_83_characters_and_recovery() {
    // 82 characters exactly (from '$' through the checksum) is accepted.
    let body_82 = format!("GPTXT,{}", "A".repeat(MAX_SENTENCE_LEN - 1 - 6 - 3));
    let cs = body_82.bytes().fold(0u8, |x, b| x ^ b);
    let s82 = format!("${body_82}*{cs:02X}\r\n");
    assert_eq!(s82.len(), MAX_SENTENCE_LEN + 2);
    let body_83 = format!("{body_82}A");
    let cs = body_83.bytes().fold(0u8, |x, b| x ^ b);
    let s83 = format!("${body_83}*{cs:02X}\r\n");
    let mut a = SentenceAssembler::new();
    let out = feed(&mut a, s82.as_bytes());
    assert!(matches!(out.as_slice(), [Ok(_)]));
    let out = feed(&mut a, s83.as_bytes());
    assert_eq!(out, vec![Err(Reject::Overflow)]);
    // The rest of the long line is skipped; the next sentence is fine.
    let out = feed(&mut a, b"$GPGGA,,,,,,0,00,99.99,,,,,,*48\r\n");
    assert!(matches!(out.as_slice(), [Ok(_)]));
    assert_eq!(a.stats().overflow, 1);
    assert_eq!(a.stats().accepted, 2);
}

#[test]
fn non_ascii_and_control_characters() {
    let mut a = SentenceAssembler::new();
    let out = feed(
        &mut a,
        b"$GPTXT,01,01,02,caf\xc3\xa9*00\r\n$GPTXT,\x07*00\r\n",
    );
    assert_eq!(out, vec![Err(Reject::NonAscii), Err(Reject::NonAscii)]);
    assert_eq!(a.stats().non_ascii, 2);
}

#[test]
fn partial_lines() {
    let mut a = SentenceAssembler::new();
    // Cut off by a new '$', then CR followed by something other than LF,
    // then end of stream in the middle of a sentence.
    let out = feed(
        &mut a,
        b"$GPGSV,3,1,12$GPGGA,,,,,,0,00,99.99,,,,,,*48\r\n$GPGGA,,,,,,0,00,99.99,,,,,,*48\rX\n$GPRMC,12",
    );
    assert_eq!(out.len(), 3);
    assert_eq!(out[0], Err(Reject::Partial));
    assert!(out[1].is_ok());
    assert_eq!(out[2], Err(Reject::Partial));
    assert_eq!(a.finish_stream(), Some(Reject::Partial));
    assert_eq!(a.finish_stream(), None);
    assert_eq!(a.stats().partial, 3);
    assert_eq!(a.stats().sentences(), 4);
}
