// The C ABI every mesh peer shim offers (scenes/src/mesh_peer.rs): a model built by
// PREFIX_new(nv, v, nt, t, config), freed by PREFIX_free, queried by PREFIX_distance and
// PREFIX_collide with two placed models (rotation rows and translation each). A shim defines
// its models as `Base`s and its `new`, then TRIDIST_MESH_ABI(PREFIX) for the rest.
#pragma once

namespace tridist_peer {
// One placed-model interface over the configurations a shim offers (tree kinds, precisions).
// Two models are queried together only when their configs are equal (mesh_peer.rs checks).
struct Base {
  virtual ~Base() = default;
  // The distance (not squared) between this model and b, each in its pose.
  virtual double distance(const double* ra, const double* ta, const Base& b, const double* rb,
                          const double* tb) const = 0;
  // 1 when they collide, else 0.
  virtual int collide(const double* ra, const double* ta, const Base& b, const double* rb,
                      const double* tb) const = 0;
};
}  // namespace tridist_peer

#define TRIDIST_MESH_ABI(prefix)                                                                       \
  extern "C" void prefix##_free(void* m) { delete static_cast<tridist_peer::Base*>(m); }               \
  extern "C" double prefix##_distance(const void* a, const double* ra, const double* ta, const void* b, \
                                      const double* rb, const double* tb) {                            \
    return static_cast<const tridist_peer::Base*>(a)->distance(                                        \
        ra, ta, *static_cast<const tridist_peer::Base*>(b), rb, tb);                                   \
  }                                                                                                    \
  extern "C" int prefix##_collide(const void* a, const double* ra, const double* ta, const void* b,    \
                                  const double* rb, const double* tb) {                                \
    return static_cast<const tridist_peer::Base*>(a)->collide(                                         \
        ra, ta, *static_cast<const tridist_peer::Base*>(b), rb, tb);                                   \
  }
