// Media that vary in space (scene/medium.h's MediumField): the copies build() makes, one per object
// bounding such a medium, their bounds, and their coefficients along a path.
//
// A copy's bounds make the trackers' majorant. Each term's scale is bounded by what the node
// program can give (NodeProgram::output_bound, which follows each instruction's range: a Noise
// through a ColorRamp is bounded by the ramp's largest entry). Where that is unknown (an attribute,
// an unbounded Math), the largest value found at kBoundSamples^3 points through the object's box,
// times kSampledMargin: not a proof, and a density above the majorant counts as the majorant (a
// biased image, never an undefined one; free_path.h).
#include "scene/scene.h"

#include "math/float_bounds.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ppm {
namespace {

constexpr int kBoundSamples = 24;
constexpr double kSampledMargin = 1.5;
constexpr double kEmissionSamples = 4.0;  // tentative collisions a glowing segment has at least, on average
// A majorant grid is kept where its cells' mean majorant is below this share of the one majorant
// (walking its cells costs a little on every segment).
constexpr double kGridPays = 0.9;

// A program output as a term's scale per channel: NaN and negative values 0, at most kMaxCoefficient.
Color scale_of(const Vec3f& v) {
  Color c(v);
  for (int i = 0; i < 3; ++i) c[i] = c[i] > 0.0 ? std::min(c[i], kMaxCoefficient) : 0.0;
  return c;
}

// The terms' coefficients at the outputs' scales `scale` times `density` (an object's
// volume_density), added to sigma_t, sigma_s and emission.
void add_terms(const std::vector<MediumTerm>& terms, const std::array<double, kMaxFieldOutputs>& scale, double density,
               Color& sigma_t, Color& sigma_s, Color& emission) {
  for (const MediumTerm& t : terms) {
    const double b = scale[t.input] * density;
    sigma_t += (t.sigma_a + t.sigma_s) * b;
    sigma_s += t.sigma_s * b;
    emission += t.emission * b;
  }
}

// The majorant along a ray through a medium with majorant grids: the sum of its grids' cells and
// its rest, piece by piece (the pieces where none of the grids' cells change); where it emits, at
// least `emission_floor`. Ratio tracking (`ratio`: a transmittance, no scattering) takes the
// medium's one majorant wherever the cells' is not 0: ratio tracking's relative variance is
// exp(tau sigma / majorant) - 1, so a tight majorant makes it a coin toss (a lamp seen through a
// plume, tools/media_throughput.py --smoke: about twice the image's relative MSE at 5 s), while
// delta tracking is indifferent to it.
class SummedMajorant {
 public:
  SummedMajorant(const Medium& m, const Ray& ray, double emission_floor, bool ratio)
      : rest_(m.majorant_rest), floor_(emission_floor), raise_to_(ratio ? max_component(m.sigma_t_bound) : 0.0),
        rest_emits_(m.rest_emits), count_(m.majorant_grids.size()) {
    for (size_t k = 0; k < count_; ++k) {
      walks_[k] = m.majorant_grids[k]->walk(ray);
      pieces_[k] = walks_[k].next();
    }
  }
  MajorantPiece next() {
    double end = kInf, sum = rest_;
    bool emits = rest_emits_;
    for (size_t k = 0; k < count_; ++k) {
      end = std::min(end, pieces_[k].end);
      sum += pieces_[k].cell->majorant;
      emits = emits || pieces_[k].cell->emits;
    }
    for (size_t k = 0; k < count_; ++k)
      if (!(pieces_[k].end > end)) pieces_[k] = walks_[k].next();
    if (sum > 0.0) sum = std::max(sum, raise_to_);
    return {end, emits ? std::max(sum, floor_) : sum};
  }

 private:
  double rest_, floor_, raise_to_;
  bool rest_emits_;
  size_t count_;
  std::array<MajorantGrid::Walk, kMaxSummedGrids> walks_;
  std::array<MajorantGrid::Piece, kMaxSummedGrids> pieces_{};
};

}  // namespace

