//! The peers, measured by the benches and the report on the same inputs as tridist and judged
//! against the same oracle:
//!
//! * parry3d (f32) and parry3d-f64 `query::distance` on two `Triangle` shapes at identity poses
//!   (GJK on support maps): what a Rust user would pick;
//! * FCL's `TriangleDistance` (PQP's TriDist as FCL 0.7 ships it, header-only, compiled with
//!   `-O3 -march=native` by `build.rs`), float and double: the fastest peer a C++ user would
//!   pick. Present when its headers were found at build time (`cfg(tridist_fcl)`; Debian:
//!   `apt-get install libfcl-dev libeigen3-dev`); [`Lib::available`] says.
//!
//! Judged only (the conformance table, `tridist peers`), through their mesh query on two
//! one-triangle meshes, since neither offers a triangle-triangle distance of its own in its
//! public C++ API but computes one per pair of leaves: Coal (`BVHModel<OBBRSS>`, double only)
//! and TrueForm (`tf::neighbor_search`, float and double). Present when built
//! ([`crate::mesh_peer`]).

use std::time::Duration;

use tridist::{Engine, Intersection, Interval, Isa, PathCounts, Query, Triangle};

use crate::eval::{summarise, truth, Output, Stats};
use crate::families::{generate, Case};
use crate::float::Float;
use crate::mesh_peer::{MeshLib, MeshPeer};
use crate::Family;

