//! Arbitrary f32/f64 bit patterns (NaN, inf, subnormals, huge values) through the batch API of
//! every variant: no panic, no UB (run it with the address sanitizer), and the documented
//! outcome: NaN (None for intersection) exactly for pairs with a non-finite coordinate, otherwise
//! a non-negative squared distance or +inf (overflow) with finite closest points.
//!
//! The body lives in `tridist_scenes::fuzzing::raw_bits`, shared with the stable replay of
//! `fuzz/regressions/raw_bits/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("raw_bits", data));
