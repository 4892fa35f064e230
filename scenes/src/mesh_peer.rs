//! The C++ mesh peers, measured beside tridist on the same meshes and poses: FCL
//! (`BVHModel<OBBRSS>`), Coal (FCL's fork, `BVHModel<OBBRSS>`) and TrueForm (`tf::neighbor_search`
//! of two forms, in three tree configurations); FCL and Coal also with `BVHModel<RSS>`, judged
//! only (the conformance table). Each is a small shim in `scenes/peer/` with one
//! C ABI (new / free / distance / collide), compiled by `build.rs` when the library is installed:
//! FCL from Debian's `libfcl-dev`, Coal and TrueForm from their PyPI wheels
//! (`bash scenes/peer/install.sh`). [`MeshLib::available`] says which were built; without them
//! the project builds and tests as before.

use core::ffi::c_void;
use core::ptr::NonNull;

use tridist::Pose;

/// A mesh peer and its configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshLib {
    /// FCL 0.7 (Debian's `libfcl-dev`), `BVHModel<OBBRSS<double>>`.
    Fcl,
    /// Coal 3 (PyPI `coal`), `BVHModel<OBBRSS>`, double.
    Coal,
    /// FCL, `BVHModel<RSS<double>>` (judged in the conformance table, not timed).
    FclRss,
    /// Coal, `BVHModel<RSS>` (judged in the conformance table, not timed).
    CoalRss,
    /// FCL, `BVHModel<kIOS<double>>` (judged, not timed).
    FclKios,
    /// Coal, `BVHModel<kIOS>` (judged, not timed).
    CoalKios,
    /// TrueForm, oriented boxes in double (4 and 4; judged, not timed).
    TrueFormObbF64,
    /// TrueForm (PyPI `trueform`), axis-aligned boxes in float, 4 children per node and 4
    /// triangles per leaf: the configuration of TrueForm's own mesh distance benchmark.
    TrueFormAabbF32,
    /// TrueForm, axis-aligned boxes in double (4 and 4).
    TrueFormAabbF64,
    /// TrueForm, OBBRSS in double (4 and 4).
    TrueFormObbrssF64,
}

impl MeshLib {
    /// The mesh peers the report times, built or not.
    pub const ALL: [MeshLib; 5] = [
        MeshLib::Fcl,
        MeshLib::Coal,
        MeshLib::TrueFormAabbF32,
        MeshLib::TrueFormAabbF64,
        MeshLib::TrueFormObbrssF64,
    ];
    /// Every configuration the conformance table judges: [`MeshLib::ALL`] and the other
    /// bounding volumes FCL's and Coal's distance queries and TrueForm's trees offer.
    pub const JUDGED: [MeshLib; 10] = [
        MeshLib::Fcl,
        MeshLib::FclRss,
        MeshLib::FclKios,
        MeshLib::Coal,
        MeshLib::CoalRss,
        MeshLib::CoalKios,
        MeshLib::TrueFormAabbF32,
        MeshLib::TrueFormAabbF64,
        MeshLib::TrueFormObbrssF64,
        MeshLib::TrueFormObbF64,
    ];

