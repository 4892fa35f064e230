// tridist's shim over Coal's mesh-vs-mesh distance and collision (BVHModel<OBBRSS>, the bounding
// volume Coal recommends for distance, or RSS or kIOS), for measuring Coal as a mesh peer on the
// same meshes and poses in the same run. Built by scenes/build.rs only when Coal's headers and shared library
// are found (`bash scenes/peer/install.sh` installs the `coal` wheel in a virtual environment
// under target/peers; or set COAL_PREFIX). Coal's library is built for double only.
//
// The C ABI is the one every mesh peer shim offers (scenes/src/mesh_peer.rs):
// new(nv, v, nt, t, config) / free / distance / collide, poses as rotation rows and translation.
#include <coal/BV/OBBRSS.h>
#include <coal/BV/RSS.h>
#include <coal/BV/kIOS.h>
#include <coal/BVH/BVH_model.h>
#include <coal/collision.h>
#include <coal/distance.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh_abi.h"

namespace {
using tridist_peer::Base;

coal::Transform3s pose(const double* r, const double* t) {
  coal::Matrix3s m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = r[3 * i + j];
  return coal::Transform3s(m, coal::Vec3s(t[0], t[1], t[2]));
}

template <typename BV>
struct Model final : Base {
  coal::BVHModel<BV> m;

  Model(std::size_t nv, const double* v, std::size_t nt, const std::uint32_t* t) {
    std::vector<coal::Vec3s> pts(nv);
    for (std::size_t i = 0; i < nv; ++i) pts[i] = coal::Vec3s(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    std::vector<coal::Triangle> tris(nt);
    for (std::size_t i = 0; i < nt; ++i) tris[i] = coal::Triangle(t[3 * i], t[3 * i + 1], t[3 * i + 2]);
    m.beginModel();
    m.addSubModel(pts, tris);
    m.endModel();
  }

  // The distance (not squared), nearest points computed.
  double distance(const double* ra, const double* ta, const Base& other, const double* rb,
                  const double* tb) const override {
    coal::DistanceRequest req;
    req.enable_nearest_points = true;
    coal::DistanceResult res;
    coal::distance(&m, pose(ra, ta), &static_cast<const Model&>(other).m, pose(rb, tb), req, res);
    return res.min_distance;
  }

  // Whether they collide (one contact requested: Coal stops at the first).
  int collide(const double* ra, const double* ta, const Base& other, const double* rb,
              const double* tb) const override {
    coal::CollisionRequest req;
    coal::CollisionResult res;
    coal::collide(&m, pose(ra, ta), &static_cast<const Model&>(other).m, pose(rb, tb), req, res);
    return res.isCollision() ? 1 : 0;
  }
};
}  // namespace

// The model of nv vertices and nt triangles, its tree built. config: 0 OBBRSS, 1 RSS, 2 kIOS
// (the bounding volumes Coal's distance query offers for meshes); two models are
// queried together only when their configs are equal. Null for an unknown config.
extern "C" void* tridist_coal_mesh_new(std::size_t nv, const double* v, std::size_t nt, const std::uint32_t* t,
                                       std::uint32_t config) {
  switch (config) {
    case 0: return static_cast<Base*>(new Model<coal::OBBRSS>(nv, v, nt, t));
    case 1: return static_cast<Base*>(new Model<coal::RSS>(nv, v, nt, t));
    case 2: return static_cast<Base*>(new Model<coal::kIOS>(nv, v, nt, t));
    default: return nullptr;
  }
}

TRIDIST_MESH_ABI(tridist_coal_mesh)
