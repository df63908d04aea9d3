#include "ppm/photon_beams.h"

#include "math/rng.h"

#include <algorithm>
#include <cmath>

namespace ppm {

namespace {

constexpr uint32_t kLeafPieces = 4;
constexpr int kMaxDepth = 60;  // below the query's stack of 64
constexpr double kPiecesAcross = 64.0;
constexpr double kMaxPieces = 256.0;

Vec3 point_on(const PhotonBeam& b, double t) { return b.origin + t * Vec3(b.direction); }

}  // namespace

void PhotonBeamIndex::build(const std::vector<std::vector<PhotonBeam>>& chunks, size_t chunk_count, size_t most,
                            uint64_t seed) {
  beams_.clear();
  nodes_.clear();
  size_t count = 0;
  for (size_t c = 0; c < chunk_count; ++c) count += chunks[c].size();
  const double keep = count > most ? static_cast<double>(most) / count : 1.0;
  uint64_t i = 0;
  for (size_t c = 0; c < chunk_count; ++c)
    for (const PhotonBeam& b : chunks[c]) {
      if (keep < 1.0 && (mix64(seed ^ mix64(i++)) >> 11) * 0x1p-53 >= keep) continue;
      beams_.push_back(b);
      beams_.back().flux /= static_cast<float>(keep);
    }
  cut_pieces();
  pieces_.resize(cut_.size());
  if (cut_.empty()) return;
  order_.resize(cut_.size());
  for (size_t i = 0; i < cut_.size(); ++i) order_[i] = static_cast<uint32_t>(i);
  nodes_.reserve(cut_.size());
  build_node(0, static_cast<uint32_t>(cut_.size()), 0);
  for (size_t i = 0; i < order_.size(); ++i) pieces_[i] = cut_[order_[i]];
}

// Each beam in pieces of about the beams' extent / kPiecesAcross, and their boxes.
void PhotonBeamIndex::cut_pieces() {
  cut_.clear();
  boxes_.clear();
  Aabb all;
  for (const PhotonBeam& b : beams_) {
    all.grow(b.origin);
    all.grow(point_on(b, b.length));
  }
  const Vec3 extent = all.extent();
  const double step = std::max({extent.x, extent.y, extent.z}) / kPiecesAcross;
  for (uint32_t i = 0; i < beams_.size(); ++i) {
    const PhotonBeam& b = beams_[i];
    const double pieces = std::clamp(std::ceil(b.length / step), 1.0, kMaxPieces);
    const auto count = static_cast<uint32_t>(pieces);
    for (uint32_t k = 0; k < count; ++k) {
      const double t0 = b.length * k / pieces, t1 = k + 1 == count ? b.length : b.length * (k + 1) / pieces;
      cut_.push_back(Piece{i, static_cast<float>(t0), static_cast<float>(t1)});
      Aabb box;
      box.grow(point_on(b, t0));
      box.grow(point_on(b, t1));
      boxes_.push_back(box);
    }
  }
}

// Median split of the pieces' box centres along the longest axis of the node's box.
uint32_t PhotonBeamIndex::build_node(uint32_t begin, uint32_t end, int depth) {
  const uint32_t index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back(Node{});
  Aabb box;
  for (uint32_t i = begin; i < end; ++i) box.grow(boxes_[order_[i]]);
  nodes_[index].box = box;
  if (end - begin <= kLeafPieces || depth >= kMaxDepth) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  const int axis = box.longest_axis();
  const uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](uint32_t a, uint32_t b) {
    return boxes_[a].lo[axis] + boxes_[a].hi[axis] < boxes_[b].lo[axis] + boxes_[b].hi[axis];
  });
  build_node(begin, mid, depth + 1);
  const uint32_t right = build_node(mid, end, depth + 1);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

size_t PhotonBeamIndex::memory_bytes() const {
  return beams_.capacity() * sizeof(PhotonBeam) + (cut_.capacity() + pieces_.capacity()) * sizeof(Piece) +
         order_.capacity() * sizeof(uint32_t) + boxes_.capacity() * sizeof(Aabb) + nodes_.capacity() * sizeof(Node);
}

}  // namespace ppm
