//! The untrusted-text readers (OFF meshes, case lines): never panic; what parses is valid (face
//! indices in range; case lines round-trip).
//!
//! The body lives in `tridist_scenes::fuzzing::parsers`, shared with the stable replay of
//! `fuzz/regressions/parsers/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("parsers", data));
