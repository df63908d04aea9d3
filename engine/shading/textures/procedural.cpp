// Operand layouts of the procedural texture instructions (in[] registers; out[] registers):
//   Noise      in: vector, w, scale, detail, roughness, lacunarity, offset, gain, distortion
//              mode: NoiseType; extra: dimensions | 16 legacy (3.x) | 32 normalize | 64 Musgrave (3.x:
//              roughness is its Dimension); out: fac, color
//   Voronoi    in: vector, w, scale, detail, roughness, lacunarity, smoothness, exponent, randomness
//              mode: feature; flags: metric; extra: dimensions | 32 normalize | 64 PCG cell hash;
//              out: distance (or radius), color, position; `data`: the W output's register
//   WhiteNoise in: vector, w; extra: dimensions; out: value, color
//   Checker    in: vector, color1, color2, scale; out: color, fac
//   Gradient   in: vector; mode: GradientType; out: color, fac
//   Wave       in: vector, scale, distortion, detail, detail scale, detail roughness, phase;
//              mode: kind | direction << 1 | profile << 3; extra: 1 legacy; out: color, fac
//   Magic      in: vector, scale, distortion; extra: depth; flags: 1 wrapped; out: color, fac
//   Brick      in: vector, color1, color2, mortar, scale, mortar size, mortar smooth, bias,
//              brick width, row height; data: offset, offset frequency, squash, squash
//              frequency (floats); out: color, fac
//   Gabor      in: vector, scale, frequency, anisotropy, orientation (2D: an angle), orientation
//              (3D: a direction); mode: 0 2D, 1 3D; out: value, phase, intensity
#include "shading/textures/procedural.h"

#include "shading/textures/gabor.h"
#include "shading/textures/hash.h"
#include "shading/textures/noise.h"
#include "shading/textures/patterns.h"
#include "shading/textures/voronoi.h"

