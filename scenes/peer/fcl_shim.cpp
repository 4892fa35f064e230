// tridist's shim over FCL's triangle distance (PQP's TriDist as FCL ships it), for measuring
// FCL as a peer on the same pairs in the same run. Built by scenes/build.rs only when the FCL
// and Eigen headers are installed (Debian: libfcl-dev, libeigen3-dev). Header-only use: the
// template definitions come from the -inl.h header, instantiated here for float and double.
#include <cstddef>
#include <Eigen/Dense>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance-inl.h>

// The header declares the double instantiation extern (libfcl ships it); define both here so
// the shim needs FCL's headers only, not its shared library.
template class fcl::detail::TriangleDistance<double>;
template class fcl::detail::TriangleDistance<float>;

namespace {
template <typename S>
void batch(std::size_t n, const S* a, const S* b, S* dist, S* p, S* q) {
  using V = fcl::Vector3<S>;
  for (std::size_t i = 0; i < n; ++i) {
    const S* x = a + 9 * i;
    const S* y = b + 9 * i;
    V t1[3] = {V(x[0], x[1], x[2]), V(x[3], x[4], x[5]), V(x[6], x[7], x[8])};
    V t2[3] = {V(y[0], y[1], y[2]), V(y[3], y[4], y[5]), V(y[6], y[7], y[8])};
    V pp, qq;
    dist[i] = fcl::detail::TriangleDistance<S>::triDistance(t1, t2, pp, qq);
    if (p) {
      for (int k = 0; k < 3; ++k) {
        p[3 * i + k] = pp[k];
        q[3 * i + k] = qq[k];
      }
    }
  }
}
}  // namespace

// Distances (not squared) of pairs a[i], b[i], each triangle 9 coordinates; p, q (3 per pair)
// may be null.
extern "C" void tridist_fcl_tri_dist_f64(std::size_t n, const double* a, const double* b, double* dist,
                                         double* p, double* q) {
  batch<double>(n, a, b, dist, p, q);
}

extern "C" void tridist_fcl_tri_dist_f32(std::size_t n, const float* a, const float* b, float* dist, float* p,
                                         float* q) {
  batch<float>(n, a, b, dist, p, q);
}
