//! The server side of the Modbus application protocol: function codes 03,
//! 06 and 16 on a register map, replies built into the caller's buffer.
//!
//! Modbus Application Protocol Specification V1.1b3 (modbus.org, 2012):
//! §6.3 (03 Read Holding Registers, 1 to 125 registers), §6.6 (06 Write
//! Single Register), §6.12 (16 Write Multiple Registers, 1 to 123
//! registers), §7 (exception responses). Checks follow the order of the
//! spec's state diagrams: function code (01), quantity and lengths (03),
//! address range (02), then the operation itself (its own code, 04 when the
//! device fails).

use crate::crc::crc16;
use crate::rtu::MAX_FRAME_BYTES;

/// Read Holding Registers.
pub const FC_READ_HOLDING: u8 = 0x03;
/// Write Single Register.
pub const FC_WRITE_SINGLE: u8 = 0x06;
/// Write Multiple Registers.
pub const FC_WRITE_MULTIPLE: u8 = 0x10;
/// Most registers one 03 request reads (§6.3).
pub const MAX_READ_REGISTERS: u16 = 125;
/// Most registers one 16 request writes (§6.12).
pub const MAX_WRITE_REGISTERS: u16 = 123;
/// The broadcast address: every server acts, none replies (Modbus over
/// Serial Line V1.02, §2.2).
pub const BROADCAST: u8 = 0;

/// A Modbus exception code (Application Protocol V1.1b3, §7).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Exception {
    /// 01: the function code is not served, or not in the server's present
    /// state (writes while they are disabled).
    IllegalFunction = 1,
    /// 02: an address, or the range from it, is not in the map (or a write
    /// covers a read-only register or only part of a point).
    IllegalDataAddress = 2,
    /// 03: a quantity, length or value is not allowed.
    IllegalDataValue = 3,
    /// 04: the device failed to carry out the request.
    ServerDeviceFailure = 4,
    /// 06: the device is busy with a long command; try again later.
    ServerDeviceBusy = 6,
}

/// A register space a [`Server`] serves.
pub trait RegisterMap {
    /// Checks that `count` registers from `start` may all be read (the
    /// range lies in the map): [`Exception::IllegalDataAddress`] if not.
    fn check_read(&mut self, start: u16, count: u16) -> Result<(), Exception>;
    /// The value of register `addr`, after a successful `check_read` of a
    /// range that holds it.
    fn read(&mut self, addr: u16) -> u16;
    /// Writes `values` (big-endian register pairs) from `start`. `broadcast`
    /// tells the request came to address 0 (no reply will be sent).
    fn write(&mut self, start: u16, values: &[u8], broadcast: bool) -> Result<(), Exception>;
}

/// The Modbus server: its address and whether writes are served.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Server {
    /// Our address on the bus, 1 to 247.
    pub address: u8,
    /// Writes (06, 16) are served only when set; otherwise they get
    /// [`Exception::IllegalFunction`], the spec's code for a function the
    /// server will not perform in its present state (§7: "the server is in
    /// the wrong state to process a request of this type"). 04 would tell
    /// the SCADA the device failed, and a master may retry or raise a
    /// device alarm for that.
    pub writes_enabled: bool,
}

/// The big-endian register at byte `at` of `frame`, 0 past its end.
fn be16(frame: &[u8], at: usize) -> u16 {
    match frame.get(at..at + 2) {
        Some(&[hi, lo]) => u16::from_be_bytes([hi, lo]),
        _ => 0,
    }
}

impl Server {
    /// The reply to `frame` (address, function code, data; CRC already
    /// checked and removed, as [`crate::rtu::RtuReceiver::poll`] gives it),
    /// written into `out` with its CRC: its length, or `None` when nothing
    /// is to be sent (another server's address, broadcast, a frame of fewer
    /// than 2 or more than 254 bytes). `out` needs [`MAX_FRAME_BYTES`]; a
    /// shorter one gets nothing written. (The frame is copied into `out`
    /// and served there: [`Server::handle_in_place`].)
    pub fn handle<M: RegisterMap>(
        &self,
        frame: &[u8],
        map: &mut M,
        out: &mut [u8],
    ) -> Option<usize> {
        let out = out.get_mut(..MAX_FRAME_BYTES)?;
        out.get_mut(..frame.len())?.copy_from_slice(frame);
        self.handle_in_place(out, frame.len(), map)
    }

