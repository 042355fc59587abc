//! The SunSpec map of a simulated tracker served over Modbus RTU on this
//! process's standard input and output, for a SunSpec client on the other
//! side of a pseudo-terminal (`modbus/sunspec/pysunspec2_e2e.py` starts it
//! with the pty's master as both):
//!
//!   pty_server [--address N] [--baud B] [--no-gps] [--read-only]
//!
//! Bytes are stamped with the microseconds since start as they arrive, and
//! go through the same receiver, server and map as on a board.

#[path = "../tests/common/mod.rs"]
mod common;

use std::io::{Read, Write};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use suntracker_modbus::rtu::{Push, RtuReceiver, RtuTiming};
use suntracker_modbus::sunspec::SunSpecMap;
use suntracker_modbus::Server;

fn main() {
    let mut address = 1_u8;
    let mut baud = 19_200_u32;
    let mut gps = true;
    let mut writes_enabled = true;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = || args.next().and_then(|v| v.parse::<u32>().ok());
        match arg.as_str() {
            "--address" => address = value().and_then(|v| u8::try_from(v).ok()).unwrap_or(0),
            "--baud" => baud = value().unwrap_or(0),
            "--no-gps" => gps = false,
            "--read-only" => writes_enabled = false,
            _ => {
                eprintln!("pty_server: unknown argument {arg}");
                std::process::exit(2);
            }
        }
    }
    if !(1..=247).contains(&address) || baud == 0 {
        eprintln!("pty_server: --address 1..247, --baud > 0");
        std::process::exit(2);
    }

    let start = Instant::now();
    let micros = move || start.elapsed().as_micros() as u32;
    let (tx, rx_bytes) = mpsc::channel::<(u8, u32)>();
    std::thread::spawn(move || {
        let mut stdin = std::io::stdin().lock();
        let mut buf = [0_u8; 512];
        while let Ok(n @ 1..) = stdin.read(&mut buf) {
            let t = micros();
            for &b in &buf[..n] {
                if tx.send((b, t)).is_err() {
                    return;
                }
            }
        }
    });

    let mut receiver = RtuReceiver::new(RtuTiming::from_baud_us(baud));
    let server = Server {
        address,
        writes_enabled,
    };
    let mut map = SunSpecMap::new(common::Demo::new(address, gps), gps);
    let mut out = [0_u8; 256];
    let mut stdout = std::io::stdout().lock();
    eprintln!(
        "pty_server: address {address}, {baud} baud, GPS model {gps}, writes {writes_enabled}"
    );
    loop {
        let byte = match rx_bytes.recv_timeout(Duration::from_micros(500)) {
            Ok(b) => Some(b),
            Err(mpsc::RecvTimeoutError::Timeout) => None,
            Err(mpsc::RecvTimeoutError::Disconnected) => return,
        };
        let mut reply = None;
        if let Some((b, t)) = byte {
            if receiver.push(b, t) == Push::FrameWaiting {
                if let Some(frame) = receiver.poll(t) {
                    reply = server.handle(frame, &mut map, &mut out);
                }
                receiver.push(b, t);
            }
        } else if let Some(frame) = receiver.poll(micros()) {
            reply = server.handle(frame, &mut map, &mut out);
        }
        if let Some(len) = reply {
            if stdout
                .write_all(&out[..len])
                .and_then(|()| stdout.flush())
                .is_err()
            {
                return;
            }
            for c in map.data.commands.drain(..) {
                eprintln!("pty_server: {c:?}");
            }
        }
    }
}
