// Tests for node programs and Blender's textures in the core: the hashes bit for bit (the values
// below are lookup3's, and nodes_compare.py shows Cycles gives the same), noise that stays finite
// and bounded for any input, image sampling modes, the Bump node against an analytic slope, and a
// program that refers to what it does not have being refused; Gabor noise's ranges.
#include "shading/node_program.h"

#include "shading/node_math.h"
#include "shading/textures/gabor.h"
#include "shading/textures/hash.h"
#include "shading/textures/noise.h"
#include "shading/textures/patterns.h"
#include "shading/textures/voronoi.h"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace {

using namespace ppm;
using namespace ppm::textures;

TEST(Hash, Lookup3MatchesItsKnownValues) {
  EXPECT_EQ(hash_uint(0u), 0x9519dc65u);
  EXPECT_EQ(hash_uint(1u), 0x4ad7c6a0u);
  EXPECT_EQ(hash_uint2(0u, 0u), 0xdc3d74f9u);
  EXPECT_EQ(hash_uint3(0u, 0u, 0u), 0x9c6eedfbu);
  EXPECT_EQ(hash_uint3(1u, 2u, 3u), 0xb8d17a0au);
  EXPECT_EQ(hash_uint4(1u, 2u, 3u, 4u), 0x0584dec1u);
}

TEST(Hash, FloatsToIntsAreDefinedForEveryFloat) {
  EXPECT_EQ(to_int(std::numeric_limits<float>::quiet_NaN()), 0);
  EXPECT_EQ(to_int(-2.5f), -2);
  EXPECT_GT(to_int(1e30f), 2000000000);
  EXPECT_LT(to_int(-std::numeric_limits<float>::infinity()), -2000000000);
}

TEST(Noise, StaysFiniteAndBoundedForAnyInput) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (float x : {0.0f, 0.37f, -12.5f, 1e5f, 1e6f + 0.25f, 3e9f, -1e30f, inf, nan}) {
    const Vec3f p(x, 0.5f * x + 0.1f, -0.25f);
    const float n = snoise(p);
    EXPECT_TRUE(std::isfinite(n) || !std::isfinite(x)) << x;
    if (std::isfinite(n)) EXPECT_LE(std::fabs(n), 1.05f) << x;
    NoiseSettings s;
    s.distortion = 0.5f;
    s.detail = x;  // any detail: clamped, NaN taken as 0
    const NoiseResult r = noise_texture(s, glm::vec4(p, 0.0f), true);
    if (std::isfinite(x)) EXPECT_TRUE(std::isfinite(r.fac) && std::isfinite(r.color.z)) << x;
  }
}

TEST(Noise, IsContinuous) {
  // Perlin noise has a continuous gradient: a step of 1e-4 changes it by well under 1e-2.
  for (int i = 0; i < 200; ++i) {
    const Vec3f p(0.173f * i, 0.071f * i - 3.0f, 0.013f * i * i);
    EXPECT_LT(std::fabs(snoise(p + Vec3f(1e-4f, 0.0f, 0.0f)) - snoise(p)), 1e-2f) << i;
  }
}

TEST(Voronoi, F1IsTheDistanceToTheNearestJitteredPointAndF2IsFarther) {
  VoronoiSettings s;
  for (int i = 0; i < 100; ++i) {
    const glm::vec4 p(0.13f * i, 0.29f * i - 4.0f, 0.07f * i, 0.0f);
    s.feature = VoronoiFeature::F1;
    const VoronoiResult f1 = voronoi_texture(s, p);
    s.feature = VoronoiFeature::F2;
    const VoronoiResult f2 = voronoi_texture(s, p);
    EXPECT_GE(f2.distance, f1.distance);
    // The nearest point is where Position says, at Distance (in the scaled space).
    EXPECT_NEAR(glm::distance(Vec3f(p) * s.scale, Vec3f(f1.position) * s.scale), f1.distance, 1e-4f);
    s.pcg = !s.pcg;  // both cell hashes
  }
}