/// A precision parry has a crate for.
pub trait Peer: Float {
    /// parry's triangle shape in this precision.
    type Shape;
    /// The triangle as a parry shape.
    fn shape(t: &Triangle<Self>) -> Self::Shape;
    /// parry's distance (not squared) between two triangles.
    fn distance(a: &Self::Shape, b: &Self::Shape) -> Self;
    /// FCL's distances of flat pairs (NaN when FCL was not built).
    fn fcl(a: &[Self], b: &[Self], out: &mut [Self]);
    /// parry's `TriMesh` in this precision.
    type Mesh;
    /// The mesh as a parry `TriMesh` (its BVH built), or `None` when parry refuses it.
    fn trimesh(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Option<Self::Mesh>;
    /// parry's distance (not squared) between two meshes, each placed by
    /// `(translation, axis * angle)` (NaN when unsupported).
    fn mesh_distance(a: &Self::Mesh, pa: &PeerPose, b: &Self::Mesh, pb: &PeerPose) -> f64;
    /// parry's `intersection_test` of two placed meshes (`None` when unsupported).
    fn mesh_intersects(a: &Self::Mesh, pa: &PeerPose, b: &Self::Mesh, pb: &PeerPose) -> Option<bool>;
}

/// A placement for parry: translation and scaled rotation axis (axis times angle in radians).
pub type PeerPose = ([f64; 3], [f64; 3]);

/// Implements [`Peer`] for one parry crate (the two differ only in their scalar type).
macro_rules! peer {
    ($t:ty, $parry:ident) => {
        impl Peer for $t {
            type Shape = $parry::shape::Triangle;
            fn shape(t: &Triangle<$t>) -> Self::Shape {
                let v = |p: [$t; 3]| $parry::math::Vector::new(p[0], p[1], p[2]);
                $parry::shape::Triangle::new(v(t[0]), v(t[1]), v(t[2]))
            }
            fn distance(a: &Self::Shape, b: &Self::Shape) -> $t {
                let id = $parry::math::Pose::identity();
                // Triangle-triangle is always supported; NaN marks the impossible error.
                $parry::query::distance(&id, a, &id, b).map_or(<$t>::NAN, |d| d.distance)
            }
            fn fcl(a: &[$t], b: &[$t], out: &mut [$t]) {
                <$t as FclCall>::fcl_call(a, b, out)
            }
            type Mesh = $parry::shape::TriMesh;
            fn trimesh(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Option<Self::Mesh> {
                let v = vertices
                    .iter()
                    .map(|p| $parry::math::Vector::new(p[0] as $t, p[1] as $t, p[2] as $t))
                    .collect();
                $parry::shape::TriMesh::new(v, triangles.to_vec()).ok()
            }
            fn mesh_distance(a: &Self::Mesh, pa: &PeerPose, b: &Self::Mesh, pb: &PeerPose) -> f64 {
                let pose_of = |p: &PeerPose| {
                    let v = |x: [f64; 3]| $parry::math::Vector::new(x[0] as $t, x[1] as $t, x[2] as $t);
                    $parry::math::Pose::new(v(p.0), v(p.1))
                };
                let (x, y) = (pose_of(pa), pose_of(pb));
                $parry::query::distance(&x, a, &y, b).map_or(f64::NAN, |d| f64::from(d.distance))
            }
            fn mesh_intersects(a: &Self::Mesh, pa: &PeerPose, b: &Self::Mesh, pb: &PeerPose) -> Option<bool> {
                let pose_of = |p: &PeerPose| {
                    let v = |x: [f64; 3]| $parry::math::Vector::new(x[0] as $t, x[1] as $t, x[2] as $t);
                    $parry::math::Pose::new(v(p.0), v(p.1))
                };
                let (x, y) = (pose_of(pa), pose_of(pb));
                $parry::query::intersection_test(&x, a, &y, b).ok().map(|r| r.intersecting)
            }
        }
    };
}
peer!(f32, parry3d);
peer!(f64, parry3d_f64);

/// A peer library.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lib {
    /// parry3d / parry3d-f64.
    Parry,
    /// FCL (C++), when built.
    Fcl,
    /// Coal (C++, double only), when built: judged, not timed.
    Coal,
    /// TrueForm (C++, float and double), when built: judged, not timed.
    TrueForm,
}

impl Lib {
    /// The peers the reports time and judge, available or not.
    pub const ALL: [Lib; 2] = [Lib::Parry, Lib::Fcl];
    /// Every peer the conformance table judges, available or not.
    pub const JUDGED: [Lib; 4] = [Lib::Parry, Lib::Fcl, Lib::Coal, Lib::TrueForm];
    /// Name in tables and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Lib::Parry => "parry3d",
            Lib::Fcl => "fcl",
            Lib::Coal => "coal",
            Lib::TrueForm => "trueform",
        }
    }
    /// Was it built into this binary?
    pub fn available(self) -> bool {
        match self {
            Lib::Parry => true,
            Lib::Fcl => cfg!(tridist_fcl),
            Lib::Coal => MeshLib::Coal.available(),
            Lib::TrueForm => MeshLib::TrueFormAabbF64.available(),
        }
    }
    /// Whether the library computes in `T` (Coal is built for double only).
    pub fn offers<T: Float>(self) -> bool {
        self != Lib::Coal || T::PRECISION == tridist::Precision::F64
    }
    /// The version built in ("unknown" when not built or not found).
    pub fn version(self) -> &'static str {
        let v = match self {
            // the workspace's Cargo.toml pins it
            Lib::Parry => Some("0.31"),
            Lib::Fcl => option_env!("TRIDIST_FCL_VERSION"),
            Lib::Coal => option_env!("TRIDIST_COAL_VERSION"),
            Lib::TrueForm => option_env!("TRIDIST_TRUEFORM_VERSION"),
        };
        v.unwrap_or("unknown")
    }
    /// The public API judged, in `T`'s words (float or double for the C++ peers).
    pub fn configuration<T: Float>(self) -> &'static str {
        let single = T::PRECISION == tridist::Precision::F32;
        match (self, single) {
            (Lib::Parry, true) => "parry3d `query::distance`, two `Triangle` shapes (GJK)",
            (Lib::Parry, false) => "parry3d-f64 `query::distance`, two `Triangle` shapes (GJK)",
            (Lib::Fcl, true) => "`TriangleDistance<float>` (PQP's TriDist, header-only)",
            (Lib::Fcl, false) => "`TriangleDistance<double>` (PQP's TriDist, header-only)",
            (Lib::Coal, _) => "`coal::distance` of two one-triangle `BVHModel<OBBRSS>`",
            (Lib::TrueForm, true) => "`tf::neighbor_search` of two one-triangle forms, float AABB trees",
            (Lib::TrueForm, false) => "`tf::neighbor_search` of two one-triangle forms, double AABB trees",
        }
    }
    /// Why it is missing, for reports.
    pub fn missing_reason(self) -> &'static str {
        match self {
            Lib::Parry => "",
            Lib::Fcl => "FCL headers were not found at build time (apt-get install libfcl-dev libeigen3-dev, then rebuild)",
            Lib::Coal | Lib::TrueForm => "its wheel was not found at build time (bash scenes/peer/install.sh, then rebuild)",
        }
    }
    /// The mesh peer answering for this library in `T` (Coal and TrueForm).
    fn mesh_lib<T: Float>(self) -> Option<MeshLib> {
        match self {
            Lib::Coal => Some(MeshLib::Coal),
            Lib::TrueForm if T::PRECISION == tridist::Precision::F32 => Some(MeshLib::TrueFormAabbF32),
            Lib::TrueForm => Some(MeshLib::TrueFormAabbF64),
            Lib::Parry | Lib::Fcl => None,
        }
    }
}

