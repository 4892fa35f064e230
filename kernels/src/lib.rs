//! # tridist: fast, certified distance queries between triangles, segments and points
//!
//! Squared distances, closest points, intersection and within-margin tests for triangles,
//! segments and points, in `f32` and `f64`, on scalar, SSE4.1, AVX, AVX2+FMA and AVX-512 kernels. Every
//! answer carries a certified interval around the exact distance, and a pair is only done when
//! that interval is within the [`Tolerance`]: the rest is escalated (accurate stage, f64, the
//! exact oracle with the `exact` feature). Every kernel variant is also checked against an exact
//! rational oracle (`tridist-oracle`); the measured error of each variant on each input family
//! is published in `reports/ACCURACY.md` of the repository.
//!
//! * Single queries on plain arrays (or glam / mint vectors with those features):
//!   [`sqdist_triangle_triangle`], [`closest_points_triangle_triangle`],
//!   [`intersect_triangle_triangle`], [`within_margin_triangle_triangle`],
//!   [`sqdist_segment_segment`], [`sqdist_point_triangle`], ... and [`Engine::single`].
//! * Batches: an [`Engine`] (one instruction-set variant, [`Isa`]) runs a [`Query`] over pairs
//!   `a[i]` vs `b[i]` or one primitive against many ([`Prims`]), writing the [`Outputs`] asked
//!   for (squared distances only, closest points, intervals, verdicts) and returning the
//!   [`PathCounts`]. Ask only for what the scene needs: within-margin skips pairs whose boxes are
//!   already too far apart; intersection stops at a proven separating axis.
//! * [`Batch`]es are SoA columns, updated in place ([`Batch::set`], [`Batch::push`],
//!   [`Batch::transform`] by a [`Pose`]).
//!
//! ## Behaviour common to every query
//! * **Degenerate input**: a triangle whose vertices coincide or are collinear is treated as the
//!   point or segment it is; a zero-length segment as a point. Never NaN for finite input.
//! * **Touching / intersecting** triangles have squared distance exactly `0`.
//! * **Non-finite input** (any NaN or infinite coordinate): the squared distance, closest points
//!   and interval are NaN, intersection answers [`Intersection::Invalid`]. Other pairs of a
//!   batch are unaffected.
//! * **Overflow**: when the squared distance exceeds the precision's range it is `+inf` (the
//!   distance itself may still be finite; take `sqrt` in a wider type if needed). Closest points
//!   stay finite. Intermediate overflow cannot happen: each query scales its input by a power of
//!   two first, exactly.
//! * **Underflow**: a squared distance below the smallest subnormal rounds to `0` (for f32 this
//!   happens for distances below about 2^-75).
//!
//! ## Precision
//! Error is measured as `E = |sqrt(D^) - d*| / (u*S)` (u the unit roundoff, S the largest
//! absolute coordinate), defined in `docs/ACCURACY.md` of the repository. Certified answers are
//! within the tolerance (default `64 u S`); measured errors are far smaller.
//!
//! ## Sources
//! Segment-segment and point-triangle after Ericson, *Real-Time Collision Detection* (2005),
//! 5.1.9 and 5.1.5; triangle-triangle distance and overlap after Larsen, Gottschalk, Lin and
//! Manocha's PQP (TriDist, TriContact); their SoA SIMD form after Shellshear & Ytterlid, *Fast
//! Distance Queries for Triangles, Lines, and Points using SSE Instructions*, JCGT 3(4), 2014;
//! the penalty method and the brute-force baseline after Krestenitis & Koziara, *Calculating the
//! Minimum Distance Between Two Triangles on SIMD Hardware*.
//!
//! ## Example
//! ```
//! use tridist::Intersection;
//! let a = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
//! let b = [[0.0f32, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]];
//! assert_eq!(tridist::sqdist_triangle_triangle(&a, &b), 4.0);
//! assert_eq!(tridist::intersect_triangle_triangle(&a, &b), Intersection::Disjoint);
//! ```
//!
//! ## Soundness of the SIMD dispatch
//! The `#[target_feature]` kernels are reached only with a capability token that runtime
//! detection made, and every SIMD value carries its token, so no code path runs an instruction
//! the CPU lacks. The batch plumbing is private to the crate; it cannot be named from outside:
//! ```compile_fail,E0603
//! use tridist::drv::Job; // private module
//! ```
//! ```compile_fail,E0603
//! use tridist::arch::dispatch::run; // the dispatch is crate-private too
//! ```
//!
//! ## Features
//! * `rayon` (default): [`Engine::threads`] uses a persistent work-stealing pool.
//! * `exact`: the exact rational oracle (GMP, through `tridist-oracle`) as the last escalation
//!   step.
//! * `glam`, `mint`: their vector types are [`AsPoint`]s.
#![cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
// `unsafe` only where SIMD intrinsics need it: in `arch`, each block with a SAFETY comment.
#![deny(unsafe_code)]
#![warn(unreachable_pub)]

