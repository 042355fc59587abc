//! Number formatting for the firmware images without `core::fmt`: the
//! library's [`suntracker::log::Sink`], shared by every image.
pub use suntracker::log::Sink;
