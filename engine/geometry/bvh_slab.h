// The slab test of a BVH node's four child boxes, in float, for a ray given
// in double. Float halves the bytes of a box and fits four children in one
// SSE register, but the test must stay conservative: a box the double ray
// touches must never be reported missed, or a hit is lost.
//
// Why it is conservative:
// - Box bounds are floats rounded outward from the double boxes (bvh.cpp).
// - The origin is rounded per plane in the safe direction: the one used for
//   entry planes makes entry distances come out smaller, the one used for
//   exit planes makes exit distances larger (float_bounds.h). tmax is
//   rounded up.
// - What remains is rounding in the subtraction, the reciprocal and the
//   product: a relative error of at most gamma(3) = 3u / (1 - 3u), u = 2^-24,
//   on each distance (Ize, "Robust BVH ray traversal", JCGT 2013). The box
//   counts as hit when entry <= exit * kSlabSlack + kSlabTiny, with
//   kSlabSlack >= (1 + gamma(3)) / (1 - gamma(3)) plus the rounding of that
//   product, and kSlabTiny covering float's absolute error below FLT_MIN.
// - 0 * inf (a ray parallel to a slab starting on its plane) gives NaN;
//   maxps/minps then keep the running bound, so that slab is ignored: the
//   test can only accept more.
// - Overflow to +-inf keeps the sign, which is all the comparison needs as
//   long as finite distances stay below FLT_MAX: geometry and origins within
//   kFloatRange of the origin guarantee it (|direction| = 1); the BVH tests
//   anything farther out by brute force.
#pragma once

#include "math/types.h"

#include <cfloat>
#include <cstdint>

// x86-64 always has SSE2; MSVC says so with _M_X64 rather than __SSE2__. Elsewhere
// (ARM: Apple silicon, Linux aarch64) the scalar loop below is used.
#if defined(__SSE2__) || defined(_M_X64)
#define PPM_BVH_SSE2 1
#include <emmintrin.h>
#endif

namespace ppm {

constexpr float kSlabSlack = 1.0f + 4.0f * FLT_EPSILON;  // 1 + 4.8e-7 >= 1 + 4.2e-7 needed
constexpr float kSlabTiny = 1e-37f;
constexpr double kFloatRange = 1e37;

struct alignas(64) BvhNode {
  // box[2a][k] / box[2a+1][k]: low / high bound on axis a of child k. An
  // unused child has low = +inf and high = -inf, which every ray misses.
  float box[6][4];
  uint32_t child[4];  // count == 0: index of the child node; else first leaf slot
  uint32_t count[4];  // primitives in a leaf child; 0 for an inner child or an unused one
};
static_assert(sizeof(BvhNode) == 128, "BvhNode is two cache lines");

// Per-ray constants of the slab test, laid out so that a node's test loads
// them as they are: each value repeated in four lanes, and the rows as byte
// offsets into the node.
struct BvhRay {
  BvhRay() = default;
  BvhRay(const Vec3& origin, const Vec3& dir);
  alignas(16) float org_near[3][4];  // origin rounded for entry planes ...
  alignas(16) float org_far[3][4];   // ... and for exit planes
  alignas(16) float inv[3][4];       // 1 / direction, +-inf for a zero component
  uint32_t near[3], far[3];          // byte offsets of the box rows entered / left first on each axis
  bool in_range;                     // origin within kFloatRange
};

// The box row (4 children) at a byte offset from BvhRay::near or far.
inline const float* box_row(const BvhNode& n, uint32_t offset) {
  return reinterpret_cast<const float*>(reinterpret_cast<const char*>(n.box) + offset);
}

// Tests a node's four boxes against (0, tmax] (tmax rounded up to float).
// Returns a bit mask of the children hit and writes their entry distances.
// Near/far rows are chosen by the direction's sign, so no min/max swap is
// needed, and an unused child (+inf, -inf) gives entry = +inf.
inline unsigned intersect_children(const BvhNode& n, const BvhRay& r, float tmax, float entry[4]) {
#if defined(PPM_BVH_SSE2)
  __m128 t0 = _mm_setzero_ps(), t1 = _mm_set1_ps(tmax);
  for (int a = 0; a < 3; ++a) {
    const __m128 inv = _mm_load_ps(r.inv[a]);
    const __m128 tn = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(box_row(n, r.near[a])), _mm_load_ps(r.org_near[a])), inv);
    const __m128 tf = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(box_row(n, r.far[a])), _mm_load_ps(r.org_far[a])), inv);
    t0 = _mm_max_ps(tn, t0);  // a NaN in tn or tf keeps the running bound
    t1 = _mm_min_ps(tf, t1);
  }
  _mm_storeu_ps(entry, t0);
  const __m128 limit = _mm_add_ps(_mm_mul_ps(t1, _mm_set1_ps(kSlabSlack)), _mm_set1_ps(kSlabTiny));
  return unsigned(_mm_movemask_ps(_mm_cmple_ps(t0, limit)));
#else
  float t0[4] = {0.0f, 0.0f, 0.0f, 0.0f}, t1[4] = {tmax, tmax, tmax, tmax};
  for (int a = 0; a < 3; ++a) {
    for (int k = 0; k < 4; ++k) {
      const float tn = (box_row(n, r.near[a])[k] - r.org_near[a][0]) * r.inv[a][0];
      const float tf = (box_row(n, r.far[a])[k] - r.org_far[a][0]) * r.inv[a][0];
      t0[k] = tn > t0[k] ? tn : t0[k];  // false for NaN: the bound stays
      t1[k] = tf < t1[k] ? tf : t1[k];
    }
  }
  unsigned mask = 0;
  for (int k = 0; k < 4; ++k) {
    entry[k] = t0[k];
    mask |= unsigned(t0[k] <= t1[k] * kSlabSlack + kSlabTiny) << k;
  }
  return mask;
#endif
}

}  // namespace ppm
