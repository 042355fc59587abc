//! Function codes 03, 06 and 16 and their exceptions, transaction by
//! transaction: the requests and replies of the Modbus Application Protocol
//! Specification V1.1b3's examples (§6.3, §6.6, §6.12) framed for RTU.

use suntracker_modbus::crc::crc16;
use suntracker_modbus::pdu::{Exception, RegisterMap, Server};

/// Registers 0 to 0x00FF, holding their test values; 0x0080 and up refuse
/// writes with a device failure.
struct Table {
    regs: [u16; 256],
    writes: Vec<(u16, Vec<u8>, bool)>,
}

impl Table {
    fn new() -> Self {
        let mut regs = [0; 256];
        // §6.3's example: registers 108 to 110 hold 0x022B, 0x0000, 0x0064.
        regs[0x6B] = 0x022B;
        regs[0x6C] = 0x0000;
        regs[0x6D] = 0x0064;
        Self {
            regs,
            writes: Vec::new(),
        }
    }
}

impl RegisterMap for Table {
    fn check_read(&mut self, start: u16, count: u16) -> Result<(), Exception> {
        if u32::from(start) + u32::from(count) <= 256 {
            Ok(())
        } else {
            Err(Exception::IllegalDataAddress)
        }
    }
    fn read(&mut self, addr: u16) -> u16 {
        self.regs[usize::from(addr)]
    }
    fn write(&mut self, start: u16, values: &[u8], broadcast: bool) -> Result<(), Exception> {
        if u32::from(start) + values.len() as u32 / 2 > 256 {
            return Err(Exception::IllegalDataAddress);
        }
        if start >= 0x80 {
            return Err(Exception::ServerDeviceFailure);
        }
        for (i, pair) in values.chunks(2).enumerate() {
            self.regs[usize::from(start) + i] = u16::from_be_bytes([pair[0], pair[1]]);
        }
        self.writes.push((start, values.to_vec(), broadcast));
        Ok(())
    }
}

const SERVER: Server = Server {
    address: 0x11,
    writes_enabled: true,
};

fn with_crc(body: &[u8]) -> Vec<u8> {
    let mut v = body.to_vec();
    v.extend_from_slice(&crc16(body).to_le_bytes());
    v
}

/// The reply (with its CRC, checked) to `request` (without CRC).
fn transact(server: &Server, table: &mut Table, request: &[u8]) -> Option<Vec<u8>> {
    let mut out = [0xEE; 256];
    let len = server.handle(request, table, &mut out)?;
    let reply = out[..len].to_vec();
    assert_eq!(crc16(&reply), 0, "the reply's CRC");
    Some(reply)
}

#[test]
fn read_holding_registers_spec_example() {
    let mut t = Table::new();
    let reply = transact(&SERVER, &mut t, &[0x11, 0x03, 0x00, 0x6B, 0x00, 0x03]).unwrap();
    // §6.3: 03 06 02 2B 00 00 00 64; the CRC over the whole RTU reply.
    assert_eq!(
        reply,
        with_crc(&[0x11, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64])
    );
}

#[test]
fn the_well_known_read_frame() {
    // `01 03 00 00 00 0A C5 CD`: ten registers from 0 at server 1.
    let server = Server {
        address: 1,
        writes_enabled: false,
    };
    let mut t = Table::new();
    t.regs[..10].copy_from_slice(&[1, 2, 3, 4, 5, 6, 7, 8, 9, 0xABCD]);
    let request = [0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD];
    assert_eq!(crc16(&request), 0);
    let reply = transact(&server, &mut t, &request[..6]).unwrap();
    let mut body = vec![0x01, 0x03, 20];
    for v in [1_u16, 2, 3, 4, 5, 6, 7, 8, 9, 0xABCD] {
        body.extend_from_slice(&v.to_be_bytes());
    }
    assert_eq!(reply, with_crc(&body));
}

#[test]
fn read_quantity_limits() {
    let mut t = Table::new();
    // 125 registers: the most (§6.3); the reply is 5 + 250 = 255 bytes.
    let reply = transact(&SERVER, &mut t, &[0x11, 0x03, 0x00, 0x00, 0x00, 125]).unwrap();
    assert_eq!(reply.len(), 255);
    assert_eq!(reply[2], 250);
    for count in [0_u16, 126, 0xFFFF] {
        let [hi, lo] = count.to_be_bytes();
        let reply = transact(&SERVER, &mut t, &[0x11, 0x03, 0x00, 0x00, hi, lo]).unwrap();
        assert_eq!(reply, with_crc(&[0x11, 0x83, 0x03]), "quantity {count}");
    }
}

