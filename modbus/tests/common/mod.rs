//! A simulated tracker behind the SunSpec map, shared by the tests and the
//! pseudo-terminal server example.
#![allow(dead_code)]

use suntracker_modbus::sunspec::{
    alarm, Angles, Command, Control, DateTime, GpsFix, Identity, TrackerData, VendorStatus,
};
use suntracker_modbus::Exception;

/// A tracker at Kano at noon on 2026-03-20, tracking.
#[derive(Debug, Clone)]
pub struct Demo {
    pub address: u8,
    pub control: Control,
    pub manual: Option<Angles>,
    pub stow: bool,
    pub has_gps: bool,
    /// Every command carried out, in order.
    pub commands: Vec<Command>,
    /// The tracker refuses every command with this.
    pub refuse: Option<Exception>,
}

impl Demo {
    pub fn new(address: u8, has_gps: bool) -> Self {
        Self {
            address,
            control: Control::Automatic,
            manual: None,
            stow: false,
            has_gps,
            commands: Vec::new(),
            refuse: None,
        }
    }
}

pub const TIME: DateTime = DateTime {
    year: 2026,
    month: 3,
    day: 20,
    hour: 12,
    minute: 34,
    second: 56,
    millisecond: 789,
    day_of_year: 79,
};
pub const TARGET: Angles = Angles {
    elevation_cdeg: 7_734,
    azimuth_cdeg: 18_050,
};
pub const POSITION: Angles = Angles {
    elevation_cdeg: 7_730,
    azimuth_cdeg: 18_041,
};
pub const FIX: GpsFix = GpsFix {
    utc: TIME,
    latitude_e7deg: 120_022_000,
    longitude_e7deg: 85_919_000,
    altitude_m: 488,
};

impl TrackerData for Demo {
    fn identity(&self) -> Identity<'_> {
        Identity {
            manufacturer: "suntracker",
            model: "dual-axis ATmega2560",
            options: "gps wind",
            version: "0.1.0",
            serial: "ST-000042",
            controller_name: "suntracker",
            tracker_name: "tracker 1",
        }
    }
    fn device_address(&self) -> u8 {
        self.address
    }
    fn local_time(&self) -> Option<DateTime> {
        Some(TIME)
    }
    fn target_cdeg(&self) -> Option<Angles> {
        Some(TARGET)
    }
    fn position_cdeg(&self) -> Option<Angles> {
        Some(POSITION)
    }
    fn control(&self) -> Control {
        self.control
    }
    fn manual_target_cdeg(&self) -> Option<Angles> {
        self.manual
    }
    fn alarms(&self) -> u16 {
        alarm::OBS_EL
    }
    fn gps_fix(&self) -> Option<GpsFix> {
        self.has_gps.then_some(FIX)
    }
    fn vendor(&self) -> VendorStatus {
        VendorStatus {
            mode_code: if self.stow { 3 } else { 8 },
            stow_reason: if self.stow { 2 } else { 0 },
            wind_speed_dms: Some(53),
            fault_bits: 0x8000_0005,
            fault_bits_hi: 0x0001,
            firmware: [0, 1, 0],
            stow_commanded: self.stow,
        }
    }
    fn command(&mut self, command: Command) -> Result<(), Exception> {
        if let Some(e) = self.refuse {
            return Err(e);
        }
        match command {
            Command::DeviceAddress(a) => self.address = a,
            Command::ManualElevation(el) => {
                let m = self.manual.get_or_insert(Angles {
                    elevation_cdeg: 0,
                    azimuth_cdeg: 0,
                });
                m.elevation_cdeg = el;
            }
            Command::ManualAzimuth(az) => {
                let m = self.manual.get_or_insert(Angles {
                    elevation_cdeg: 0,
                    azimuth_cdeg: 0,
                });
                m.azimuth_cdeg = az;
            }
            Command::Control(c) => self.control = c,
            Command::Stow(on) => self.stow = on,
            Command::ClearFaults => {}
        }
        self.commands.push(command);
        Ok(())
    }
}