TEST(Voronoi, HugeAndNanCoordinatesDoNotMisbehave) {
  VoronoiSettings s;
  s.pcg = true;
  for (float x : {1e30f, -1e30f, std::numeric_limits<float>::quiet_NaN()}) {
    const VoronoiResult r = voronoi_texture(s, glm::vec4(x, x, x, x));
    EXPECT_FALSE(std::isinf(r.color.x));  // no crash, no undefined conversion
  }
}

TEST(Gabor, ValueCentresOnAHalfAndPhaseAndIntensityStayInTheirRanges) {
  for (bool three_d : {false, true}) {
    double sum = 0.0;
    const int n = 2000;
    for (int i = 0; i < n; ++i) {
      const Vec3f p(0.173f * i, 0.071f * i - 3.0f, 0.013f * float(i % 97));
      const GaborResult g = gabor(three_d, p, 2.0f, 0.5f, 0.3f, Vec3f(0.6f, 0.0f, 0.8f));
      EXPECT_TRUE(g.phase >= 0.0f && g.phase <= 1.0f) << i;
      EXPECT_GE(g.intensity, 0.0f);
      // Normalised by six standard deviations: almost always within [0, 1] (Blender clamps nothing).
      EXPECT_TRUE(g.value > -0.5f && g.value < 1.5f) << i;
      sum += g.value;
    }
    EXPECT_NEAR(sum / n, 0.5, 0.02) << three_d;  // the imaginary part has zero mean
  }
}

TEST(Gabor, DegenerateInputsGiveNoInfinityOrHang) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (float x : {0.0f, 1e30f, -1e30f, nan}) {
    // A zero or vertical 3D orientation (Cycles divides by its zero planar length there), any frequency.
    for (const Vec3f& orientation : {Vec3f(0.0f), Vec3f(0.0f, 0.0f, 1.0f)}) {
      const GaborResult g = gabor(true, Vec3f(x, 0.5f, 0.25f), x, 0.2f, 0.0f, orientation);
      EXPECT_FALSE(std::isinf(g.value) || std::isinf(g.intensity)) << x;
    }
  }
}

TEST(Patterns, CheckerAlternatesAndBricksHaveMortar) {
  EXPECT_EQ(checker(Vec3f(0.5f, 0.5f, 0.5f)), 0.0f);  // Cycles' colour 2 in the cell at the origin
  EXPECT_EQ(checker(Vec3f(1.5f, 0.5f, 0.5f)), 1.0f);
  EXPECT_EQ(checker(Vec3f(1.5f, 1.5f, 0.5f)), 0.0f);
  EXPECT_EQ(checker(Vec3f(-0.5f, 0.5f, 0.5f)), 1.0f);
  BrickSettings b;
  EXPECT_EQ(brick(b, Vec3f(0.1f, 0.125f, 0.0f)).mortar, 0.0f);    // inside a brick (row 0 is offset)
  EXPECT_EQ(brick(b, Vec3f(0.25f, 0.001f, 0.0f)).mortar, 1.0f);   // on a row's edge
  b.brick_width = 0.0f;                                           // a zero width stays defined
  EXPECT_TRUE(std::isfinite(brick(b, Vec3f(0.3f, 0.3f, 0.0f)).tint));
}

Texture gradient_texture() {  // 4 x 1 texels of values 0, 1/3, 2/3, 1, linear
  std::vector<float> texels;
  for (int i = 0; i < 4; ++i) texels.insert(texels.end(), {i / 3.0f, i / 3.0f, i / 3.0f, 1.0f});
  return Texture::from_floats(4, 1, 4, texels.data(), TexelStorage::Half);
}

