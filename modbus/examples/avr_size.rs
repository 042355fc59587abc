//! What the frame layer, the server and the SunSpec map cost in an AVR
//! image: the receiver, server and map over a dummy tracker whose every
//! value, like every received byte and time stamp, comes through
//! `black_box` (so nothing is folded away), the replies going to
//! `black_box` too. `avr_size_base` is the same loop without them; the
//! difference of the two images' `avr-size` is the cost.
//!
//! `bash modbus/avr_size.sh` builds both for the ATmega2560 and prints it.
//! On the host this example does nothing.
#![cfg_attr(target_arch = "avr", no_std, no_main)]

#[cfg(target_arch = "avr")]
mod avr {
    use core::hint::black_box;
    use suntracker_modbus::rtu::{Push, RtuReceiver, RtuTiming};
    use suntracker_modbus::sunspec::{
        Angles, Command, Control, DateTime, GpsFix, Identity, SunSpecMap, TrackerData, VendorStatus,
    };
    use suntracker_modbus::{Exception, Server};

    struct Dummy {
        time: DateTime,
        target: Angles,
        position: Angles,
        manual: Angles,
        control: Control,
        fix: GpsFix,
        vendor: VendorStatus,
    }

    impl TrackerData for Dummy {
        fn identity(&self) -> Identity<'_> {
            black_box(Identity {
                manufacturer: "suntracker",
                model: "mega",
                options: "",
                version: "0.1.0",
                serial: "1",
                controller_name: "st",
                tracker_name: "1",
            })
        }
        fn device_address(&self) -> u8 {
            black_box(1)
        }
        fn local_time(&self) -> Option<DateTime> {
            black_box(Some(black_box(self).time))
        }
        fn target_cdeg(&self) -> Option<Angles> {
            black_box(Some(black_box(self).target))
        }
        fn position_cdeg(&self) -> Option<Angles> {
            black_box(Some(black_box(self).position))
        }
        fn control(&self) -> Control {
            black_box(self).control
        }
        fn manual_target_cdeg(&self) -> Option<Angles> {
            black_box(Some(black_box(self).manual))
        }
        fn alarms(&self) -> u16 {
            black_box(0)
        }
        fn gps_fix(&self) -> Option<GpsFix> {
            black_box(Some(black_box(self).fix))
        }
        fn vendor(&self) -> VendorStatus {
            black_box(self).vendor
        }
        fn command(&mut self, command: Command) -> Result<(), Exception> {
            black_box(command);
            black_box(Ok(()))
        }
    }

    /// The reply written over the request in the receiver's buffer (no
    /// second 256-byte buffer), sent byte by byte.
    fn serve<D: TrackerData>(
        rx: &mut RtuReceiver,
        t: u32,
        server: &Server,
        map: &mut SunSpecMap<D>,
    ) {
        if let Some((buf, len)) = rx.poll_in_place(t) {
            if let Some(len) = server.handle_in_place(buf, len, map) {
                for &b in buf.get(..len).unwrap_or(&[]) {
                    black_box(b);
                }
            }
        }
    }

    #[no_mangle]
    pub extern "C" fn main() -> ! {
        let t0 = DateTime::default();
        let a = Angles::default();
        let data = black_box(Dummy {
            time: t0,
            target: a,
            position: a,
            manual: a,
            control: Control::Automatic,
            fix: GpsFix {
                utc: t0,
                latitude_e7deg: 0,
                longitude_e7deg: 0,
                altitude_m: 0,
            },
            vendor: VendorStatus {
                mode_code: 0,
                stow_reason: 0,
                wind_speed_dms: None,
                fault_bits: 0,
                fault_bits_hi: 0,
                firmware: [0; 3],
                stow_commanded: false,
            },
        });
        let mut rx = RtuReceiver::new(RtuTiming::from_baud_us(black_box(19_200)));
        let server = Server {
            address: black_box(1),
            writes_enabled: black_box(true),
        };
        let mut map = SunSpecMap::new(data, black_box(true));
        loop {
            let (byte, t) = black_box((0_u8, 0_u32));
            if rx.push(byte, t) == Push::FrameWaiting {
                serve(&mut rx, t, &server, &mut map);
                black_box(rx.push(byte, t));
            }
            serve(&mut rx, black_box(t), &server, &mut map);
        }
    }

    #[panic_handler]
    fn panic(_: &core::panic::PanicInfo) -> ! {
        loop {}
    }
}

#[cfg(not(target_arch = "avr"))]
fn main() {}
