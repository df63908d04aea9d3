// Photon beams (Jarosz et al. 2011): the stretches photons travel through homogeneous scattering
// media after reaching them along chains of specular bounces (a volumetric caustic: a lamp's light
// through glass into fog), kept per pass and indexed by a BVH over pieces of them, so that an eye
// beam (hit_point.h's VolumeBeam) finds every one that passes within its radius (the Beam x Beam
// estimate, photon_pass_beams.cpp). Light that scattered diffusely or in a medium before stays
// with volume photons (photon_tracer_media.h): each photon's light goes to one estimate only.
//
// A beam is "short": it ends where its photon's free path scattered or left the medium, and
// carries at t what the photon carries past t, flux T(t) / P(the free path reaches t), whose
// expectation over the free path is flux T(t) (free_path.h: P is the channel mixture's
// sum_c pdf_c T_c(t)). Light straight from a lamp is direct light, sampled at the eye, unless
// photons carry that too (Settings::direct_light).
#pragma once

#include "math/aabb.h"
#include "math/types.h"
#include "ppm/bounce_limits.h"

#include <cstdint>
#include <vector>

namespace ppm {

// Photons per photon beam kept in a pass, at most (PhotonBeamIndex::build). Each beam crosses
// many camera rays, so a few suffice, and their gather's cost grows with their number: on the
// bundled fog caustic (tools/volume_beams_noise.py, 10 s) the image noise was 0.0143 with 300
// beams a pass, 0.0146 with 1000, 0.0206 with 3000 and 0.046 with all (about 11000) kept.
constexpr uint64_t kPhotonsPerBeam = 200;
constexpr uint64_t kMinPhotonBeams = 1000;

struct PhotonBeam {
  Vec3 origin;
  Vec3f direction;
  float length;
  Vec3f flux;         // at origin
  Vec3f channel_pdf;  // the free path's channel probabilities
  int32_t medium;
  Bounces used;  // with bounce limits: the path's counts with a scattering on the beam
};

// A long beam's box holds mostly space far from it: the index holds pieces of the beams instead,
// about a 64th of the beams' extent long (at most kMaxPieces per beam), and a crossing counts in
// the piece its point on the photon beam falls in.
class PhotonBeamIndex {
 public:
  // The beams of `chunks` in chunk order (the same index whichever thread traced which chunk), of
  // which about `most` are kept where there are more (each with probability most / count, its
  // flux divided by that; which by `seed`).
  void build(const std::vector<std::vector<PhotonBeam>>& chunks, size_t chunk_count, size_t most, uint64_t seed);

  // A stretch [t0, t1) of beam `beam` (t1 of the last piece: the beam's length, included).
  struct Piece {
    uint32_t beam;
    float t0, t1;
    // Whether distance t along the beam falls in this piece.
    bool holds(double t, const PhotonBeam& b) const { return t >= t0 && (t < t1 || t1 >= b.length); }
  };

  // fn(beam, piece) for every piece whose box, widened by r, meets origin + t dir for t in
  // [t0, t1] (`inv_dir` = 1 / dir): a superset of those passing within r of the segment.
  template <class Fn>
  void for_each_near_segment(const Vec3& origin, const Vec3& inv_dir, double t0, double t1, double r,
                             Fn&& fn) const {
    if (nodes_.empty()) return;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      double a, b;
      slab_interval(Aabb{node.box.lo - r, node.box.hi + r}, origin, inv_dir, t1, a, b);
      if (!(std::max(a, t0) <= b)) continue;
      if (node.count > 0) {
        for (uint32_t i = node.first; i < node.first + node.count; ++i) fn(beams_[pieces_[i].beam], pieces_[i]);
      } else {
        stack[top++] = node.first;
        stack[top++] = static_cast<uint32_t>(&node - nodes_.data()) + 1;
      }
    }
  }

  size_t size() const { return beams_.size(); }
  size_t memory_bytes() const;

 private:
  struct Node {
    Aabb box;
    uint32_t first;  // a leaf's first piece; an inner node's right child (its left is the next node)
    uint32_t count;  // pieces in a leaf, 0 for an inner node
  };
  uint32_t build_node(uint32_t begin, uint32_t end, int depth);
  void cut_pieces();

  std::vector<PhotonBeam> beams_;  // chunk order
  std::vector<Piece> cut_, pieces_;  // in the order cut; in leaf order
  std::vector<Aabb> boxes_;          // of cut_
  std::vector<uint32_t> order_;      // cut_ index of each pieces_ entry
  std::vector<Node> nodes_;
};

}  // namespace ppm
