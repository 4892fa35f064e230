// tridist's shim over FCL's mesh-vs-mesh distance and collision (BVHModel<OBBRSS<double>>, the
// bounding volume FCL recommends for distance), for measuring FCL as the mesh peer on the same
// meshes and poses in the same run. Built by scenes/build.rs only when FCL's headers and its
// shared library are installed (Debian: libfcl-dev, libeigen3-dev); links libfcl. FCL's library
// instantiates double only, so this peer is double only.
#include <cstddef>
#include <cstdint>
#include <vector>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

namespace {
using Model = fcl::BVHModel<fcl::OBBRSSd>;

// A pose as tridist writes it: rotation rows r[0..9], translation t[0..3].
fcl::Transform3d pose(const double* r, const double* t) {
  fcl::Transform3d p = fcl::Transform3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = r[3 * i + j];
    p.translation()(i) = t[i];
  }
  return p;
}
}  // namespace

// The model of nv vertices (3 coordinates each) and nt triangles (3 indices each), its tree
// built; free with tridist_fcl_mesh_free. config: unused (one configuration; the mesh peers'
// common C ABI, scenes/src/mesh_peer.rs).
extern "C" void* tridist_fcl_mesh_new(std::size_t nv, const double* v, std::size_t nt, const std::uint32_t* t,
                                      std::uint32_t) {
  std::vector<fcl::Vector3d> pts(nv);
  for (std::size_t i = 0; i < nv; ++i) pts[i] = fcl::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  std::vector<fcl::Triangle> tris(nt);
  for (std::size_t i = 0; i < nt; ++i) tris[i] = fcl::Triangle(t[3 * i], t[3 * i + 1], t[3 * i + 2]);
  Model* m = new Model();
  m->beginModel();
  m->addSubModel(pts, tris);
  m->endModel();
  return m;
}

extern "C" void tridist_fcl_mesh_free(void* m) { delete static_cast<Model*>(m); }

// The distance (not squared) between two placed models, nearest points computed (as tridist's
// mesh distance computes its closest points).
extern "C" double tridist_fcl_mesh_distance(const void* a, const double* ra, const double* ta, const void* b,
                                            const double* rb, const double* tb) {
  fcl::DistanceRequestd req;
  req.enable_nearest_points = true;
  fcl::DistanceResultd res;
  fcl::distance(static_cast<const Model*>(a), pose(ra, ta), static_cast<const Model*>(b), pose(rb, tb), req, res);
  return res.min_distance;
}

// Whether two placed models collide (FCL stops at the first contact: one requested).
extern "C" int tridist_fcl_mesh_collide(const void* a, const double* ra, const double* ta, const void* b,
                                        const double* rb, const double* tb) {
  fcl::CollisionRequestd req;
  fcl::CollisionResultd res;
  fcl::collide(static_cast<const Model*>(a), pose(ra, ta), static_cast<const Model*>(b), pose(rb, tb), req, res);
  return res.isCollision() ? 1 : 0;
}
