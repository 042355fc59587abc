//! Where the tracker stands: the site in force ([`resolve`]: GPS, the stored
//! site or a postal code) and the postal-code table (after Dahli & Cheggaga
//! 2023, Table 1), generated at build time from `data/postal_codes.csv`; see
//! [`postal`] for its format and flash cost.

pub mod filter;
pub mod key;
pub mod postal;
pub mod resolve;

pub use postal::{lookup, lookup_str, PostalEntry, PostalError};
pub use resolve::{
    follow_gps_site, resolve_site, site_from_config, site_from_fix, site_moved,
    wmm_declination_deg, SiteError, SiteOrigin,
};
