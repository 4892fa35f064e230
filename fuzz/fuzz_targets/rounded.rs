//! The correctly rounded mode on every variant: a certified square is `RN(D*)` and a certified
//! distance `RN(sqrt(D*))` bit for bit, intervals contain the exact distance, the single query
//! gives the batch's bits, and uncertified pairs are the ones counted undecided.
//!
//! The body lives in `tridist_scenes::fuzzing::rounded`, shared with the stable replay of
//! `fuzz/regressions/rounded/` by `cargo test`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| tridist_scenes::fuzzing::fuzz("rounded", data));
