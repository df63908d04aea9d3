// Photon beams' index (ppm/photon_beams.h): every piece of a beam that passes within r of a segment
// is visited, each piece at most once, pieces cover their beam without gaps, and the kept share
// of a pass's beams carries their flux on average.
#include "math/rng.h"
#include "ppm/photon_beams.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

namespace ppm {
namespace {

// The least distance between segment a0 + s da (s in [0, la]) and b0 + t db (t in [0, lb]), by
// dense sampling of one of them (a test's brute force).
double segment_distance(const Vec3& a0, const Vec3& da, double la, const Vec3& b0, const Vec3& db, double lb) {
  double best = kInf;
  for (int k = 0; k <= 4000; ++k) {
    const Vec3 p = b0 + (lb * k / 4000.0) * db;
    const double s = std::clamp(glm::dot(p - a0, da), 0.0, la);
    best = std::min(best, glm::length(p - (a0 + s * da)));
  }
  return best;
}

Vec3 random_direction(Rng& rng) {
  const double z = 2.0 * rng.uniform() - 1.0, phi = 2.0 * kPi * rng.uniform(), s = std::sqrt(1.0 - z * z);
  return Vec3(s * std::cos(phi), s * std::sin(phi), z);
}

std::vector<std::vector<PhotonBeam>> random_beams(int count, Rng& rng) {
  std::vector<std::vector<PhotonBeam>> chunks(3);
  for (int i = 0; i < count; ++i) {
    PhotonBeam b{};
    b.origin = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0;
    b.direction = Vec3f(random_direction(rng));
    b.length = static_cast<float>(i % 7 == 0 ? 40.0 : 3.0 * rng.uniform());  // some cross everything
    b.flux = Vec3f(1.0f);
    chunks[i % 3].push_back(b);
  }
  return chunks;
}

TEST(PhotonBeams, EveryBeamNearASegmentIsVisitedOnceByPiece) {
  Rng rng(5, 0, 0);
  PhotonBeamIndex index;
  const auto chunks = random_beams(300, rng);
  index.build(chunks, chunks.size(), 100000, 1);
  ASSERT_EQ(index.size(), 300u);
  for (int q = 0; q < 40; ++q) {
    const Vec3 origin = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0, dir = random_direction(rng);
    const double length = 5.0 * rng.uniform(), r = 0.02 + 0.2 * rng.uniform();
    std::map<const PhotonBeam*, std::vector<std::pair<float, float>>> seen;
    index.for_each_near_segment(origin, 1.0 / dir, 0.0, length, r,
                                [&](const PhotonBeam& b, const PhotonBeamIndex::Piece& p) { seen[&b].push_back({p.t0, p.t1}); });
    for (const auto& chunk : chunks)
      for (const PhotonBeam& b : chunk) {
        const double d = segment_distance(origin, dir, length, b.origin, Vec3(b.direction), b.length);
        if (d < 0.99 * r) {
          // Its beam is found (a copy of it: compare by origin).
          bool found = false;
          for (const auto& [beam, pieces] : seen) found |= beam->origin == b.origin;
          EXPECT_TRUE(found) << "query " << q << " missed a beam at distance " << d << " < r " << r;
        }
      }
    for (const auto& [beam, pieces] : seen) {
      std::map<float, int> starts;
      for (const auto& p : pieces) EXPECT_EQ(++starts[p.first], 1) << "a piece visited twice";
    }
  }
}

TEST(PhotonBeams, KeptBeamsCarryTheFluxOfAll) {
  Rng rng(6, 0, 0);
  const auto chunks = random_beams(20000, rng);
  PhotonBeamIndex index;
  index.build(chunks, chunks.size(), 2000, 9);
  EXPECT_NEAR(static_cast<double>(index.size()), 2000.0, 5.0 * std::sqrt(2000.0));
  // Whole beams: one piece per beam starts at 0; their flux sums to about 20000.
  double flux = 0.0;
  index.for_each_near_segment(Vec3(-100.0, 2.0, 2.0), Vec3(1.0 / 1.0, kInf, kInf), 0.0, 300.0, 100.0,
                              [&](const PhotonBeam& b, const PhotonBeamIndex::Piece& p) {
                                if (p.t0 == 0.0f) flux += b.flux.x;
                              });
  EXPECT_NEAR(flux, 20000.0, 5.0 * std::sqrt(2000.0) * 10.0);
}

}  // namespace
}  // namespace ppm