void Scene::prepare_media() {
  copy_varying_media();
  media_boxes_ = medium_boxes(true);
  combine_overlapping_media();
}

void Scene::copy_varying_media() {
  media_.resize(added_media_);
  copy_of_.clear();
  if (std::none_of(media_.begin(), media_.end(), [](const Medium& m) { return bool(m.field); })) return;
  for (const auto& [key, box] : medium_boxes(false)) {
    const auto [object, id] = key;
    if (!media_[static_cast<size_t>(id)].field) continue;
    if (media_.size() >= static_cast<size_t>(std::numeric_limits<int16_t>::max())) break;  // the added one serves
    Medium copy = media_[static_cast<size_t>(id)];
    copy.uses = {FieldUse{copy.field, object}};
    const double scale = object_info(object).volume_density;  // (the terms take it in local_medium)
    copy.c.sigma_a *= scale, copy.c.sigma_s *= scale, copy.c.emission *= scale;
    copy.bound_by_constants();
    bound_field(copy, box);
    copy_of_[{id, object}] = static_cast<int>(media_.size());
    media_.push_back(std::move(copy));
  }
}

std::array<double, kMaxFieldOutputs> Scene::field_output_bounds(const Medium& copy, const Aabb& box) const {
  const MediumField& f = *copy.field;
  const size_t outputs = f.program.outputs.size();
  std::array<double, kMaxFieldOutputs> bound{};
  bool sample = false;
  const ObjectInfo& object = object_info(copy.uses[0].object);
  for (size_t k = 0; k < outputs; ++k) {
    bound[k] = f.program.output_bound(k, textures_, &object);
    sample = sample || !(bound[k] < kInf);
  }
  if (!sample) return bound;
  std::array<double, kMaxFieldOutputs> found{};
  std::array<Vec3f, kMaxFieldOutputs> results{};
  ShadingContext ctx;
  ctx.object = &object;
  ctx.camera = &camera_;
  const Vec3 step = box.extent() / double(kBoundSamples);
  for (int i = 0; i < kBoundSamples; ++i)
    for (int j = 0; j < kBoundSamples; ++j)
      for (int k = 0; k < kBoundSamples; ++k) {
        ctx.position = box.lo + (Vec3(i, j, k) + 0.5) * step;
        f.program.run(ctx, textures_, results.data());
        for (size_t o = 0; o < outputs; ++o) found[o] = std::max(found[o], max_component(scale_of(results[o])));
      }
  for (size_t o = 0; o < outputs; ++o)
    if (!(bound[o] < kInf)) bound[o] = std::min(kSampledMargin * found[o], kMaxCoefficient);
  return bound;
}

void Scene::bound_field(Medium& copy, const Aabb& box) const {
  const std::array<double, kMaxFieldOutputs> bound = field_output_bounds(copy, box);
  const ObjectInfo& object = object_info(copy.uses[0].object);
  add_terms(copy.field->terms, bound, object.volume_density, copy.sigma_t_bound, copy.sigma_s_bound,
            copy.emission_bound);
  for (int c = 0; c < 3; ++c) copy.sigma_t_bound[c] = std::min(copy.sigma_t_bound[c], kMaxCoefficient);
  if (majorant_grids_) bound_field_per_cell(copy, box, bound);
}

