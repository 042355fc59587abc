//! Time: which UTC is in force (GPS or the RTC, [`keeper`]), the window of
//! plausible dates ([`window`]), and the conversions between the drivers'
//! calendar dates and `sun_algos`' instants.

mod convert;
pub mod keeper;
pub mod window;

pub use convert::{datetime_from_utc, utc_from_datetime, TimeConversionError};
pub use keeper::{gps_time, GpsTime, TimeConfig, TimeKeeper, TimeOrigin, TimeStatus};
pub use window::DateWindow;