/// Triangle pairs prepared once for a peer (parry shapes, or FCL's flat arrays).
pub struct Shapes<T: Peer> {
    lib: Lib,
    a: Vec<T::Shape>,
    b: Vec<T::Shape>,
    fa: Vec<T>,
    fb: Vec<T>,
}

impl<T: Peer> Shapes<T> {
    /// Converts the pairs for parry.
    pub fn new(a: &[Triangle<T>], b: &[Triangle<T>]) -> Self {
        Shapes::for_lib(Lib::Parry, a, b)
    }

    /// Converts the pairs for `lib`.
    pub fn for_lib(lib: Lib, a: &[Triangle<T>], b: &[Triangle<T>]) -> Self {
        let n = a.len().min(b.len());
        match lib {
            Lib::Parry => Shapes {
                lib,
                a: a[..n].iter().map(T::shape).collect(),
                b: b[..n].iter().map(T::shape).collect(),
                fa: vec![],
                fb: vec![],
            },
            Lib::Fcl | Lib::Coal | Lib::TrueForm => Shapes {
                lib,
                a: vec![],
                b: vec![],
                fa: a[..n].as_flattened().as_flattened().to_vec(),
                fb: b[..n].as_flattened().as_flattened().to_vec(),
            },
        }
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        match self.lib {
            Lib::Parry => self.a.len(),
            Lib::Fcl | Lib::Coal | Lib::TrueForm => self.fa.len() / 9,
        }
    }

    /// True when there are no pairs.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The peer's distances (not squared) into `out` (one per pair); NaN everywhere for a peer
    /// that was not built or does not compute in `T`, and for a pair it refuses (Coal and
    /// TrueForm build no model of a triangle with a non-finite coordinate).
    pub fn distances(&self, out: &mut [T]) {
        match self.lib {
            Lib::Parry => {
                for ((o, a), b) in out.iter_mut().zip(&self.a).zip(&self.b) {
                    *o = T::distance(a, b);
                }
            }
            Lib::Fcl => T::fcl(&self.fa, &self.fb, out),
            Lib::Coal | Lib::TrueForm => {
                let mesh = self.lib.mesh_lib::<T>().filter(|_| self.lib.offers::<T>());
                let tri = |f: &[T]| -> Vec<[f64; 3]> {
                    f.chunks_exact(3).map(|p| [p[0].to_f64(), p[1].to_f64(), p[2].to_f64()]).collect()
                };
                let id = tridist::Pose::identity();
                let pairs = self.fa.chunks_exact(9).zip(self.fb.chunks_exact(9));
                for (o, (a, b)) in out.iter_mut().zip(pairs) {
                    let model = |t: &[T]| mesh.and_then(|m| MeshPeer::new(m, &tri(t), &[[0, 1, 2]]));
                    *o = match (model(a), model(b)) {
                        (Some(ma), Some(mb)) => T::from_f64(ma.distance(&id, &mb, &id)),
                        _ => T::NAN,
                    };
                }
            }
        }
    }
}

#[cfg(tridist_fcl)]
mod fcl_ffi {
    extern "C" {
        pub fn tridist_fcl_tri_dist_f64(
            n: usize,
            a: *const f64,
            b: *const f64,
            d: *mut f64,
            p: *mut f64,
            q: *mut f64,
        );
        pub fn tridist_fcl_tri_dist_f32(
            n: usize,
            a: *const f32,
            b: *const f32,
            d: *mut f32,
            p: *mut f32,
            q: *mut f32,
        );
    }
}

/// FCL's distances of flat pairs (9 coordinates per triangle) in one precision.
trait FclCall: Sized {
    fn fcl_call(a: &[Self], b: &[Self], out: &mut [Self]);
}