#[test]
fn read_address_exceptions() {
    let mut t = Table::new();
    // The map ends at 0x00FF.
    let reply = transact(&SERVER, &mut t, &[0x11, 0x03, 0x00, 0xFF, 0x00, 0x02]).unwrap();
    assert_eq!(reply, with_crc(&[0x11, 0x83, 0x02]));
    // A range past register 65,535.
    let reply = transact(&SERVER, &mut t, &[0x11, 0x03, 0xFF, 0xFF, 0x00, 0x02]).unwrap();
    assert_eq!(reply, with_crc(&[0x11, 0x83, 0x02]));
    let reply = transact(&SERVER, &mut t, &[0x11, 0x03, 0x00, 0xFF, 0x00, 0x01]).unwrap();
    assert_eq!(reply.len(), 7);
}

#[test]
fn malformed_lengths_are_illegal_values() {
    let mut t = Table::new();
    for request in [
        &[0x11, 0x03, 0x00, 0x6B, 0x00][..],
        &[0x11, 0x03, 0x00, 0x6B, 0x00, 0x01, 0x00],
        &[0x11, 0x06, 0x00],
    ] {
        let reply = transact(&SERVER, &mut t, request).unwrap();
        assert_eq!(reply[1..3], [request[1] | 0x80, 0x03]);
    }
    // A lone address: no function code, nothing to answer.
    assert_eq!(transact(&SERVER, &mut t, &[0x11]), None);
}

#[test]
fn write_single_register_spec_example() {
    let mut t = Table::new();
    let request = [0x11, 0x06, 0x00, 0x01, 0x00, 0x03];
    let reply = transact(&SERVER, &mut t, &request).unwrap();
    // §6.6: the reply echoes the request.
    assert_eq!(reply, with_crc(&request));
    assert_eq!(t.regs[1], 3);
    assert_eq!(t.writes, vec![(1, vec![0x00, 0x03], false)]);
}

#[test]
fn write_multiple_registers_spec_example() {
    let mut t = Table::new();
    let request = [
        0x11, 0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02,
    ];
    let reply = transact(&SERVER, &mut t, &request).unwrap();
    // §6.12: 10 00 01 00 02.
    assert_eq!(reply, with_crc(&[0x11, 0x10, 0x00, 0x01, 0x00, 0x02]));
    assert_eq!(t.regs[1..3], [0x000A, 0x0102]);
}

#[test]
fn write_multiple_quantity_and_byte_count() {
    let mut t = Table::new();
    let request = |count: u16, byte_count: u8, data: usize| {
        let mut r = vec![0x11, 0x10, 0x00, 0x00];
        r.extend_from_slice(&count.to_be_bytes());
        r.push(byte_count);
        r.extend(std::iter::repeat_n(0x55, data));
        r
    };
    // 123 registers, the most (§6.12).
    let reply = transact(&SERVER, &mut t, &request(123, 246, 246)).unwrap();
    assert_eq!(reply, with_crc(&[0x11, 0x10, 0x00, 0x00, 0x00, 123]));
    // 124 registers (in the most a frame holds: 254 bytes without CRC).
    for (count, byte_count, data) in [(124, 248, 247), (0, 0, 0), (2, 4, 3), (2, 3, 3), (2, 4, 5)] {
        let reply = transact(&SERVER, &mut t, &request(count, byte_count, data)).unwrap();
        assert_eq!(
            reply,
            with_crc(&[0x11, 0x90, 0x03]),
            "{count} {byte_count} {data}"
        );
    }
}

#[test]
fn unsupported_functions_are_illegal() {
    let mut t = Table::new();
    for function in [
        0x01_u8, 0x02, 0x04, 0x05, 0x0F, 0x17, 0x2B, 0x7F, 0x80, 0xFF,
    ] {
        let reply = transact(&SERVER, &mut t, &[0x11, function, 0x00, 0x00, 0x00, 0x01]).unwrap();
        assert_eq!(
            reply,
            with_crc(&[0x11, function | 0x80, 0x01]),
            "function {function:#04x}"
        );
    }
}

