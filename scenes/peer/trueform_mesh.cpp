// tridist's shim over TrueForm's mesh-vs-mesh nearest pair (`tf::neighbor_search` of two forms)
// and intersection test (`tf::intersects`), for measuring TrueForm as a mesh peer on the same
// meshes and poses in the same run. TrueForm is header-only and runs through oneTBB; both come
// with the `trueform` wheel, which `bash scenes/peer/install.sh` installs in a virtual
// environment under target/peers (or set TRUEFORM_INCLUDE and TBB_LIB). Built by scenes/build.rs.
//
// The C ABI is the one every mesh peer shim offers (scenes/src/mesh_peer.rs), plus the thread
// count (TBB's global parallelism).
#include <tbb/global_control.h>
#include <trueform/trueform.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "mesh_abi.h"

namespace {
using tridist_peer::Base;

bool identity(const double* r, const double* t) {
  for (int i = 0; i < 3; ++i) {
    if (t[i] != 0.0) return false;
    for (int j = 0; j < 3; ++j)
      if (r[3 * i + j] != (i == j ? 1.0 : 0.0)) return false;
  }
  return true;
}

template <typename T>
tf::frame<T, 3> frame(const double* r, const double* t) {
  auto m = tf::make_identity_transformation<T, 3>();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m(i, j) = static_cast<T>(r[3 * i + j]);
    m(i, 3) = static_cast<T>(t[i]);
  }
  return tf::make_frame(m);
}

// Vertices and indices owned here; the tree built over the polygons viewing them.
template <typename T, typename Tree>
struct Model final : Base {
  std::vector<T> pts;
  std::vector<std::int32_t> ids;
  Tree tree;

  Model(std::size_t nv, const double* v, std::size_t nt, const std::uint32_t* t) : pts(3 * nv), ids(3 * nt) {
    for (std::size_t i = 0; i < 3 * nv; ++i) pts[i] = static_cast<T>(v[i]);
    for (std::size_t i = 0; i < 3 * nt; ++i) ids[i] = static_cast<std::int32_t>(t[i]);
    tree.build(polys(), tf::config_tree(4, 4));
  }
  auto polys() const { return tf::make_polygons(tf::make_faces<3>(ids), tf::make_points<3>(pts)); }

  double distance(const double* ra, const double* ta, const Base& other, const double* rb,
                  const double* tb) const override {
    const auto& b = static_cast<const Model&>(other);
    auto fb = frame<T>(rb, tb);
    if (identity(ra, ta)) {
      // the first mesh at rest, as TrueForm's own benchmarks place it: no frame (the same
      // answers as with an identity frame)
      auto r = tf::neighbor_search(polys() | tf::tag(tree), b.polys() | tf::tag(b.tree) | tf::tag(fb));
      return std::sqrt(static_cast<double>(r.metric()));
    }
    auto fa = frame<T>(ra, ta);
    auto r = tf::neighbor_search(polys() | tf::tag(tree) | tf::tag(fa), b.polys() | tf::tag(b.tree) | tf::tag(fb));
    return std::sqrt(static_cast<double>(r.metric()));
  }
  int collide(const double* ra, const double* ta, const Base& other, const double* rb,
              const double* tb) const override {
    const auto& b = static_cast<const Model&>(other);
    auto fa = frame<T>(ra, ta);
    auto fb = frame<T>(rb, tb);
    return tf::intersects(polys() | tf::tag(tree) | tf::tag(fa), b.polys() | tf::tag(b.tree) | tf::tag(fb)) ? 1 : 0;
  }
};

// Never destroyed at exit: TBB's own statics may be gone by then (the process crashed in its
// exit handlers when this was a static unique_ptr).
tbb::global_control* threads = nullptr;
}  // namespace

// The model of nv vertices and nt triangles, its tree built with 4 children per node and 4
// triangles per leaf (`tf::config_tree(4, 4)`, as TrueForm's own benchmarks build it). config:
// 0 axis-aligned boxes in float (TrueForm's benchmarks), 1 axis-aligned boxes in double,
// 2 OBBRSS in double, 3 oriented boxes in double. Two models are queried together only when
// their configs are equal.
extern "C" void* tridist_trueform_mesh_new(std::size_t nv, const double* v, std::size_t nt, const std::uint32_t* t,
                                           std::uint32_t config) {
  switch (config) {
    case 0: return static_cast<Base*>(new Model<float, tf::aabb_tree<int, float, 3>>(nv, v, nt, t));
    case 1: return static_cast<Base*>(new Model<double, tf::aabb_tree<int, double, 3>>(nv, v, nt, t));
    case 2: return static_cast<Base*>(new Model<double, tf::obbrss_tree<int, double, 3>>(nv, v, nt, t));
    case 3: return static_cast<Base*>(new Model<double, tf::obb_tree<int, double, 3>>(nv, v, nt, t));
    default: return nullptr;
  }
}

TRIDIST_MESH_ABI(tridist_trueform_mesh)

// TBB's parallelism for the queries that follow: n threads at most, or TBB's default for 0.
extern "C" void tridist_trueform_threads(std::uint32_t n) {
  delete threads;
  threads = n > 0 ? new tbb::global_control(tbb::global_control::max_allowed_parallelism, n) : nullptr;
}