TEST(TextureSample, ExtensionsAndInterpolationsReadWhatBlenderReads) {
  const Texture t = gradient_texture();
  auto at = [&](double u, TextureInterpolation i, TextureExtension e) { return t.sample(Vec2(u, 0.5), i, e).x; };
  using I = TextureInterpolation;
  using E = TextureExtension;
  EXPECT_NEAR(at(0.375, I::Closest, E::Repeat), 1.0 / 3.0, 1e-3);
  EXPECT_NEAR(at(0.25, I::Linear, E::Repeat), 1.0 / 6.0, 1e-3);   // between texels 0 and 1
  EXPECT_NEAR(at(1.25, I::Linear, E::Repeat), 1.0 / 6.0, 1e-3);   // repeats
  EXPECT_NEAR(at(1.5, I::Linear, E::Extend), 1.0, 1e-3);          // the last texel
  EXPECT_NEAR(at(-0.25, I::Linear, E::Mirror), 1.0 / 6.0, 1e-3);  // mirrored: as at 0.25
  EXPECT_EQ(t.sample(Vec2(1.5, 0.5), I::Linear, E::Clip).w, 0.0);  // outside: transparent
  // Beyond the edge it fades over half a texel: an eighth of a texel out, 3/8 of the last texel.
  EXPECT_NEAR(t.sample(Vec2(1.0 + 0.125 / 4.0, 0.5), I::Linear, E::Clip).w, 0.375, 1e-3);
  // A cubic B-spline reproduces a straight line where all four taps lie on it.
  EXPECT_NEAR(at(0.5, I::Cubic, E::Extend), 0.5, 1e-3);
}

// A program reading position x through Math Multiply: height = slope * x.
NodeProgram slope_program(float slope, float distance) {
  NodeProgram p;
  p.constants = {Vec3f(slope), Vec3f(0.0f), Vec3f(1.0f), Vec3f(distance)};  // registers 1-4
  const uint16_t slope_r = 1, zero = 2, one = 3, dist = 4;
  p.registers = 5;
  auto next = [&] { return static_cast<uint16_t>(p.registers++); };
  auto add = [&](NodeOp op, uint8_t mode, std::initializer_list<uint16_t> in, uint16_t out) {
    NodeInstruction ins;
    ins.op = op;
    ins.mode = mode;
    std::copy(in.begin(), in.end(), ins.in.begin());
    ins.out[0] = out;
    p.code.push_back(ins);
  };
  const uint16_t normal = next();
  add(NodeOp::Coord, static_cast<uint8_t>(CoordKind::ShadingNormal), {}, normal);
  std::vector<uint16_t> heights;
  for (uint8_t side : {0, 1, 2}) {  // centre, then beside along the two steps
    if (side != 0) add(NodeOp::BumpOffset, side, {one}, 0);  // filter width 1
    const uint16_t position = next(), height = next();
    add(NodeOp::Coord, static_cast<uint8_t>(CoordKind::Position), {}, position);
    add(NodeOp::Math, 2, {position, slope_r, zero}, height);  // Multiply (x only: a float reads .x)
    heights.push_back(height);
  }
  add(NodeOp::BumpOffset, 0, {one}, 0);
  const uint16_t bumped = next();
  add(NodeOp::Bump, 0, {one, dist, heights[0], heights[1], heights[2], normal, one}, bumped);
  p.outputs = {bumped};
  return p;
}

TEST(Bump, TiltsTheNormalAgainstTheHeightsGradient) {
  // On the plane z = 0, height h = a x and distance d: Cycles' normal is N - d grad h, normalised.
  for (float slope : {0.0f, 0.5f, 3.0f}) {
    const NodeProgram p = slope_program(slope, 0.2f);
    p.validate(0, "bump");
    ShadingContext c;
    c.position = Vec3(0.3, -0.7, 0.0);
    Vec3f n;
    p.run(c, {}, &n);
    const Vec3 expected = glm::normalize(Vec3(-0.2 * slope, 0.0, 1.0));
    EXPECT_NEAR(n.x, expected.x, 1e-4) << slope;
    EXPECT_NEAR(n.z, expected.z, 1e-4) << slope;
  }
}

