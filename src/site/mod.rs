//! Where the tracker stands: a site from a postal code (seed dahli-2023).
//!
//! The table is generated at build time from `data/postal_codes.csv`; see
//! [`postal`] for its format and flash cost.

pub mod key;
pub mod postal;

pub use postal::{lookup, lookup_str, PostalEntry, PostalError};
