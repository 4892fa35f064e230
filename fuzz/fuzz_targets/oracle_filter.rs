//! The oracle's floating-point filter against its unfiltered computation: the same exact
//! distance and closest points, bit for bit. Pairs are structured (or family) pairs rescaled by
//! `2^e` across the whole f64 exponent range (the extra `i16`), or, after [`RAW_TAG`], 18 raw
//! finite bit patterns (non-finite ones become 0).
//!
//! The body lives in `tridist_scenes::fuzzing::oracle_filter`, shared with the stable replay of
//! `fuzz/regressions/oracle_filter/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("oracle_filter", data));
