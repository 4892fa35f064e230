// tridist's shim over FCL's mesh-vs-mesh distance and collision (BVHModel<OBBRSS<double>>, the
// bounding volume FCL recommends for distance, or RSS or kIOS), for measuring FCL as the mesh
// peer on the same meshes and poses in the same run. Built by scenes/build.rs only when FCL's headers and its
// shared library are installed (Debian: libfcl-dev, libeigen3-dev); links libfcl. FCL's library
// instantiates double only, so this peer is double only.
#include <cstddef>
#include <cstdint>
#include <vector>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/RSS.h>
#include <fcl/math/bv/kIOS.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include "mesh_abi.h"

namespace {
using tridist_peer::Base;

// A pose as tridist writes it: rotation rows r[0..9], translation t[0..3].
fcl::Transform3d pose(const double* r, const double* t) {
  fcl::Transform3d p = fcl::Transform3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.linear()(i, j) = r[3 * i + j];
    p.translation()(i) = t[i];
  }
  return p;
}

template <typename BV>
struct Model final : Base {
  fcl::BVHModel<BV> m;

  Model(std::size_t nv, const double* v, std::size_t nt, const std::uint32_t* t) {
    std::vector<fcl::Vector3d> pts(nv);
    for (std::size_t i = 0; i < nv; ++i) pts[i] = fcl::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    std::vector<fcl::Triangle> tris(nt);
    for (std::size_t i = 0; i < nt; ++i) tris[i] = fcl::Triangle(t[3 * i], t[3 * i + 1], t[3 * i + 2]);
    m.beginModel();
    m.addSubModel(pts, tris);
    m.endModel();
  }

  // The distance (not squared), nearest points computed (as tridist's mesh distance computes
  // its closest points).
  double distance(const double* ra, const double* ta, const Base& other, const double* rb,
                  const double* tb) const override {
    fcl::DistanceRequestd req;
    req.enable_nearest_points = true;
    fcl::DistanceResultd res;
    fcl::distance(&m, pose(ra, ta), &static_cast<const Model&>(other).m, pose(rb, tb), req, res);
    return res.min_distance;
  }

  // Whether they collide (FCL stops at the first contact: one requested).
  int collide(const double* ra, const double* ta, const Base& other, const double* rb,
              const double* tb) const override {
    fcl::CollisionRequestd req;
    fcl::CollisionResultd res;
    fcl::collide(&m, pose(ra, ta), &static_cast<const Model&>(other).m, pose(rb, tb), req, res);
    return res.isCollision() ? 1 : 0;
  }
};
}  // namespace

// The model of nv vertices (3 coordinates each) and nt triangles (3 indices each), its tree
// built; free with tridist_fcl_mesh_free. config (the mesh peers' common C ABI,
// scenes/src/mesh_peer.rs): 0 OBBRSS, 1 RSS, 2 kIOS, the bounding volumes FCL's distance query
// offers for meshes; two models are queried together only when their configs are
// equal. Null for an unknown config.
extern "C" void* tridist_fcl_mesh_new(std::size_t nv, const double* v, std::size_t nt, const std::uint32_t* t,
                                      std::uint32_t config) {
  switch (config) {
    case 0: return static_cast<Base*>(new Model<fcl::OBBRSSd>(nv, v, nt, t));
    case 1: return static_cast<Base*>(new Model<fcl::RSSd>(nv, v, nt, t));
    case 2: return static_cast<Base*>(new Model<fcl::kIOSd>(nv, v, nt, t));
    default: return nullptr;
  }
}

TRIDIST_MESH_ABI(tridist_fcl_mesh)
