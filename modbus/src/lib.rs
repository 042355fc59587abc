//! A Modbus RTU server with the SunSpec register map of a dual-axis solar
//! tracker: `no_std`, no allocation, no `unsafe`, no floating point and no
//! 64-bit arithmetic, for the 8-bit AVR boards as well as the Cortex-M4F.
//!
//! A plant's SCADA reads the tracker's state and commands it over RS-485
//! through the SunSpec information models: model 1 (Common), model 601
//! (Tracker Controller) with one tracker, model 305 (GPS) when a receiver is
//! fitted, and the vendor model 64201 (mode, stow reason, wind, faults,
//! firmware version, stow command).
//!
//! # Layers
//!
//! - [`crc`]: the CRC-16 of Modbus RTU.
//! - [`line`](mod@line): [`HalfDuplexLine`], an RS-485 port driven by a UART's
//!   interrupts (replies sent and the driver released without the loop).
//! - [`ring`]: [`StampedRing`], the queue of received bytes with their
//!   arrival times between a UART's receive interrupt and the frame layer.
//! - [`rtu`]: the frame layer. [`RtuReceiver`] takes each byte with its
//!   arrival time and hands out whole frames after the silence of 3.5
//!   characters, dropping frames with a gap of over 1.5 characters, over
//!   256 bytes or with a bad CRC. Every call is O(1), nothing blocks.
//! - [`pdu`]: the [`Server`] of function codes 03, 06 and 16 on any
//!   [`RegisterMap`], with exceptions 01 to 04, replying over the request
//!   in the receiver's buffer (or into the caller's); nothing for other
//!   addresses or broadcast.
//! - [`sunspec`]: [`SunSpecMap`], the register map at 40000, computing each
//!   register on read from a [`TrackerData`] the firmware implements (no
//!   copy of the map in RAM); writes become [`sunspec::Command`]s.
//!
//! # Use
//!
//! One pass of the firmware's loop: the UART's receive interrupt queues
//! each byte with its time in µs; the loop feeds them to the receiver and
//! sends the reply after the frame's silence (the RS-485 driver enabled
//! around the send).
//!
//! ```
//! use suntracker_modbus::{Push, RtuReceiver, Server, SunSpecMap, TrackerData};
//!
//! fn modbus_pass<D: TrackerData>(
//!     receiver: &mut RtuReceiver,
//!     server: &Server,
//!     map: &mut SunSpecMap<D>,
//!     queue: &mut core::iter::Peekable<impl Iterator<Item = (u8, u32)>>,
//!     now_us: u32,
//!     mut send: impl FnMut(&[u8]),
//! ) {
//!     // The reply is written over the request in the receiver's buffer.
//!     let mut serve = |receiver: &mut RtuReceiver, t_us: u32| {
//!         if let Some((buf, len)) = receiver.poll_in_place(t_us) {
//!             if let Some(len) = server.handle_in_place(buf, len, map) {
//!                 send(&buf[..len]);
//!             }
//!         }
//!     };
//!     while let Some(&(byte, t_us)) = queue.peek() {
//!         if receiver.push(byte, t_us) == Push::FrameWaiting {
//!             // The previous frame ended before this byte: serve it first.
//!             serve(receiver, t_us);
//!             continue;
//!         }
//!         queue.next();
//!     }
//!     serve(receiver, now_us);
//! }
//! ```
//!
//! # Why not `rmodbus`
//!
//! Size and control on an 8-bit AVR. Measured on the ATmega2560 (release
//! profile, opt-level "s", LTO, libgcc's division as the boards link it):
//! rmodbus 0.13 (no_std, heapless) parsing an RTU frame, processing it on
//! its register storage and finalising the reply took 2,210 B of flash over
//! a baseline, against 1,288 B for this crate's [`Server`] on the same
//! 172-register table (rmodbus serves coils, discrete inputs and input
//! registers too, which this crate does not; the probe was built outside
//! this repository). rmodbus's storage also indexes registers by address:
//! serving SunSpec's 40000 needs a 40,172-register array (80 KB of RAM) or
//! an implementation of its 44-method context trait, while [`SunSpecMap`]
//! computes each register when read and keeps nothing. rmodbus leaves frame
//! timing (the 1.5 and 3.5 character silences) to the application; here it
//! is part of the tested crate. The whole of this crate (receiver, server,
//! map over a dummy tracker) is 5,540 B on the ATmega2560 (`bash
//! modbus/avr_size.sh`).
//!
//! # Sources
//!
//! - Modbus Organization, *MODBUS over Serial Line Specification and
//!   Implementation Guide V1.02* (2006): RTU framing (§2.5.1, §2.5.1.1),
//!   the CRC (§6.2.2, Appendix B), broadcast (§2.2).
//! - Modbus Organization, *MODBUS Application Protocol Specification
//!   V1.1b3* (2012): function codes 03, 06, 16 (§6.3, §6.6, §6.12),
//!   exception codes (§7).
//! - SunSpec Alliance, *SunSpec Information Model Reference*: model 1
//!   Common, model 601 Tracker Controller, model 305 GPS, as the JSON model
//!   definitions shipped in the SunSpec Alliance's `pysunspec2` (1.3.7)
//!   give them; `tests/sunspec_layout.rs` checks the map against them.
#![no_std]
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod crc;
pub mod line;
pub mod pdu;
pub mod ring;
pub mod rtu;
pub mod sunspec;

pub use line::{HalfDuplexLine, UartIo};
pub use pdu::{Exception, RegisterMap, Server};
pub use ring::StampedRing;
pub use rtu::{Push, RtuReceiver, RtuTiming};
pub use sunspec::{SunSpecMap, TrackerData};
