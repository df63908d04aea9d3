// Participating media of the render scene (issue 48): each RGB coefficients and a phase function
// (shading/medium_coefficients.h), constant or plus terms a node program scales where the path is
// (MediumField: a medium that varies in space), and the medium stack a path carries to know which
// medium it is in.
//
// Where media are: a material may carry an interior medium (Blender: a material's Volume output
// fills the closed mesh it is on); the world may carry a medium that fills all space outside the
// meshes with media. A material with a medium but no surface (`Material::surface` false, Blender's
// Volume output alone) is a boundary only: rays cross it unchanged and only change medium.
//
// The medium stack (Cycles' volume stack): a path entering a mesh with a medium through a front
// face pushes it, leaving through a back face removes it; the media on it add up, with the world's
// (Scene::medium_of: as Cycles sums the volumes on its stack, whose first is the world's), the
// world's alone where the stack is empty. Paths start with the media around the camera or the light
// (Scene::media_at). Deeper than kMaxMediumStack, further entries are counted but not kept (proper
// nesting assumed: a leave first undoes an uncounted enter), so 100 nested boxes neither crash nor
// overflow.
#pragma once

#include "math/types.h"
#include "shading/free_path.h"
#include "shading/majorant_grid.h"
#include "shading/medium_coefficients.h"
#include "shading/node_program.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ppm {

// ---- Media that vary in space (heterogeneous). ----
// What varies in a medium: terms, each RGB coefficients times one output of a node program run
// where the path is (Blender: a volume shader's Density, Color or Strength driven by a texture),
// added to the medium's constant coefficients. An output below 0 (or NaN) counts as 0.
struct MediumTerm {
  Color sigma_a{0.0}, sigma_s{0.0}, emission{0.0};
  uint16_t input = 0;  // the program's output that scales them
};
constexpr size_t kMaxFieldOutputs = 8;
struct MediumField {
  NodeProgram program;  // at most kMaxFieldOutputs outputs
  std::vector<MediumTerm> terms;
};
// A field as paths evaluate it: inside one object, whose coordinates (Texture Coordinate's
// Generated and Object) the program reads, as Cycles' volume stack knows the object of each entry.
struct FieldUse {
  std::shared_ptr<const MediumField> field;
  uint32_t object = 0;
};
// A medium's coefficients at one point.
struct LocalMedium {
  Color sigma_a{0.0}, sigma_s{0.0}, emission{0.0};
  Color sigma_t() const { return sigma_a + sigma_s; }
};

constexpr size_t kMaxSummedGrids = 4;  // a sum of media with more majorant grids takes one majorant

struct Medium {
  std::string name;
  MediumCoefficients c;  // validated: finite, >= 0, coefficients at most kMaxCoefficient
  Color sigma_t{0.0};    // c.sigma_t()
  // As added: what varies (null: homogeneous). Paths never evaluate it there: build() gives each
  // object that bounds such a medium a copy of its own (Scene::medium_in) whose `uses` hold it.
  std::shared_ptr<const MediumField> field;
  std::vector<FieldUse> uses;  // what paths evaluate: a copy's field, or the fields of a sum's parts
  // Per channel, at least as large as the coefficients anywhere in it (the constants where it is
  // homogeneous): the trackers' majorant, and what says whether it scatters or emits at all.
  Color sigma_t_bound{0.0}, sigma_s_bound{0.0}, emission_bound{0.0};
  // Where bounds per place pay (a sparse cloud): the trackers' majorant is the sum of these grids'
  // cells along the path and `majorant_rest` (a sum's parts without a grid), emitting where a cell
  // does or `rest_emits`; empty: max_component(sigma_t_bound) everywhere (Scene::track).
  std::vector<std::shared_ptr<const MajorantGrid>> majorant_grids;
  double majorant_rest = 0.0;
  bool rest_emits = false;
  bool varies() const { return !uses.empty(); }
  // Whether sigma_t varies: a field may drive emission alone (a glow by a texture in a medium of
  // constant density), where paths sample free paths as in a homogeneous medium.
  bool extinction_varies() const {
    for (const FieldUse& use : uses)
      for (const MediumTerm& t : use.field->terms)
        if (max_component(t.sigma_a + t.sigma_s) > 0.0) return true;
    return false;
  }
  bool scatters() const { return max_component(sigma_s_bound) > 0.0; }
  bool emits() const { return max_component(emission_bound) > 0.0; }
  // sigma_t and the bounds from the constants alone (a copy that varies adds its terms' bounds next).
  void bound_by_constants() {
    sigma_t = c.sigma_t();
    sigma_t_bound = sigma_t, sigma_s_bound = c.sigma_s, emission_bound = c.emission;
    majorant_grids.clear();
  }
};

constexpr int kMaxMediumStack = 7;
// Boundaries a single ray segment's walk crosses at most (eye, photon and shadow rays): a hit
// after that many ends the path (a scene of media boxes stacked deeper than this is refused by
// nothing, it only loses light beyond).
constexpr int kMaxMediumCrossings = 256;

struct MediumStack {
  int16_t ids[kMaxMediumStack] = {};
  uint8_t count = 0;
  uint8_t overflow = 0;  // entries beyond kMaxMediumStack, not kept
  int top(int world) const { return count ? ids[count - 1] : world; }
  void enter(int id) {
    if (count < kMaxMediumStack)
      ids[count++] = static_cast<int16_t>(id);
    else if (overflow < 255)
      ++overflow;
  }
  void leave(int id) {
    if (overflow > 0) {
      --overflow;
      return;
    }
    for (int k = count - 1; k >= 0; --k)
      if (ids[k] == id) {
        for (int j = k; j + 1 < count; ++j) ids[j] = ids[j + 1];
        --count;
        return;
      }
  }
};
static_assert(sizeof(MediumStack) == 16, "MediumStack grew");

// The radiance a homogeneous medium's emission adds along `distance` of a ray:
// emission * integral_0^d T(t) dt, per channel (1 - exp(-sigma_t d)) / sigma_t, or d where a
// channel has no extinction (0 over an infinite distance: an emitting medium without extinction
// escaping to infinity would be infinitely bright; it adds nothing there instead).
inline Color medium_emission_along(const Medium& m, double distance) {
  Color out(0.0);
  const double d = safe_distance(distance);
  for (int c = 0; c < 3; ++c) {
    const double s = m.sigma_t[c], e = m.c.emission[c];
    if (!(e > 0.0)) continue;
    if (s > 0.0)
      out[c] = e * (d < kInf ? -std::expm1(-s * d) : 1.0) / s;
    else if (d < kInf)
      out[c] = e * d;
  }
  return out;
}

}  // namespace ppm