    /// The reply to the frame in `buf[..len]` (as
    /// [`crate::rtu::RtuReceiver::poll_in_place`] leaves it), written over
    /// it in `buf` with its CRC: its length, or `None` as for
    /// [`Server::handle`]. No second 256-byte buffer: the request's fields
    /// are read before the reply overwrites them.
    pub fn handle_in_place<M: RegisterMap>(
        &self,
        buf: &mut [u8],
        len: usize,
        map: &mut M,
    ) -> Option<usize> {
        let buf = buf.get_mut(..MAX_FRAME_BYTES)?;
        if !(2..=MAX_FRAME_BYTES - 2).contains(&len) {
            return None;
        }
        let address = buf[0];
        if address != self.address && address != BROADCAST {
            return None;
        }
        let broadcast = address == BROADCAST;
        let function = buf[1];
        let result = self.serve(function, buf, len, map, broadcast);
        if broadcast {
            return None;
        }
        let len = match result {
            Ok(len) => len,
            Err(e) => {
                buf[1] = function | 0x80;
                buf[2] = e as u8;
                3
            }
        };
        // Checked, not indexed: no panic path in a firmware image.
        let [lo, hi] = crc16(buf.get(..len)?).to_le_bytes();
        let end = len.checked_add(2)?;
        if let [a, b] = buf.get_mut(len..end)? {
            *a = lo;
            *b = hi;
        }
        Some(end)
    }

    /// Serves the request in `buf[..len]`, writing the reply over it from
    /// byte 2 on (address and function code stay); the reply's length
    /// without the CRC.
    fn serve<M: RegisterMap>(
        &self,
        function: u8,
        buf: &mut [u8],
        len: usize,
        map: &mut M,
        broadcast: bool,
    ) -> Result<usize, Exception> {
        let request = buf.get(..len).unwrap_or(&[]);
        let start = be16(request, 2);
        let count = be16(request, 4);
        match function {
            FC_READ_HOLDING => {
                if broadcast {
                    // A read cannot be answered; nothing to do.
                    return Ok(0);
                }
                if len != 6 || count == 0 || count > MAX_READ_REGISTERS {
                    return Err(Exception::IllegalDataValue);
                }
                check_range(start, count)?;
                map.check_read(start, count)?;
                // `start` and `count` are read: the reply may overwrite them.
                // At most 125 registers: 250 bytes after the 3 of the
                // header, inside the 256-byte frame (checked, not indexed).
                let bytes = usize::from(count) * 2;
                *buf.get_mut(2).ok_or(Exception::IllegalDataValue)? = bytes as u8;
                let reply = buf
                    .get_mut(3..3 + bytes)
                    .ok_or(Exception::IllegalDataValue)?;
                // `start + i` stays within 65,535: `check_range` above.
                // Two bytes a register, without `chunks_exact_mut`'s
                // check of its chunk size (a panic path where not inlined).
                let mut out = reply.iter_mut();
                for i in 0..count {
                    for byte in map.read(start + i).to_be_bytes() {
                        if let Some(o) = out.next() {
                            *o = byte;
                        }
                    }
                }
                Ok(3 + bytes)
            }
            FC_WRITE_SINGLE => {
                if !self.writes_enabled {
                    return Err(Exception::IllegalFunction);
                }
                if len != 6 {
                    return Err(Exception::IllegalDataValue);
                }
                let value = buf.get(4..6).ok_or(Exception::IllegalDataValue)?;
                map.write(start, value, broadcast)?;
                // The reply echoes the request, already in place.
                Ok(6)
            }
            FC_WRITE_MULTIPLE => {
                if !self.writes_enabled {
                    return Err(Exception::IllegalFunction);
                }
                let byte_count = request.get(6).copied().map_or(0, usize::from);
                if count == 0
                    || count > MAX_WRITE_REGISTERS
                    || byte_count != usize::from(count) * 2
                    || len != 7 + byte_count
                {
                    return Err(Exception::IllegalDataValue);
                }
                check_range(start, count)?;
                let values = buf.get(7..len).ok_or(Exception::IllegalDataValue)?;
                map.write(start, values, broadcast)?;
                // The reply: address, function, start and count, in place.
                Ok(6)
            }
            _ => Err(Exception::IllegalFunction),
        }
    }
}

/// The range must not run past register 65,535.
fn check_range(start: u16, count: u16) -> Result<(), Exception> {
    match start.checked_add(count - 1) {
        Some(_) => Ok(()),
        None => Err(Exception::IllegalDataAddress),
    }
}
