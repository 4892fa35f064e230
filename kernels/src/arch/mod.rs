//! The ISA layer: vector types implementing [`crate::lanes::Lanes`] and the
//! `#[target_feature]` entry points that instantiate the generic driver with them.
//! Nothing here knows any geometry.

#[cfg(target_arch = "x86_64")]
pub(crate) mod x86_simd;