    /// The name reports print.
    pub fn name(self) -> &'static str {
        match self {
            MeshLib::Fcl => "FCL (OBBRSS, double)",
            MeshLib::Coal => "Coal (OBBRSS, double)",
            MeshLib::FclRss => "FCL (RSS, double)",
            MeshLib::CoalRss => "Coal (RSS, double)",
            MeshLib::FclKios => "FCL (kIOS, double)",
            MeshLib::CoalKios => "Coal (kIOS, double)",
            MeshLib::TrueFormObbF64 => "TrueForm (OBB, double)",
            MeshLib::TrueFormAabbF32 => "TrueForm (AABB, float)",
            MeshLib::TrueFormAabbF64 => "TrueForm (AABB, double)",
            MeshLib::TrueFormObbrssF64 => "TrueForm (OBBRSS, double)",
        }
    }

    /// The name `tridist mesh-eval --peer` takes.
    pub fn cli_name(self) -> &'static str {
        match self {
            MeshLib::Fcl => "fcl",
            MeshLib::FclRss => "fcl-rss",
            MeshLib::FclKios => "fcl-kios",
            MeshLib::Coal => "coal",
            MeshLib::CoalRss => "coal-rss",
            MeshLib::CoalKios => "coal-kios",
            MeshLib::TrueFormAabbF32 => "trueform-aabb-f32",
            MeshLib::TrueFormAabbF64 => "trueform-aabb-f64",
            MeshLib::TrueFormObbrssF64 => "trueform-obbrss-f64",
            MeshLib::TrueFormObbF64 => "trueform-obb-f64",
        }
    }

    /// Whether this peer's shim was built (its library found at build time) and loads.
    pub fn available(self) -> bool {
        abi(self).is_some()
    }

    /// How to get this peer when it was not built.
    pub fn how_to_get(self) -> &'static str {
        match self {
            MeshLib::Fcl | MeshLib::FclRss | MeshLib::FclKios => {
                "apt-get install libfcl-dev libeigen3-dev, then rebuild"
            }
            _ => "bash scenes/peer/install.sh, then rebuild",
        }
    }

    /// The shim's configuration argument.
    fn config(self) -> u32 {
        match self {
            MeshLib::TrueFormAabbF32 => 0,
            MeshLib::TrueFormAabbF64 => 1,
            MeshLib::TrueFormObbrssF64 => 2,
            MeshLib::Fcl | MeshLib::Coal => 0,
            MeshLib::FclRss | MeshLib::CoalRss => 1,
            MeshLib::FclKios | MeshLib::CoalKios => 2,
            MeshLib::TrueFormObbF64 => 3,
        }
    }
}

/// A query of two placed models (model, rotation rows, translation, each side).
type Query<R> =
    unsafe extern "C" fn(*const c_void, *const f64, *const f64, *const c_void, *const f64, *const f64) -> R;

/// One shim's entry points.
struct Abi {
    new: unsafe extern "C" fn(usize, *const f64, usize, *const u32, u32) -> *mut c_void,
    free: unsafe extern "C" fn(*mut c_void),
    distance: Query<f64>,
    collide: Query<i32>,
}

/// Declares one shim's C functions and its [`Abi`] (present under its `cfg`).
macro_rules! shim {
    ($cfg:ident, $abi:ident, $new:ident, $free:ident, $distance:ident, $collide:ident) => {
        #[cfg($cfg)]
        extern "C" {
            fn $new(nv: usize, v: *const f64, nt: usize, t: *const u32, config: u32) -> *mut c_void;
            fn $free(m: *mut c_void);
            fn $distance(
                a: *const c_void,
                ra: *const f64,
                ta: *const f64,
                b: *const c_void,
                rb: *const f64,
                tb: *const f64,
            ) -> f64;
            fn $collide(
                a: *const c_void,
                ra: *const f64,
                ta: *const f64,
                b: *const c_void,
                rb: *const f64,
                tb: *const f64,
            ) -> i32;
        }
        #[cfg($cfg)]
        static $abi: Abi = Abi { new: $new, free: $free, distance: $distance, collide: $collide };
    };
}

shim!(
    tridist_fcl_mesh,
    FCL,
    tridist_fcl_mesh_new,
    tridist_fcl_mesh_free,
    tridist_fcl_mesh_distance,
    tridist_fcl_mesh_collide
);
shim!(
    tridist_trueform,
    TRUEFORM,
    tridist_trueform_mesh_new,
    tridist_trueform_mesh_free,
    tridist_trueform_mesh_distance,
    tridist_trueform_mesh_collide
);

#[cfg(tridist_trueform)]
extern "C" {
    fn tridist_trueform_threads(n: u32);
}

/// The shim of `lib`, when it was built (and, for Coal, loads).
fn abi(lib: MeshLib) -> Option<&'static Abi> {
    match lib {
        #[cfg(tridist_fcl_mesh)]
        MeshLib::Fcl | MeshLib::FclRss | MeshLib::FclKios => Some(&FCL),
        #[cfg(tridist_coal)]
        MeshLib::Coal | MeshLib::CoalRss | MeshLib::CoalKios => coal::abi(),
        #[cfg(tridist_trueform)]
        MeshLib::TrueFormAabbF32
        | MeshLib::TrueFormAabbF64
        | MeshLib::TrueFormObbrssF64
        | MeshLib::TrueFormObbF64 => Some(&TRUEFORM),
        #[allow(unreachable_patterns)]
        _ => None,
    }
}

