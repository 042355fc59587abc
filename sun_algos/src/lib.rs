//! Solar position algorithms for solar trackers, `no_std`, in `f32` and `f64`.
#![no_std]
