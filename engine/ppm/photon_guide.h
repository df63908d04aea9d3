// Photon guiding (Settings::photon_guiding): point, sphere, spot and area lights draw their
// photons' directions from a learned histogram instead of their own distribution, towards where
// the error estimate finds the image noisiest.
//
// Each guided light has a histogram over its directions: equal-area bins (rings of cos(theta) by
// sectors of phi) over the sphere, or over an area light's front hemisphere in its own frame. A
// photon that left in bin b and is gathered by a hit point credits b with the luminance it brings
// times its pixel's weight, the pixel's noise over its luminance (RenderContext::
// weigh_pixels_for_guide): the share of the pixel's error this photon's light is part of. After
// each pass the bins' credits, normalised, add to their importance; later passes draw a bin by
// importance with probability 1 - kUniformShare, uniformly otherwise, so that every direction
// keeps a chance. The photon's flux is divided by the ratio of the guide's density to the uniform
// one (emit_photon_towards): guiding changes which photons fly, not what they estimate.
#pragma once

#include "math/types.h"
#include "scene/light.h"

#include <cstdint>
#include <vector>

namespace ppm {

class PhotonGuide {
 public:
  static constexpr int kRings = 16, kSectors = 32, kBins = kRings * kSectors;
  static constexpr double kUniformShare = 0.25;

  // The scene's guidable lights (scene/light.h) get a histogram each, uniform to start with.
  void reset(const std::vector<Light>& lights);
  // The histogram of light `light`, or -1 if it is not guided.
  int slot(uint32_t light) const { return light < slot_of_.size() ? slot_of_[light] : -1; }
  int slots() const { return static_cast<int>(frames_.size()); }
  // Whether slot's histogram has learned anything: until then its light emits as it would unguided
  // (an area light's own cosine lobe beats a uniform hemisphere).
  bool learned(int slot) const { return frames_[slot].learned; }

  // A world direction drawn with (u1, u2) from slot's histogram, its bin, and the ratio of its
  // density to the uniform one over the slot's sphere or hemisphere.
  Vec3 sample(int slot, double u1, double u2, uint32_t& bin, double& ratio) const;
  // The bin of slot's histogram a world direction falls in.
  uint32_t bin_of(int slot, const Vec3& direction) const;

  // Adds one pass's credits (slots() * kBins, slot by slot) to the importance and draws the
  // histograms anew. A slot without credit keeps its histogram.
  void learn(const std::vector<double>& credit);

  // The probability of each bin of `slot`, ring by ring from cos(theta) = -1 (0 for a hemisphere)
  // to 1, in the light's frame for an area light.
  std::vector<double> probabilities(int slot) const;
  size_t memory_bytes() const {
    return slot_of_.capacity() * sizeof(int) + frames_.capacity() * sizeof(Frame) +
           (importance_.capacity() + cdf_.capacity()) * sizeof(double);
  }

 private:
  struct Frame {
    bool hemisphere;  // an area light's: its front side, about its direction
    Vec3 t, b, n;     // the world axes of the histogram's x, y and z
    bool learned;
  };
  std::vector<int> slot_of_;
  std::vector<Frame> frames_;
  std::vector<double> importance_;  // slots * kBins
  std::vector<double> cdf_;         // slots * (kBins + 1)
};

}  // namespace ppm