/// The Coal shim, a shared object loaded at run time with its own symbols ahead of the
/// process's (`RTLD_DEEPBIND`): libcoal brings the wheel's octomap 1.10, libfcl the system's
/// octomap 1.9, and with both in the global scope the process crashes at exit (scenes/build.rs).
#[cfg(tridist_coal)]
mod coal {
    use core::ffi::{c_char, c_int, c_void};
    use std::sync::OnceLock;

    use super::Abi;

    #[link(name = "dl")]
    extern "C" {
        fn dlopen(filename: *const c_char, flags: c_int) -> *mut c_void;
        fn dlsym(handle: *mut c_void, symbol: *const c_char) -> *mut c_void;
    }
    // glibc's values
    const RTLD_NOW: c_int = 0x2;
    const RTLD_DEEPBIND: c_int = 0x8;

    /// The shim's entry points, loaded once; `None` when the shared object (built into
    /// `OUT_DIR`) is gone or lacks one.
    pub(super) fn abi() -> Option<&'static Abi> {
        static ABI: OnceLock<Option<Abi>> = OnceLock::new();
        ABI.get_or_init(load).as_ref()
    }

    fn load() -> Option<Abi> {
        let path = std::ffi::CString::new(env!("TRIDIST_COAL_SHIM")).ok()?;
        // SAFETY: a NUL-terminated path; the handle is never closed, so the symbols below stay
        // valid for the process's life.
        let h = unsafe { dlopen(path.as_ptr(), RTLD_NOW | RTLD_DEEPBIND) };
        if h.is_null() {
            return None;
        }
        // SAFETY: `h` is a live handle and the names are NUL-terminated.
        let sym = |name: &core::ffi::CStr| Some(unsafe { dlsym(h, name.as_ptr()) }).filter(|p| !p.is_null());
        let (new, free, distance, collide) = (
            sym(c"tridist_coal_mesh_new")?,
            sym(c"tridist_coal_mesh_free")?,
            sym(c"tridist_coal_mesh_distance")?,
            sym(c"tridist_coal_mesh_collide")?,
        );
        // SAFETY: each symbol is the shim's `extern "C"` function of exactly the signature of its
        // field (scenes/peer/coal_mesh.cpp, the mesh peers' common ABI).
        unsafe {
            Some(Abi {
                new: core::mem::transmute::<
                    *mut c_void,
                    unsafe extern "C" fn(usize, *const f64, usize, *const u32, u32) -> *mut c_void,
                >(new),
                free: core::mem::transmute::<*mut c_void, unsafe extern "C" fn(*mut c_void)>(free),
                distance: core::mem::transmute::<*mut c_void, super::Query<f64>>(distance),
                collide: core::mem::transmute::<*mut c_void, super::Query<i32>>(collide),
            })
        }
    }
}

/// TrueForm's threads for the queries that follow (TBB's global parallelism): at most `n`, or
/// TBB's default (every core) for 0. Does nothing when TrueForm was not built.
pub fn trueform_threads(n: u32) {
    #[cfg(tridist_trueform)]
    // SAFETY: the shim replaces a TBB global control object; no pointer crosses.
    unsafe {
        tridist_trueform_threads(n)
    }
    #[cfg(not(tridist_trueform))]
    let _ = n;
}

/// A peer's model of a mesh, its tree built. Queries take two models of the same [`MeshLib`].
pub struct MeshPeer {
    lib: MeshLib,
    abi: &'static Abi,
    ptr: NonNull<c_void>,
}

