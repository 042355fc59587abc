//! Intel HEX, the format `avrdude -U eeprom:w:FILE:i` takes (and
//! `avr-objcopy -O ihex` writes): lines `:LLAAAATT<data>CC`, LL data bytes
//! at 16-bit address AAAA, record type TT, CC the two's complement of the
//! sum of all the other bytes. Record types 00 (data) and 01 (end of file)
//! are read; an EEPROM image (1 KB on the ATmega328P, 4 KB on the
//! ATmega2560) needs no other.

/// The bytes of an Intel HEX text as one image from address 0: bytes no
/// record gives are 0xFF (erased EEPROM), up to the highest byte given.
/// Stops at the end-of-file record (01); blank lines are skipped. Errors
/// name the line: a line not starting with `:`, odd or non-hex digits, a
/// length that disagrees with the line, a bad checksum, a record type other
/// than 00 and 01, or a missing end-of-file record.
pub fn parse(text: &str) -> Result<Vec<u8>, String> {
    let mut image: Vec<u8> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let n = i + 1;
        let line = raw.trim();
        if line.is_empty() {
            continue;
        }
        let hex = line
            .strip_prefix(':')
            .ok_or(format!("line {n}: does not start with ':'"))?;
        if hex.len() % 2 != 0 || hex.len() < 10 {
            return Err(format!("line {n}: not a record"));
        }
        let bytes = (0..hex.len() / 2)
            .map(|k| u8::from_str_radix(&hex[2 * k..2 * k + 2], 16))
            .collect::<Result<Vec<u8>, _>>()
            .map_err(|_| format!("line {n}: not hexadecimal"))?;
        let len = usize::from(bytes[0]);
        if bytes.len() != len + 5 {
            return Err(format!(
                "line {n}: {} data bytes for a length of {len}",
                bytes.len() - 5
            ));
        }
        let sum = bytes.iter().fold(0u8, |s, b| s.wrapping_add(*b));
        if sum != 0 {
            return Err(format!("line {n}: bad checksum"));
        }
        let addr = usize::from(u16::from_be_bytes([bytes[1], bytes[2]]));
        let data = &bytes[4..4 + len];
        match bytes[3] {
            0x00 => {
                let end = addr + len;
                if image.len() < end {
                    image.resize(end, 0xFF);
                }
                image[addr..end].copy_from_slice(data);
            }
            0x01 => return Ok(image),
            t => {
                return Err(format!(
                    "line {n}: record type {t:02X} (only 00 data and 01 end of file)"
                ))
            }
        }
    }
    Err("no end-of-file record (:00000001FF)".into())
}

/// `bytes` from address 0 as Intel HEX: data records of 16 bytes (the last
/// shorter), then the end-of-file record; each line ends with `\n`.
/// Panics above 64 KB (no extended-address records).
pub fn encode(bytes: &[u8]) -> String {
    assert!(
        bytes.len() <= 0x1_0000,
        "Intel HEX without extended addresses"
    );
    let mut out = String::new();
    for (k, chunk) in bytes.chunks(16).enumerate() {
        let addr = (k * 16) as u16;
        let mut rec = vec![chunk.len() as u8];
        rec.extend_from_slice(&addr.to_be_bytes());
        rec.push(0x00);
        rec.extend_from_slice(chunk);
        let sum = rec.iter().fold(0u8, |s, b| s.wrapping_add(*b));
        rec.push(sum.wrapping_neg());
        out.push(':');
        for b in rec {
            out.push_str(&format!("{b:02X}"));
        }
        out.push('\n');
    }
    out.push_str(":00000001FF\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_avrdude_style_records() {
        // Two data records with a gap (erased), CRLF ends, then EOF.
        let text = ":0400000001020304F2\r\n:02000800AABB91\r\n:00000001FF\r\n";
        assert_eq!(
            parse(text).unwrap(),
            [1, 2, 3, 4, 0xFF, 0xFF, 0xFF, 0xFF, 0xAA, 0xBB]
        );
        // Lines after the end-of-file record are not read.
        assert_eq!(parse(":00000001FF\n:zz\n").unwrap(), Vec::<u8>::new());
    }

    #[test]
    fn refuses_what_it_cannot_read() {
        for (text, want) in [
            (
                "0400000001020304F2\n:00000001FF\n",
                "line 1: does not start",
            ),
            (":0400000001020304F3\n:00000001FF\n", "line 1: bad checksum"),
            (":0500000001020304F2\n:00000001FF\n", "line 1: 4 data bytes"),
            (":0400000001020G04F2\n", "line 1: not hexadecimal"),
            (":020000040000FA\n:00000001FF\n", "line 1: record type 04"),
            (":0400000001020304F2\n", "no end-of-file record"),
        ] {
            let e = parse(text).unwrap_err();
            assert!(e.starts_with(want), "{text:?}: {e}");
        }
    }

    #[test]
    fn round_trip() {
        let bytes: Vec<u8> = (0..1024u32).map(|i| (i * 37 % 251) as u8).collect();
        let text = encode(&bytes);
        assert_eq!(text.lines().count(), 1024 / 16 + 1);
        assert_eq!(parse(&text).unwrap(), bytes);
        assert_eq!(encode(&[]), ":00000001FF\n");
    }
}
