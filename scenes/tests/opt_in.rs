//! The build with this crate's `all-variants` feature (CI's step for the opt-in variants, the
//! fuzz targets, the reports' command) compiles both opt-in variants: there
//! `TRIDIST_REQUIRE_ISA=detected` requires them wherever the CPU runs them, and this test
//! makes sure the feature did turn them on. Without the feature it checks they are left out,
//! as the README's test command's build time assumes (docs/notes/build-time.md).

use tridist_scenes::eval::OPT_IN;

#[test]
fn the_opt_in_variants_follow_the_feature() {
    for isa in OPT_IN {
        assert_eq!(isa.is_compiled(), cfg!(feature = "all-variants"), "{isa}");
    }
}