impl MeshPeer {
    /// `lib`'s model of the mesh, or `None` when that peer was not built, the mesh has no
    /// triangle (the peers build no tree for it; tridist accepts an empty mesh and its queries
    /// answer `None`), a coordinate is not finite, or an index names no vertex (both refused by
    /// `tridist::Mesh::new` too).
    pub fn new(lib: MeshLib, vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Option<MeshPeer> {
        let abi = abi(lib)?;
        if triangles.is_empty()
            || !vertices.iter().flatten().all(|x| x.is_finite())
            || triangles.iter().flatten().any(|&i| i as usize >= vertices.len())
        {
            return None;
        }
        // SAFETY: the shim reads 3 coordinates per vertex and 3 indices per triangle, within
        // the slices, and only indices checked above to name a vertex; it returns an owned
        // model (null for an unknown configuration) that `Drop` frees once.
        let ptr = unsafe {
            (abi.new)(
                vertices.len(),
                vertices.as_ptr().cast(),
                triangles.len(),
                triangles.as_ptr().cast(),
                lib.config(),
            )
        };
        NonNull::new(ptr).map(|ptr| MeshPeer { lib, abi, ptr })
    }

    /// The peer.
    pub fn lib(&self) -> MeshLib {
        self.lib
    }

    /// The distance (not squared) between this mesh and `other`, each in its pose, nearest
    /// points requested where the peer has the option (as tridist computes its closest points);
    /// NaN when `other` is another peer's model.
    pub fn distance(&self, pose: &Pose<f64>, other: &MeshPeer, other_pose: &Pose<f64>) -> f64 {
        self.placed(pose, other, other_pose, self.abi.distance).unwrap_or(f64::NAN)
    }

    /// Whether the peer finds the two placed meshes colliding (it stops at the first contact);
    /// `None` when `other` is another peer's model.
    pub fn collide(&self, pose: &Pose<f64>, other: &MeshPeer, other_pose: &Pose<f64>) -> Option<bool> {
        self.placed(pose, other, other_pose, self.abi.collide).map(|c| c != 0)
    }

    /// One of the shim's queries on this mesh and `other`, each in its pose.
    fn placed<R>(
        &self,
        pose: &Pose<f64>,
        other: &MeshPeer,
        other_pose: &Pose<f64>,
        query: Query<R>,
    ) -> Option<R> {
        if other.lib != self.lib {
            return None;
        }
        // SAFETY: both models are live (owned by `self` and `other`) and of the same shim and
        // configuration (checked above); the shim reads 9 rotation and 3 translation values
        // from each pose, which hold exactly that many.
        Some(unsafe {
            query(
                self.ptr.as_ptr(),
                pose.rotation.as_ptr().cast(),
                pose.translation.as_ptr(),
                other.ptr.as_ptr(),
                other_pose.rotation.as_ptr().cast(),
                other_pose.translation.as_ptr(),
            )
        })
    }
}

impl Drop for MeshPeer {
    fn drop(&mut self) {
        // SAFETY: `ptr` came from this shim's `new` and is freed only here, once.
        unsafe { (self.abi.free)(self.ptr.as_ptr()) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peers_refuse_what_tridist_refuses() {
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        for lib in MeshLib::JUDGED {
            assert!(MeshPeer::new(lib, &v, &[]).is_none(), "{lib:?}: no triangle");
            assert!(MeshPeer::new(lib, &v, &[[0, 1, 3]]).is_none(), "{lib:?}: index out of range");
            let nan = [[0.0, 0.0, 0.0], [1.0, f64::NAN, 0.0], [0.0, 1.0, 0.0]];
            assert!(MeshPeer::new(lib, &nan, &[[0, 1, 2]]).is_none(), "{lib:?}: NaN");
            assert_eq!(MeshPeer::new(lib, &v, &[[0, 1, 2]]).is_some(), lib.available(), "{lib:?}");
        }
    }

    /// Every built peer answers a known pair: two unit tetrahedra 2 apart along x, and
    /// touching; two peers' models are not mixed.
    #[test]
    fn built_peers_answer_a_known_pair() {
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let t = [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]];
        let id = Pose::identity();
        let (far, near) = (Pose::translation([3.0, 0.0, 0.0]), Pose::translation([0.5, 0.0, 0.0]));
        let built: Vec<MeshPeer> = MeshLib::JUDGED.iter().filter_map(|&l| MeshPeer::new(l, &v, &t)).collect();
        eprintln!("mesh peers built: {:?}", built.iter().map(MeshPeer::lib).collect::<Vec<_>>());
        for a in &built {
            let b = MeshPeer::new(a.lib(), &v, &t).expect("built");
            let d = a.distance(&id, &b, &far);
            let tol = if a.lib() == MeshLib::TrueFormAabbF32 { 1e-6 } else { 1e-12 };
            assert!((d - 2.0).abs() <= tol, "{:?}: {d}", a.lib());
            assert_eq!(a.collide(&id, &b, &far), Some(false), "{:?}", a.lib());
            assert_eq!(a.collide(&id, &b, &near), Some(true), "{:?}", a.lib());
            assert!(a.distance(&id, &b, &near) <= tol, "{:?}", a.lib());
        }
        if let [a, b, ..] = built.as_slice() {
            if a.lib() != b.lib() {
                assert!(a.distance(&id, b, &far).is_nan());
                assert_eq!(a.collide(&id, b, &far), None);
            }
        }
    }
}