#[test]
fn writes_disabled_are_illegal_functions() {
    let server = Server {
        address: 0x11,
        writes_enabled: false,
    };
    let mut t = Table::new();
    let reply = transact(&server, &mut t, &[0x11, 0x06, 0x00, 0x01, 0x00, 0x03]).unwrap();
    assert_eq!(reply, with_crc(&[0x11, 0x86, 0x01]));
    let reply = transact(
        &server,
        &mut t,
        &[0x11, 0x10, 0x00, 0x01, 0x00, 0x01, 0x02, 0x00, 0x0A],
    )
    .unwrap();
    assert_eq!(reply, with_crc(&[0x11, 0x90, 0x01]));
    assert!(t.writes.is_empty());
}

#[test]
fn map_refusals_pass_through() {
    let mut t = Table::new();
    let reply = transact(&SERVER, &mut t, &[0x11, 0x06, 0x00, 0x80, 0x00, 0x03]).unwrap();
    assert_eq!(reply, with_crc(&[0x11, 0x86, 0x04]));
    let reply = transact(&SERVER, &mut t, &[0x11, 0x06, 0x01, 0x00, 0x00, 0x03]).unwrap();
    assert_eq!(reply, with_crc(&[0x11, 0x86, 0x02]));
}

#[test]
fn other_addresses_get_nothing() {
    let mut t = Table::new();
    for address in [0x01, 0x10, 0x12, 0xF7, 0xFF] {
        assert_eq!(
            transact(&SERVER, &mut t, &[address, 0x03, 0x00, 0x6B, 0x00, 0x03]),
            None
        );
        assert_eq!(
            transact(&SERVER, &mut t, &[address, 0x06, 0x00, 0x01, 0x00, 0x03]),
            None
        );
    }
    assert!(t.writes.is_empty());
}

#[test]
fn broadcast_writes_act_without_reply() {
    let mut t = Table::new();
    assert_eq!(
        transact(&SERVER, &mut t, &[0x00, 0x06, 0x00, 0x01, 0x00, 0x03]),
        None
    );
    assert_eq!(t.writes, vec![(1, vec![0x00, 0x03], true)]);
    // Reads, errors and unknown functions: nothing either.
    assert_eq!(
        transact(&SERVER, &mut t, &[0x00, 0x03, 0x00, 0x6B, 0x00, 0x03]),
        None
    );
    assert_eq!(
        transact(&SERVER, &mut t, &[0x00, 0x06, 0x00, 0x80, 0x00, 0x03]),
        None
    );
    assert_eq!(
        transact(&SERVER, &mut t, &[0x00, 0x2B, 0x0E, 0x01, 0x00]),
        None
    );
}

#[test]
fn frames_no_rtu_line_carries_get_nothing() {
    let mut t = Table::new();
    // 255 bytes and a CRC would be 257 on the wire.
    let mut request = vec![0x11, 0x10, 0x00, 0x00, 0x00, 124, 248];
    request.resize(255, 0);
    assert_eq!(transact(&SERVER, &mut t, &request), None);
    request.truncate(254);
    assert!(transact(&SERVER, &mut t, &request).is_some());
}

#[test]
fn reply_in_place_over_the_request() {
    let mut t = Table::new();
    let mut buf = [0xEE_u8; 256];
    let request = [0x11, 0x03, 0x00, 0x6B, 0x00, 0x03];
    buf[..6].copy_from_slice(&request);
    let len = SERVER.handle_in_place(&mut buf, 6, &mut t).unwrap();
    assert_eq!(
        buf[..len],
        with_crc(&[0x11, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64])[..]
    );
    let request = [
        0x11, 0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02,
    ];
    buf[..11].copy_from_slice(&request);
    let len = SERVER.handle_in_place(&mut buf, 11, &mut t).unwrap();
    assert_eq!(
        buf[..len],
        with_crc(&[0x11, 0x10, 0x00, 0x01, 0x00, 0x02])[..]
    );
    assert_eq!(t.regs[1..3], [0x000A, 0x0102]);
    // A length past the buffer, or a buffer too short: nothing.
    assert_eq!(SERVER.handle_in_place(&mut buf, 300, &mut t), None);
    assert_eq!(SERVER.handle_in_place(&mut buf[..255], 6, &mut t), None);
}

#[test]
fn short_output_buffer_gets_nothing() {
    let mut t = Table::new();
    let mut out = [0; 255];
    assert_eq!(
        SERVER.handle(&[0x11, 0x03, 0x00, 0x6B, 0x00, 0x03], &mut t, &mut out),
        None
    );
}