// Build-time rule: callers sort before callees under legacy mangling (`drv` < `algo` < `lanes`
// < the vector types' impls), so LLVM inlines top-down; `inline_order` below checks it.
mod algo;
#[allow(unsafe_code)]
mod arch;
mod batch;
mod drv;
mod engine;
mod error;
#[cfg(feature = "exact")]
mod exact;
mod isa;
mod lanes;
mod mesh;
mod pose;
mod query;
mod real;
mod single;
mod types;

pub use batch::{Batch, PointBatch, SegmentBatch, TriangleBatch};
pub use engine::{Engine, Outputs, PenaltyOptions, Prims, Tolerance, ISA_ENV};
pub use error::Error;
pub use isa::Isa;
pub use mesh::{Contact, Mesh, MeshDistance, MeshPoint, TreeShape};
pub use pose::{AsPoint, Pose};
pub use query::Query;
pub use real::{Precision, Real};
pub use single::*;
pub use types::{ClosestPoints, Intersection, Interval, PathCounts, Point, Proximity, Segment, Triangle};

/// The repository's README: `cargo test` compiles and runs every Rust block of it, so the
/// examples a newcomer pastes first are the ones that build.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
struct ReadmeDoctests;

/// Guards the module naming that makes LLVM inline callers before callees (see the comment on
/// the module list): under legacy mangling, `drv` < `algo` < `lanes` < the vector types' impls.
#[cfg(test)]
mod inline_order {
    /// A path segment as legacy mangling writes it: its length, then the segment.
    fn seg(s: &str) -> String {
        format!("{}{}", s.len(), s)
    }

    /// The crate-level module of a type of this crate.
    fn module_of<T: ?Sized>() -> String {
        seg(core::any::type_name::<T>().split("::").nth(1).expect("a crate-local path"))
    }

    #[test]
    fn callers_sort_before_callees_under_legacy_mangling() {
        let drv = module_of::<crate::drv::Job<'static, f32>>();
        let algo = module_of::<crate::algo::Params<f32>>();
        let lanes = module_of::<crate::lanes::V3<f32>>();
        assert!(drv < algo && algo < lanes, "module order {drv}, {algo}, {lanes}");
        #[cfg(target_arch = "x86_64")]
        {
            use crate::arch::x86_simd::*;
            use core::any::type_name;
            // after every `_ZN7tridist...` name: a length of 80 to 99 ("8..." or "9..." > "7t")
            let after = seg("tridist");
            for (ty, tr) in [
                (type_name::<F32x4<Sse41>>(), "Lanes"),
                (type_name::<F64x2<Sse41>>(), "Lanes"),
                (type_name::<F32x8<Avx2Fma>>(), "Lanes"),
                (type_name::<F64x4<Avx2Fma>>(), "Lanes"),
                (type_name::<M32x4<Sse41>>(), "Mask"),
                (type_name::<M64x2<Sse41>>(), "Mask"),
                (type_name::<M32x8<Avx2Fma>>(), "Mask"),
                (type_name::<M64x4<Avx2Fma>>(), "Mask"),
                (type_name::<F32x16<Avx512>>(), "Lanes"),
                (type_name::<F64x8<Avx512>>(), "Lanes"),
                (type_name::<M32x16<Avx512>>(), "Mask"),
                (type_name::<M64x8<Avx512>>(), "Mask"),
            ] {
                let path = ty.split('<').next().expect("a type path").replace("::", "..");
                let imp = format!("_$LT${path}$LT$K$GT$$u20$as$u20$tridist..lanes..{tr}$GT$");
                assert!(seg(&imp) > after, "the impl {imp} sorts before the crate's own functions");
            }
        }
    }
}