// A majorant grid over the copy's box where the program bounds its outputs more tightly by place
// (grids read at the Object or Generated coordinate: NodeProgram::output_bound's region) and that
// pays: the cells' mean majorant below kGridPays of the copy's one majorant.
void Scene::bound_field_per_cell(Medium& copy, const Aabb& box,
                                 const std::array<double, kMaxFieldOutputs>& bound) const {
  const MediumField& f = *copy.field;
  const ObjectInfo& object = object_info(copy.uses[0].object);
  const double everywhere = max_component(copy.sigma_t_bound);
  if (!(everywhere > 0.0) || box.empty() || !(box.half_area() > 0.0) || !(box.half_area() < kInf)) return;
  const auto cell_bound = [&](const Aabb& cell) {
    std::array<double, kMaxFieldOutputs> here{};
    for (size_t k = 0; k < f.program.outputs.size(); ++k)
      here[k] = std::min(bound[k], f.program.output_bound(k, textures_, &object, &cell));
    Color sigma_t = copy.sigma_t, sigma_s = copy.c.sigma_s, emission = copy.c.emission;
    add_terms(f.terms, here, object.volume_density, sigma_t, sigma_s, emission);
    return MajorantGrid::Cell{float_up(std::min(max_component(sigma_t), everywhere)), max_component(emission) > 0.0};
  };
  auto grid = std::make_shared<MajorantGrid>(box, MajorantGrid::Cell{float_up(everywhere), copy.emits()}, cell_bound);
  if (grid->mean_majorant() < kGridPays * everywhere) copy.majorant_grids = {std::move(grid)};
}

LocalMedium Scene::local_medium(const Medium& m, const Vec3& x, const Vec3& direction,
                                uint32_t voxel_random) const {
  LocalMedium out{m.c.sigma_a, m.c.sigma_s, m.c.emission};
  ShadingContext ctx;
  ctx.voxel_random = voxel_random;
  ctx.position = x;
  ctx.normal = ctx.true_normal = ctx.incoming = -direction;
  ctx.camera = &camera_;
  std::array<Vec3f, kMaxFieldOutputs> results;
  for (const FieldUse& use : m.uses) {
    ctx.object = &object_info(use.object);
    use.field->program.run(ctx, textures_, results.data());
    if (ctx.voxel_random != 0) ctx.voxel_random = (ctx.voxel_random * 747796405u + 2891336453u) | 1u;  // own numbers
    for (const MediumTerm& t : use.field->terms) {
      const Color s = scale_of(results[t.input]) * double(ctx.object->volume_density);
      out.sigma_a += t.sigma_a * s, out.sigma_s += t.sigma_s * s, out.emission += t.emission * s;
    }
  }
  return out;
}

TrackedSegment Scene::track(const Medium& m, const Ray& ray, double segment, const Color& throughput,
                            bool may_scatter, bool sums_emission, Rng& rng) const {
  const auto at = [&](double t) {
    const LocalMedium l = local_medium(m, ray.origin + t * ray.direction, ray.direction, rng.next_u32() | 1u);
    return TrackedCoefficients{l.sigma_t(), l.sigma_s, l.emission};
  };
  // The bound itself is the majorant, for ratio tracking too. A larger one lowers its variance
  // (relative variance exp(tau sigma / majorant) - 1) for more steps, and lost at equal time: the
  // bundled cloud at 160x120, 12 s, rel. MSE 0.015 with the bound, 0.029 with up to 4 times it and
  // 0.046 with up to 16 times (tau_bound times it, capped; /tmp scripts, 2026-12-07).
  // Emission is summed at the tentative collisions, so a glow that hardly absorbs (a fire's thin
  // smoke, or none) takes a majorant of at least kEmissionSamples over the segment: any majorant
  // above sigma_t is unbiased, and one of 0 saw no emission at all (a Principled Volume of density 0
  // glowing by a temperature grid read 0.63 of Cycles beside it). Photons and shadow rays sum none.
  const bool floored = sums_emission && segment > 0.0 && segment < kInf;
  const double floor = floored ? kEmissionSamples / segment : 0.0;
  if (!m.majorant_grids.empty()) {
    SummedMajorant majorants(m, ray, floor, !may_scatter);
    return track_segment_pieces(at, majorants, segment, throughput, may_scatter, [&] { return rng.uniform(); });
  }
  double majorant = max_component(m.sigma_t_bound);
  if (m.emits()) majorant = std::max(majorant, floor);
  return track_segment(at, majorant, segment, throughput, may_scatter, [&] { return rng.uniform(); });
}

}  // namespace ppm