TEST(Program, ReferencesItDoesNotHaveAreRefused) {
  NodeProgram p = slope_program(1.0f, 0.1f);
  EXPECT_NO_THROW(p.validate(0, "ok"));
  NodeProgram reads_beyond = p;
  reads_beyond.code[2].in[0] = 200;
  EXPECT_THROW(reads_beyond.validate(0, "m"), std::invalid_argument);
  NodeProgram writes_constant = p;
  writes_constant.code[0].out[0] = 1;
  EXPECT_THROW(writes_constant.validate(0, "m"), std::invalid_argument);
  NodeProgram image = p;
  image.code[0].op = NodeOp::Image;
  image.code[0].data = 3;  // no such texture
  EXPECT_THROW(image.validate(2, "m"), std::invalid_argument);
  NodeProgram nan = p;
  nan.constants[0] = Vec3f(std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(nan.validate(0, "m"), std::invalid_argument);
  NodeProgram matrix = p;  // a Transform's matrix must lie in the data
  matrix.code[0].op = NodeOp::Transform;
  matrix.code[0].mode = 0;
  matrix.data.assign(11, 0.0f);
  EXPECT_THROW(matrix.validate(0, "m"), std::invalid_argument);
  matrix.data.assign(12, 0.0f);
  EXPECT_NO_THROW(matrix.validate(0, "m"));
  NodeProgram projection = p;
  projection.code[0].op = NodeOp::Image;
  projection.code[0].extra = 4;  // no such projection
  EXPECT_THROW(projection.validate(1, "m"), std::invalid_argument);
}

TEST(Program, OutputsThatOverflowOrAreNotANumberAreZero) {
  NodeProgram p;
  p.constants = {Vec3f(1000.0f), Vec3f(0.0f)};
  p.registers = 3;
  NodeInstruction exp;  // e^1000 = inf
  exp.op = NodeOp::Math;
  exp.mode = static_cast<uint8_t>(nodes::MathOp::Exponent);
  exp.in = {1, 1, 1};
  exp.out[0] = p.registers++;
  NodeInstruction nan = exp;  // inf * 0 = NaN
  nan.mode = static_cast<uint8_t>(nodes::MathOp::Multiply);
  nan.in = {exp.out[0], 2, 2};
  nan.out[0] = p.registers++;
  p.code = {exp, nan};
  p.outputs = {exp.out[0], nan.out[0]};
  std::array<Vec3f, 2> out;
  p.run(ShadingContext{}, {}, out.data());
  EXPECT_EQ(out[0], Vec3f(0.0f));
  EXPECT_EQ(out[1], Vec3f(0.0f));
}

TEST(Program, OutputBoundsFollowTheOperations) {
  NodeProgram p;
  p.constants = {Vec3f(0.5f), Vec3f(3.0f)};
  p.registers = 3;
  NodeInstruction uv;
  uv.op = NodeOp::Coord;
  uv.mode = static_cast<uint8_t>(CoordKind::Uv);
  uv.out[0] = p.registers++;
  NodeInstruction times;  // UV * 3: unbounded
  times.op = NodeOp::Math;
  times.mode = 2;
  times.in = {uv.out[0], 2};
  times.out[0] = p.registers++;
  NodeInstruction clamped = times;  // the same, clamped: at most 1
  clamped.flags = 1;
  clamped.out[0] = p.registers++;
  p.code = {uv, times, clamped};
  p.outputs = {times.out[0], clamped.out[0], 1};
  EXPECT_TRUE(std::isinf(p.output_bound(0, {})));
  EXPECT_EQ(p.output_bound(1, {}), 1.0);
  EXPECT_EQ(p.output_bound(2, {}), 0.5);
}

}  // namespace

namespace {

// A program of one instruction reading coordinate `kind` (and an optional second instruction).
Vec3f run_one(const NodeProgram& p, const ShadingContext& c) {
  Vec3f out[1];
  p.run(c, {}, out);
  return out[0];
}

NodeProgram coordinate_program(CoordKind kind) {
  NodeProgram p;
  NodeInstruction coord;
  coord.op = NodeOp::Coord;
  coord.mode = static_cast<uint8_t>(kind);
  coord.out[0] = 1;
  p.code.push_back(coord);
  p.outputs = {1};
  p.registers = 2;
  return p;
}

}  // namespace