namespace ppm::textures {
namespace {

// The point a texture of `dims` dimensions reads (noise.h's layout), times `scale`.
glm::vec4 texture_point(int dims, const Vec3f& vector, float w, float scale) {
  if (dims == 1) return glm::vec4(w * scale, 0.0f, 0.0f, 0.0f);
  if (dims == 2) return glm::vec4(vector.x * scale, vector.y * scale, 0.0f, 0.0f);
  return glm::vec4(vector * scale, dims == 4 ? w * scale : 0.0f);
}

void noise(const NodeInstruction& ins, Vec3f* r) {
  auto f = [&](int k) { return r[ins.in[k]].x; };
  NoiseSettings s;
  s.dimensions = ins.extra & 7;
  s.type = static_cast<NoiseType>(ins.mode);
  s.legacy = (ins.extra & 16) != 0;
  s.normalize = (ins.extra & 32) != 0;
  s.detail = f(3), s.roughness = f(4), s.lacunarity = f(5), s.offset = f(6), s.gain = f(7), s.distortion = f(8);
  const glm::vec4 p = texture_point(s.dimensions, r[ins.in[0]], f(1), f(2));
  if (ins.extra & 64) {  // Blender 3.x's Musgrave texture: Fac only
    r[ins.out[0]] = Vec3f(musgrave_texture(s, p));
    return;
  }
  const NoiseResult n = noise_texture(s, p, ins.out[1] != 0);
  r[ins.out[0]] = Vec3f(n.fac);
  r[ins.out[1]] = n.color;
}

void voronoi(const NodeInstruction& ins, Vec3f* r) {
  auto f = [&](int k) { return r[ins.in[k]].x; };
  VoronoiSettings s;
  s.dimensions = ins.extra & 7;
  s.feature = static_cast<VoronoiFeature>(ins.mode);
  s.metric = static_cast<VoronoiMetric>(ins.flags);
  s.normalize = (ins.extra & 32) != 0;
  s.pcg = (ins.extra & 64) != 0;
  s.scale = f(2), s.detail = f(3), s.roughness = f(4), s.lacunarity = f(5), s.smoothness = f(6), s.exponent = f(7),
  s.randomness = f(8);
  const VoronoiResult v = voronoi_texture(s, texture_point(s.dimensions, r[ins.in[0]], f(1), 1.0f));
  r[ins.out[0]] = Vec3f(v.distance);
  r[ins.out[1]] = v.color;
  r[ins.out[2]] = Vec3f(v.position);
  r[ins.data] = Vec3f(v.position.w);
}

void brick_texture(const NodeInstruction& ins, const std::vector<float>& data, Vec3f* r) {
  auto f = [&](int k) { return r[ins.in[k]].x; };
  BrickSettings s;
  const float* d = data.data() + ins.data;
  s.offset = d[0], s.offset_frequency = to_int(d[1]), s.squash = d[2], s.squash_frequency = to_int(d[3]);
  s.mortar_size = f(5), s.mortar_smooth = f(6), s.bias = f(7), s.brick_width = f(8), s.row_height = f(9);
  const BrickResult b = brick(s, r[ins.in[0]] * f(4));
  Vec3f color = r[ins.in[1]];
  if (b.mortar != 1.0f) color = (1.0f - b.tint) * color + b.tint * r[ins.in[2]];
  r[ins.out[0]] = color * (1.0f - b.mortar) + r[ins.in[3]] * b.mortar;
  r[ins.out[1]] = Vec3f(b.mortar);
}

}  // namespace

void run(const NodeInstruction& ins, const std::vector<float>& data, Vec3f* r) {
  auto f = [&](int k) { return r[ins.in[k]].x; };
  switch (ins.op) {
    case NodeOp::Noise: noise(ins, r); break;
    case NodeOp::Voronoi: voronoi(ins, r); break;
    case NodeOp::WhiteNoise: {
      const int dims = ins.extra & 7;
      const WhiteNoiseResult w = white_noise(dims, texture_point(dims, r[ins.in[0]], f(1), 1.0f));
      r[ins.out[0]] = Vec3f(w.value);
      r[ins.out[1]] = w.color;
      break;
    }
    case NodeOp::Checker: {
      const float c = checker(r[ins.in[0]] * f(3));
      r[ins.out[0]] = c == 1.0f ? r[ins.in[1]] : r[ins.in[2]];
      r[ins.out[1]] = Vec3f(c);
      break;
    }
    case NodeOp::Gradient: {
      const float g = gradient(static_cast<GradientType>(ins.mode), r[ins.in[0]]);
      r[ins.out[0]] = Vec3f(g);
      r[ins.out[1]] = Vec3f(g);
      break;
    }
    case NodeOp::Wave: {
      WaveSettings s;
      s.kind = ins.mode & 1, s.direction = (ins.mode >> 1) & 3, s.profile = (ins.mode >> 3) & 3;
      s.legacy = (ins.extra & 1) != 0;
      s.distortion = f(2), s.detail = f(3), s.detail_scale = f(4), s.detail_roughness = f(5), s.phase = f(6);
      const float w = wave(s, r[ins.in[0]] * f(1));
      r[ins.out[0]] = Vec3f(w);
      r[ins.out[1]] = Vec3f(w);
      break;
    }
    case NodeOp::Magic: {
      const Vec3f c = magic(r[ins.in[0]], f(1), ins.extra, f(2), (ins.flags & 1) != 0);
      r[ins.out[0]] = c;
      r[ins.out[1]] = Vec3f((c.x + c.y + c.z) * (1.0f / 3.0f));
      break;
    }
    case NodeOp::Brick: brick_texture(ins, data, r); break;
    case NodeOp::Gabor: {
      const GaborResult g = gabor(ins.mode == 1, r[ins.in[0]] * f(1), f(2), f(3), f(4), r[ins.in[5]]);
      r[ins.out[0]] = Vec3f(g.value);
      r[ins.out[1]] = Vec3f(g.phase);
      r[ins.out[2]] = Vec3f(g.intensity);
      break;
    }
    default: break;
  }
}

bool valid(const NodeInstruction& ins, size_t data_size, int registers) {
  const int dims = ins.extra & 7;
  switch (ins.op) {
    case NodeOp::Noise: return dims >= 1 && dims <= 4 && ins.mode <= static_cast<int>(NoiseType::HeteroTerrain);
    case NodeOp::Voronoi:
      return dims >= 1 && dims <= 4 && ins.mode <= static_cast<int>(VoronoiFeature::NSphereRadius) &&
             ins.flags <= static_cast<int>(VoronoiMetric::Minkowski) && ins.data >= 1 &&
             ins.data < static_cast<uint32_t>(registers);
    case NodeOp::WhiteNoise: return dims >= 1 && dims <= 4;
    case NodeOp::Gradient: return ins.mode <= static_cast<int>(GradientType::Spherical);
    case NodeOp::Wave: return ((ins.mode >> 3) & 3) <= 2;
    case NodeOp::Magic: return ins.extra <= 10;
    case NodeOp::Brick: return size_t(ins.data) + 4 <= data_size;
    case NodeOp::Gabor: return ins.mode <= 1;
    default: return true;
  }
}

}  // namespace ppm::textures
