//! The query registry: the one list of queries. Each line names a query, its kernel (the
//! algorithm file's type implementing `algo::Kernel`) and a one-line description. From it come
//! the public [`Query`] enum and its metadata (here), the algorithm files' module declarations
//! and [`Query::arity`] (`crate::algo`), and every instruction set's entry points
//! (`crate::arch`). This module names no other of the crate: the kernel paths in the list are
//! tokens for the macros that expand it elsewhere. The harness, the benches and the CLI enumerate
//! [`Query::ALL`]; adding a query is its algorithm file plus one line here (ARCHITECTURE.md).

/// Calls `$m!` with the registry (optionally preceded by `[extra arguments]`): one
/// `Variant, "name", module::KernelType, "description";` per query, where `module` is the
/// algorithm file `kernels/src/algo/module.rs` (declared from this list by `algo/mod.rs`) and
/// `KernelType` its type implementing `algo::Kernel`.
macro_rules! for_each_query {
    ($m:ident $(, $extra:tt)*) => {
        $m! { [$($extra),*]
            SegSeg, "seg_seg", seg_seg::SegSeg,
                "segment-segment squared distance and closest points (Ericson 5.1.9)";
            PointTri, "point_tri", point_tri::PointTri,
                "point-triangle squared distance and closest point (Ericson 5.1.5)";
            TriTri, "tri_tri", pqp::TriTri,
                "triangle-triangle squared distance and closest points: fast stage, then PQP's TriDist";
            TriTriBrute, "tri_tri_brute", brute::Brute,
                "triangle-triangle by brute force: 15 feature pairs + separating axes";
            Intersect, "intersect", sat::Intersect,
                "triangle-triangle intersection: certified separating axes or piercing witness";
            Within, "within", within::Within,
                "triangle-triangle within-margin: box test, then the distance when within the margin";
            Penalty, "penalty", penalty::Penalty,
                "triangle-triangle by Krestenitis & Koziara's penalty method (approximate)";
        }
    };
}
pub(crate) use for_each_query;

macro_rules! define_query {
    ([] $($v:ident, $name:literal, $m:ident :: $k:ident, $about:literal;)*) => {
        /// Every query the crate answers (the registry). Batch queries run through
        /// [`crate::Engine::run`] by this name as well as through their typed methods.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[non_exhaustive]
        pub enum Query {
            $(#[doc = $about] $v,)*
        }

        impl Query {
            /// Every query, in registry order.
            pub const ALL: &'static [Query] = &[$(Query::$v),*];

            /// Short name (CLI, reports): `seg_seg`, `point_tri`, `tri_tri`, ...
            pub fn name(self) -> &'static str {
                match self {
                    $(Query::$v => $name,)*
                }
            }

            /// Parses [`Query::name`].
            pub fn parse(s: &str) -> Option<Query> {
                Query::ALL.iter().copied().find(|q| q.name() == s)
            }

            /// One line on what the query computes.
            pub fn about(self) -> &'static str {
                match self {
                    $(Query::$v => $about,)*
                }
            }
        }
    };
}
for_each_query!(define_query);

impl Query {
    /// Is the answer an intersection verdict ([`crate::Intersection`]) rather than a distance?
    pub fn is_verdict(self) -> bool {
        self == Query::Intersect
    }

    /// Does the query take a margin ([`crate::Engine::margin`])?
    pub fn has_margin(self) -> bool {
        self == Query::Within
    }

    /// Is the answer an approximation (never escalated, its interval may be wide)?
    pub fn is_approximate(self) -> bool {
        self == Query::Penalty
    }
}

impl core::fmt::Display for Query {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}
