// Blender's Voronoi texture (see voronoi.h). Written once for N dimensions: cells are visited in
// Cycles' order (x fastest), which decides ties.
#include "shading/textures/voronoi.h"

#include "shading/textures/hash.h"

#include <algorithm>
#include <cmath>

namespace ppm::textures {
namespace {

template <int N>
using VecN = glm::vec<N, float, glm::defaultp>;

// A cell's jittered point (in [0, 1]^N) and its colour, as Cycles hashes a cell: by its position's
// float bits (Blender 3.x to 4.2, and 1-D always), or newer Blender's PCG hash of its integer
// coordinates (`pcg`).
VecN<1> cell_point(const VecN<1>& k, bool) { return VecN<1>(hash_float_to_float(k.x)); }
VecN<2> cell_point(const VecN<2>& k, bool pcg) {
  if (pcg) return hash_int_to_unit<2>(to_ints<2>(k));
  return VecN<2>(hash_float2_to_float(k.x, k.y), hash_float3_to_float(Vec3f(k, 1.0f)));
}
VecN<3> cell_point(const VecN<3>& k, bool pcg) {
  if (pcg) return hash_int_to_unit<3>(to_ints<3>(k));
  return VecN<3>(hash_float3_to_float(k), hash_float4_to_float(glm::vec4(k, 1.0f)),
                 hash_float4_to_float(glm::vec4(k, 2.0f)));
}
VecN<4> cell_point(const VecN<4>& k, bool pcg) {
  if (pcg) return hash_int_to_unit<4>(to_ints<4>(k));
  return VecN<4>(hash_float4_to_float(k), hash_float4_to_float(glm::vec4(k.w, k.x, k.y, k.z)),
                 hash_float4_to_float(glm::vec4(k.z, k.w, k.x, k.y)),
                 hash_float4_to_float(glm::vec4(k.y, k.z, k.w, k.x)));
}
Vec3f cell_color(const VecN<1>& k, bool) {
  return Vec3f(hash_float_to_float(k.x), hash_float2_to_float(k.x, 1.0f), hash_float2_to_float(k.x, 2.0f));
}
Vec3f cell_color(const VecN<2>& k, bool pcg) {
  if (pcg) return hash_int_to_unit<3>(glm::ivec3(to_int(k.x), to_int(k.y), 0));
  return Vec3f(hash_float2_to_float(k.x, k.y), hash_float3_to_float(Vec3f(k, 1.0f)),
               hash_float3_to_float(Vec3f(k, 2.0f)));
}
Vec3f cell_color(const VecN<3>& k, bool pcg) { return Vec3f(cell_point(k, pcg)); }
Vec3f cell_color(const VecN<4>& k, bool pcg) {
  if (pcg) return Vec3f(hash_int_to_unit<4>(to_ints<4>(k)));
  return Vec3f(hash_float4_to_float(k), hash_float4_to_float(glm::vec4(k.z, k.x, k.w, k.y)),
               hash_float4_to_float(glm::vec4(k.w, k.z, k.y, k.x)));
}

template <int N>
float metric_distance(const VecN<N>& a, const VecN<N>& b, VoronoiMetric metric, float exponent) {
  const VecN<N> d = glm::abs(a - b);
  float sum = 0.0f, most = 0.0f;
  switch (metric) {
    case VoronoiMetric::Euclidean: return glm::length(a - b);
    case VoronoiMetric::Manhattan:
      for (int i = 0; i < N; ++i) sum += d[i];
      return sum;
    case VoronoiMetric::Chebychev:
      for (int i = 0; i < N; ++i) most = std::max(most, d[i]);
      return most;
    case VoronoiMetric::Minkowski:
      for (int i = 0; i < N; ++i) sum += std::pow(d[i], exponent);
      return std::pow(sum, 1.0f / exponent);
  }
  return 0.0f;
}

// Calls f(offset) for every cell offset in [-reach, reach]^N, x fastest.
template <int N, class F>
void for_cells(int reach, F&& f) {
  const int side = 2 * reach + 1;
  int count = 1;
  for (int i = 0; i < N; ++i) count *= side;
  for (int index = 0; index < count; ++index) {
    VecN<N> offset;
    int rest = index;
    for (int i = 0; i < N; ++i) {
      offset[i] = float(rest % side - reach);
      rest /= side;
    }
    f(offset);
  }
}

template <int N>
struct Octave {
  float distance = 0.0f;
  Vec3f color{0.0f};
  VecN<N> position{0.0f};
};

template <int N>
Octave<N> f1_or_f2(const VoronoiSettings& s, const VecN<N>& coord, bool second) {
  const VecN<N> cell = glm::floor(coord), local = coord - cell;
  float d1 = 8.0f, d2 = 8.0f;
  VecN<N> off1(0.0f), off2(0.0f), pos1(0.0f), pos2(0.0f);
  for_cells<N>(1, [&](const VecN<N>& offset) {
    const VecN<N> point = offset + cell_point(cell + offset, s.pcg) * s.randomness;
    const float d = metric_distance<N>(point, local, s.metric, s.exponent);
    if (d < d1) {
      d2 = d1, off2 = off1, pos2 = pos1;
      d1 = d, off1 = offset, pos1 = point;
    } else if (d < d2) {
      d2 = d, off2 = offset, pos2 = point;
    }
  });
  Octave<N> o;
  o.distance = second ? d2 : d1;
  o.color = cell_color(cell + (second ? off2 : off1), s.pcg);
  o.position = (second ? pos2 : pos1) + cell;
  return o;
}

float smoothstep01(float x) {
  if (x < 0.0f) return 0.0f;
  if (x >= 1.0f) return 1.0f;
  return (3.0f - 2.0f * x) * x * x;
}

template <int N>
Octave<N> smooth_f1(const VoronoiSettings& s, const VecN<N>& coord) {
  const float smoothness = s.smoothness;
  const VecN<N> cell = glm::floor(coord), local = coord - cell;
  float distance = 8.0f;
  Vec3f color(0.0f);
  VecN<N> position(0.0f);
  for_cells<N>(2, [&](const VecN<N>& offset) {
    const VecN<N> point = offset + cell_point(cell + offset, s.pcg) * s.randomness;
    const float d = metric_distance<N>(point, local, s.metric, s.exponent);
    const float h = smoothstep01(0.5f + 0.5f * (distance - d) / smoothness);
    float correction = smoothness * h * (1.0f - h);
    distance = (1.0f - h) * distance + h * d - correction;
    correction /= 1.0f + 3.0f * smoothness;
    color = glm::mix(color, cell_color(cell + offset, s.pcg), h) - Vec3f(correction);
    position = glm::mix(position, point, h) - VecN<N>(correction);
  });
  return {distance, color, cell + position};
}

template <int N>
float distance_to_edge(const VoronoiSettings& s, const VecN<N>& coord) {
  const VecN<N> cell = glm::floor(coord), local = coord - cell;
  if constexpr (N == 1) {
    const float mid = hash_float_to_float(cell.x) * s.randomness;  // 1-D: float hashes in every version
    const float left = -1.0f + hash_float_to_float(cell.x - 1.0f) * s.randomness;
    const float right = 1.0f + hash_float_to_float(cell.x + 1.0f) * s.randomness;
    return std::min(std::fabs((mid + left) / 2.0f - local.x), std::fabs((mid + right) / 2.0f - local.x));
  } else {
    VecN<N> closest(0.0f);
    float best = 8.0f;
    for_cells<N>(1, [&](const VecN<N>& offset) {
      const VecN<N> to_point = offset + cell_point(cell + offset, s.pcg) * s.randomness - local;
      const float d = glm::dot(to_point, to_point);
      if (d < best) best = d, closest = to_point;
    });
    best = 8.0f;
    for_cells<N>(1, [&](const VecN<N>& offset) {
      const VecN<N> to_point = offset + cell_point(cell + offset, s.pcg) * s.randomness - local;
      const VecN<N> perpendicular = to_point - closest;
      if (glm::dot(perpendicular, perpendicular) > 0.0001f)
        best = std::min(best, glm::dot((closest + to_point) / 2.0f, glm::normalize(perpendicular)));
    });
    return best;
  }
}

template <int N>
float n_sphere_radius(const VoronoiSettings& s, const VecN<N>& coord) {
  const VecN<N> cell = glm::floor(coord), local = coord - cell;
  VecN<N> closest(0.0f), closest_offset(0.0f);
  float best = 8.0f;
  for_cells<N>(1, [&](const VecN<N>& offset) {
    const VecN<N> point = offset + cell_point(cell + offset, s.pcg) * s.randomness;
    const float d = glm::distance(point, local);
    if (d < best) best = d, closest = point, closest_offset = offset;
  });
  best = 8.0f;
  VecN<N> nearest(0.0f);
  for_cells<N>(1, [&](const VecN<N>& offset) {
    if (offset == VecN<N>(0.0f)) return;
    const VecN<N> o = offset + closest_offset;
    const VecN<N> point = o + cell_point(cell + o, s.pcg) * s.randomness;
    const float d = glm::distance(closest, point);
    if (d < best) best = d, nearest = point;
  });
  return glm::distance(nearest, closest) / 2.0f;
}

template <int N>
Octave<N> octave(const VoronoiSettings& s, const VecN<N>& coord) {
  switch (s.feature) {
    case VoronoiFeature::F1: return f1_or_f2<N>(s, coord, false);
    case VoronoiFeature::F2: return f1_or_f2<N>(s, coord, true);
    default:  // Smooth F1 with no smoothness is F1 (4.x; 3.x divided by zero there)
      return s.smoothness > 0.0f ? smooth_f1<N>(s, coord) : f1_or_f2<N>(s, coord, false);
  }
}

// The largest distance one octave's feature can reach (what Normalize divides by).
template <int N>
float max_distance(const VoronoiSettings& s) {
  const float reach = 0.5f + 0.5f * s.randomness;
  const float d = N == 1 ? reach : metric_distance<N>(VecN<N>(0.0f), VecN<N>(reach), s.metric, s.exponent);
  return s.feature == VoronoiFeature::F2 ? 2.0f * d : d;
}

// The fractal sum over octaves of Blender 4.0 on (detail 0: one octave, as before 4.0).
template <int N>
Octave<N> fractal(const VoronoiSettings& s, const VecN<N>& coord) {
  const bool single = s.detail == 0.0f || s.roughness == 0.0f;
  float amplitude = 1.0f, max_amplitude = 0.0f, scale = 1.0f;
  Octave<N> out;
  const int last = to_int(std::ceil(s.detail));
  for (int i = 0; i <= last; ++i) {
    const Octave<N> o = octave<N>(s, coord * scale);
    if (single) {
      max_amplitude = 1.0f;
      out = o;
      break;
    }
    if (float(i) <= s.detail) {
      max_amplitude += amplitude;
      out.distance += o.distance * amplitude;
      out.color += o.color * amplitude;
      out.position = glm::mix(out.position, o.position / scale, amplitude);
      scale *= s.lacunarity;
      amplitude *= s.roughness;
    } else {
      const float rmd = s.detail - std::floor(s.detail);
      if (rmd != 0.0f) {
        max_amplitude = glm::mix(max_amplitude, max_amplitude + amplitude, rmd);
        out.distance = glm::mix(out.distance, out.distance + o.distance * amplitude, rmd);
        out.color = glm::mix(out.color, out.color + o.color * amplitude, rmd);
        out.position = glm::mix(out.position, glm::mix(out.position, o.position / scale, amplitude), rmd);
      }
    }
  }
  if (s.normalize) {  // by the largest distance an octave can have (max_distance below)
    out.distance /= max_amplitude * max_distance<N>(s);
    out.color /= max_amplitude;
  }
  return out;
}

template <int N>
VoronoiResult voronoi_n(const VoronoiSettings& settings, const VecN<N>& p) {
  VoronoiSettings s = settings;
  if (!std::isfinite(s.detail)) s.detail = 0.0f;
  s.randomness = std::clamp(s.randomness, 0.0f, 1.0f);
  s.detail = std::clamp(s.detail, 0.0f, 15.0f);
  s.roughness = std::clamp(s.roughness, 0.0f, 1.0f);
  s.smoothness = std::clamp(s.smoothness / 2.0f, 0.0f, 0.5f);
  const VecN<N> coord = p * s.scale;
  VoronoiResult r;
  if (s.feature == VoronoiFeature::DistanceToEdge) {
    r.distance = distance_to_edge<N>(s, coord);
    return r;
  }
  if (s.feature == VoronoiFeature::NSphereRadius) {
    r.distance = n_sphere_radius<N>(s, coord);
    return r;
  }
  const Octave<N> o = fractal<N>(s, coord);
  r.distance = o.distance;
  r.color = o.color;
  const VecN<N> position = s.scale != 0.0f ? o.position / s.scale : VecN<N>(0.0f);
  for (int i = 0; i < N; ++i) r.position[N == 1 ? 3 : i] = position[i];
  return r;
}

}  // namespace

VoronoiResult voronoi_texture(const VoronoiSettings& s, const glm::vec4& p) {
  switch (s.dimensions) {
    case 1: return voronoi_n<1>(s, VecN<1>(p.x));
    case 2: return voronoi_n<2>(s, VecN<2>(p.x, p.y));
    case 3: return voronoi_n<3>(s, VecN<3>(p));
    default: return voronoi_n<4>(s, p);
  }
}

}  // namespace ppm::textures