macro_rules! fcl_call {
    ($t:ty, $f:ident) => {
        impl FclCall for $t {
            #[cfg(tridist_fcl)]
            fn fcl_call(a: &[$t], b: &[$t], out: &mut [$t]) {
                let n = (a.len() / 9).min(b.len() / 9).min(out.len());
                // SAFETY: the shim reads 9 values per pair from `a` and `b` and writes one to
                // `out` for n pairs, all within the slices (n is bounded by each length); the
                // point outputs are null, which the shim checks. (FFI to the measured C++ peer:
                // the only `unsafe` outside the SIMD layer.)
                unsafe {
                    fcl_ffi::$f(
                        n,
                        a.as_ptr(),
                        b.as_ptr(),
                        out.as_mut_ptr(),
                        core::ptr::null_mut(),
                        core::ptr::null_mut(),
                    )
                }
            }
            #[cfg(not(tridist_fcl))]
            fn fcl_call(_: &[$t], _: &[$t], out: &mut [$t]) {
                out.fill(<$t>::NAN);
            }
        }
    };
}
fcl_call!(f32, tridist_fcl_tri_dist_f32);
fcl_call!(f64, tridist_fcl_tri_dist_f64);

/// Checks that parry answers the same question as tridist on these pairs (a harness error, a
/// wrong pose or an unsquared distance would disagree on most pairs): parry's distance against
/// tridist's scalar one within `1e-3 S` (S: the pair's largest coordinate magnitude) on at least
/// 90% of the pairs. Returns the largest `|d - d'| / S` and the number of pairs beyond `1e-3`.
///
/// # Errors
/// A message when the check fails.
pub fn agreement<T: Peer>(lib: Lib, a: &[Triangle<T>], b: &[Triangle<T>]) -> Result<(f64, usize), String> {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let (mut ours, mut theirs) = (vec![T::ZERO; n], vec![T::ZERO; n]);
    let e = Engine::new(Isa::Scalar).map_err(|e| e.to_string())?;
    e.sqdist_triangle_triangle(a, b, &mut ours).map_err(|e| e.to_string())?;
    Shapes::for_lib(lib, a, b).distances(&mut theirs);
    compare(a, b, &ours, &theirs)
}

/// [`agreement`]'s test on given answers: `ours` squared, `theirs` not.
fn compare<T: Float>(
    a: &[Triangle<T>],
    b: &[Triangle<T>],
    ours: &[T],
    theirs: &[T],
) -> Result<(f64, usize), String> {
    let n = ours.len();
    let (mut worst, mut beyond) = (0.0f64, 0usize);
    for i in 0..n {
        let s = a[i].iter().chain(b[i].iter()).flatten().fold(0.0f64, |m, x| m.max(x.to_f64().abs()));
        let diff = (theirs[i].to_f64() - ours[i].to_f64().sqrt()).abs() / s.max(f64::MIN_POSITIVE);
        let diff = if diff.is_nan() { f64::INFINITY } else { diff };
        worst = worst.max(diff);
        beyond += usize::from(diff > 1e-3);
    }
    if beyond * 10 > n {
        return Err(format!("parry3d ({}) disagrees with tridist on {beyond} of {n} pairs", T::NAME));
    }
    Ok((worst, beyond))
}

/// Median seconds of one pass of parry's distance over the pairs (see
/// [`crate::workload::median_time`]).
pub fn time_pass<T: Peer>(shapes: &Shapes<T>, budget: Duration) -> f64 {
    let mut out = vec![T::ZERO; shapes.len()];
    crate::workload::median_time(|| shapes.distances(&mut out), budget)
}

/// A peer's triangle distance judged against the oracle on `n` cases of `family`, with the
/// metrics of ACCURACY.md. Distance only: the closest-point error of the result is meaningless
/// (no points are returned) and left at 0.
pub fn judge<T: Peer>(lib: Lib, family: Family, seed: u64, n: usize) -> Stats {
    judge_cases(lib, &generate::<T>(family, seed, n))
}

/// [`judge`] on given cases (their triangle-triangle distance).
pub fn judge_cases<T: Peer>(lib: Lib, cases: &[Case<T>]) -> Stats {
    let allow = crate::bounds::VERDICT_ALLOW;
    let out = answers(lib, cases);
    let mut st = summarise(Query::TriTri, cases, &truth(Query::TriTri, cases), &out, allow, None).0;
    st.max_point_error = 0.0;
    st
}

