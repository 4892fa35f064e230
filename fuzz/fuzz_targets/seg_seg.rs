//! Segment-segment distance against the oracle.
//!
//! The body lives in `tridist_scenes::fuzzing::seg_seg`, shared with the stable replay of
//! `fuzz/regressions/seg_seg/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("seg_seg", data));
