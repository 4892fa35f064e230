//! Differential fuzzing of the point_tri query: every variant and precision against the oracle.
#![no_main]
use libfuzzer_sys::fuzz_target;
use tridist_fuzz::{differential, PairInput};
use tridist_scenes::eval::Query;

fuzz_target!(|input: PairInput| {
    differential(&input, Query::PointTri);
});