TEST(CameraCoordinates, WindowIsWhereTheCameraRayThroughAPixelLandsOnTheFullFrame) {
  Camera cam;
  cam.camera_to_world = glm::rotate(Mat4(1.0), 0.4, Vec3(0.3, 1.0, 0.2));
  cam.camera_to_world[3] = glm::dvec4(1.0, -2.0, 3.0, 1.0);
  cam.width = 64;  // a border window 64 x 40 at (100, 30) of a 320 x 200 frame
  cam.height = 40;
  cam.frame_x = 100;
  cam.frame_y = 30;
  cam.frame_width = 320;
  cam.frame_height = 200;
  cam.shift_x = 0.3;
  cam.shift_y = -0.1;
  for (const Projection projection : {Projection::Perspective, Projection::Orthographic}) {
    cam.projection = projection;
    const NodeProgram window = coordinate_program(CoordKind::Window), camera = coordinate_program(CoordKind::Camera);
    ShadingContext c;
    c.camera = &cam;
    for (const auto& [px, py] : {std::pair{0.5, 0.5}, {63.5, 12.25}, {20.0, 39.0}}) {
      const Ray ray = cam.generate_ray(px, py);
      c.position = ray.origin + 7.5 * ray.direction;
      const Vec3f w = run_one(window, c);
      EXPECT_NEAR(w.x, (px + 100.0) / 320.0, 1e-5);
      EXPECT_NEAR(w.y, (py + 30.0) / 200.0, 1e-5);
      EXPECT_EQ(w.z, 0.0f);
      // Camera space looks along +z: the depth of the point in front of the camera.
      EXPECT_NEAR(run_one(camera, c).z, cam.depth_of(c.position), 1e-4);
    }
  }
}

TEST(VectorTransform, GoesToEverySpaceAndBack) {
  Camera cam;
  cam.camera_to_world = glm::rotate(Mat4(1.0), 1.1, Vec3(1.0, 0.2, -0.4));
  cam.camera_to_world[3] = glm::dvec4(-3.0, 0.5, 2.0, 1.0);
  ObjectInfo object;
  object.object_to_world = glm::scale(glm::rotate(Mat4(1.0), -0.7, Vec3(0.0, 1.0, 1.0)), Vec3(2.0, 0.5, 1.5));
  object.object_to_world[3] = glm::dvec4(4.0, 1.0, -2.0, 1.0);
  object.world_to_object = glm::inverse(object.object_to_world);
  ShadingContext c;
  c.camera = &cam;
  c.object = &object;
  for (uint8_t type = 0; type < 2; ++type) {  // point, vector
    for (int from = 0; from < 3; ++from) {
      for (int to = 0; to < 3; ++to) {
        NodeProgram p;
        p.constants = {Vec3f(0.3f, -1.2f, 2.5f)};
        NodeInstruction there, back;
        there.op = back.op = NodeOp::VectorTransform;
        there.flags = back.flags = type;
        there.mode = static_cast<uint8_t>(from * 3 + to);
        back.mode = static_cast<uint8_t>(to * 3 + from);
        there.in[0] = 1;
        there.out[0] = 2;
        back.in[0] = 2;
        back.out[0] = 3;
        p.code = {there, back};
        p.outputs = {3, 2};
        p.registers = 4;
        Vec3f out[2];
        p.run(c, {}, out);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[0][k], p.constants[0][k], 1e-4) << from << to << int(type);
        if (from == 0 && to == 2 && type == 0)  // world -> camera is Texture Coordinate's Camera
          for (int k = 0; k < 3; ++k) EXPECT_NEAR(out[1][k], cam.camera_space(Vec3(p.constants[0]))[k], 1e-4);
      }
    }
  }
}