/// A peer's triangle-triangle distances of `cases` as the judge reads them: squared in `T`
/// (at most half an ulp of D more, far below the errors measured), no closest points, no
/// certificate (the interval that contains everything).
pub fn answers<T: Peer>(lib: Lib, cases: &[Case<T>]) -> Output<T> {
    let a: Vec<_> = cases.iter().map(|c| c.a).collect();
    let b: Vec<_> = cases.iter().map(|c| c.b).collect();
    let mut d = vec![T::ZERO; cases.len()];
    Shapes::for_lib(lib, &a, &b).distances(&mut d);
    let n = cases.len();
    Output {
        d: d.iter().map(|&x| x * x).collect(),
        dist: d,
        p: vec![[T::ZERO; 3]; n],
        q: vec![[T::ZERO; 3]; n],
        iv: vec![Interval { lo: T::ZERO, hi: T::INFINITY }; n],
        verdict: vec![Intersection::Invalid; n],
        certified: vec![false; n],
        counts: PathCounts::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parry_answers_the_same_question() {
        let a = [[[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
        let b = [[[0.0f64, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]]];
        let mut d = [0.0];
        Shapes::new(&a, &b).distances(&mut d);
        assert_eq!(d[0], 2.0);
        let cases: Vec<Case<f64>> = generate(Family::Random, 1, 50);
        let ca: Vec<_> = cases.iter().map(|c| c.a).collect();
        let cb: Vec<_> = cases.iter().map(|c| c.b).collect();
        let (worst, beyond) = agreement(Lib::Parry, &ca, &cb).unwrap();
        assert!(worst < 1e-9 && beyond == 0, "{worst} {beyond}");
        // a harness that compared squared with unsquared distances would be caught
        let mut ours = vec![0.0; 50];
        Engine::new(Isa::Scalar).unwrap().sqdist_triangle_triangle(&ca, &cb, &mut ours).unwrap();
        let disjoint = ours.iter().filter(|&&x| x > 1e-2).count();
        assert!(disjoint > 10);
        assert!(compare(&ca, &cb, &ours, &ours).is_err());
    }

    #[test]
    fn judged_against_the_oracle() {
        let st = judge::<f64>(Lib::Parry, Family::Random, 7, 40);
        assert_eq!(st.n, 40);
        assert!(st.max_excess.is_finite() && st.nonfinite == 0);
    }

    /// Coal and TrueForm, through one-triangle meshes, answer the question tridist answers
    /// (when built): the same distances on random pairs, and no answer for bad input.
    #[test]
    fn mesh_peers_answer_triangle_pairs_when_built() {
        for lib in [Lib::Coal, Lib::TrueForm] {
            if !lib.available() {
                eprintln!("{}: {}", lib.name(), lib.missing_reason());
                continue;
            }
            let cases: Vec<Case<f64>> = generate(Family::Random, 3, 100);
            let ca: Vec<_> = cases.iter().map(|c| c.a).collect();
            let cb: Vec<_> = cases.iter().map(|c| c.b).collect();
            let (worst, beyond) = agreement(lib, &ca, &cb).unwrap();
            assert!(beyond == 0 && worst < 1e-9, "{}: {worst} {beyond}", lib.name());
            let a = [[[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
            let b = [[[0.0f32, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]]];
            let mut d = [0.0f32];
            Shapes::for_lib(lib, &a, &b).distances(&mut d);
            assert_eq!(d[0] == 2.0, lib.offers::<f32>(), "{}: {}", lib.name(), d[0]);
            assert!(d[0].is_nan() || lib.offers::<f32>());
            let nan = [[[0.0f64, f64::NAN, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
            let mut d = [0.0f64];
            Shapes::for_lib(lib, &nan, &[[[0.0f64, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]]])
                .distances(&mut d);
            assert!(d[0].is_nan());
        }
    }

    #[test]
    fn fcl_answers_the_same_question_when_built() {
        if !Lib::Fcl.available() {
            eprintln!("{}", Lib::Fcl.missing_reason());
            return;
        }
        let cases: Vec<Case<f64>> = generate(Family::Random, 3, 200);
        let ca: Vec<_> = cases.iter().map(|c| c.a).collect();
        let cb: Vec<_> = cases.iter().map(|c| c.b).collect();
        let (worst, beyond) = agreement(Lib::Fcl, &ca, &cb).unwrap();
        assert!(beyond == 0 && worst < 1e-9, "{worst} {beyond}");
        let a = [[[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
        let b = [[[0.0f32, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]]];
        let mut d = [0.0f32];
        Shapes::for_lib(Lib::Fcl, &a, &b).distances(&mut d);
        assert_eq!(d[0], 2.0);
    }
}
