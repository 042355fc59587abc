//! Time: which UTC is in force (GPS or the RTC, [`keeper`]), the window of
//! plausible dates ([`window`]), the conversions between the drivers'
//! calendar dates and `sun_algos`' instants, and the 32-bit monotonic clock
//! every duration is measured on ([`monotonic`]).

mod convert;
pub mod keeper;
pub mod monotonic;
pub mod window;

pub use convert::{datetime_from_utc, utc_from_datetime, TimeConversionError};
pub use keeper::{
    gps_time, GpsTime, TimeConfig, TimeKeeper, TimeOrigin, TimeStatus, UNSTABLE_DISAGREEMENTS,
};
pub use window::DateWindow;
