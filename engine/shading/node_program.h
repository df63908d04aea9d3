// A material's node program: Blender's texture and utility nodes compiled by the add-on into a flat
// list of instructions over float-triple registers, as Cycles' SVM runs them. A shading point runs
// the program once (a switch per instruction: no virtual calls, no allocation) and its outputs
// become the material's inputs (SurfacePoint::inputs), which lobes, the normal and the emission
// refer to through InputRef. Values are floats, as in Cycles, so procedural patterns line up with
// Cycles' to float rounding; a float sits in all three channels of its register.
#pragma once

#include "math/aabb.h"
#include "math/types.h"
#include "geometry/ray.h"
#include "geometry/camera.h"
#include "shading/texture.h"
#include "shading/voxel_grid.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace ppm {

constexpr int kMaxRegisters = 256;

// What Blender knows of an object that nodes read: Texture Coordinate's Object and Generated
// (through the texture space, Blender's auto bounds of the undeformed mesh), Object Info, and the
// Attribute node's object and instancer attributes (RGBA, by the slot the add-on gave each name;
// a slot the object lacks reads 0, as a property Cycles does not find).
struct ObjectInfo {
  Mat4 world_to_object{1.0}, object_to_world{1.0};
  Vec3 texspace_min{-1.0}, texspace_size{2.0};  // generated = (object - min) / size
  Vec3 location{0.0};
  float random = 0.0f, pass_index = 0.0f;
  glm::vec4 color{1.0f};  // Object Info's Color and Alpha: the object's viewport display colour
  std::vector<glm::vec4> attributes;
  // Its voxel grids (a smoke domain's or a Volume object's) by the slot the add-on gave each name;
  // null: the object has none of that name.
  std::vector<std::shared_ptr<const VoxelGrid>> grids;
  // What Cycles multiplies a Volume object's volume closures by (its density follows the object's
  // scale: 1 / |M (1, 1, 1) / sqrt 3| when the Volume's space is Object); 1 for other objects.
  float volume_density = 1.0f;
};

// What Blender's Light Path node reads at a shading point: the ray that arrived and the path's
// scatterings before it. Camera paths know it as Cycles does; a photon arrives on a shadow ray
// straight from its light (photons see what shadow rays see), later on the kind of its last
// scattering, with a depth of 1 + its scatterings (the camera side of its path is not known yet).
// A plain record (hit points keep one: no initialisers, see fill_vector.h).
struct LightPath {
  uint8_t kind;   // a RayKind; 0: a light's emission being sampled
  bool singular;  // the last scattering was a mirror's or smooth glass's
  uint8_t depth, diffuse, glossy, transmission;
  float length;   // of the ray that arrived
};
inline constexpr LightPath kCameraPath{kCameraRay, false, 0, 0, 0, 0, 0.0f};

// Where a program runs: the shading point as Blender's Geometry and Texture Coordinate nodes see
// it. The bump offsets say how far a Bump node's height is looked at sideways (bump.h).
struct ShadingContext {
  Vec3 position{0.0};
  Vec3 normal{0.0, 0.0, 1.0};       // the shading normal (interpolated)
  Vec3 true_normal{0.0, 0.0, 1.0};  // geometric, facing as the primitive defines
  Vec3 incoming{0.0, 0.0, 1.0};     // towards the viewer
  Vec2 uv{0.0};
  Vec3 tangent{0.0};                // a mesh's UV tangent; zero: none
  double tangent_sign = 1.0;
  Vec3 du_dp{0.0}, dv_dp{0.0};      // how the UV changes along the surface (triangles)
  const ObjectInfo* object = nullptr;
  const Camera* camera = nullptr;   // the scene's (Camera and Window coordinates, Vector Transform)
  bool backfacing = false;
  double footprint = 0.0;           // world size of a pixel here, seen by a camera ray; 0: unknown
  glm::vec4 attribute{0.0f};        // the mesh attribute here (Attribute, Color Attribute nodes)
  LightPath path = kCameraPath;
  // Stochastic grids (VoxelGrid::stochastic) pick one voxel by trilinear weights with random numbers
  // from this LCG state where it is not 0 (a tracker's point); 0: they interpolate.
  uint32_t voxel_random = 0;
};

enum class NodeOp : uint8_t {
  Coord,          // mode: CoordKind
  Convert,        // mode: 0 colour -> grey (luminance; 2: Blender 3.x-4.x's weights), 1 vector -> average
  Math,           // mode: MathOp; flag 1: clamp to [0, 1]
  VectorMath,     // mode: VectorMathOp; out[0] vector, out[1] value
  Mix,            // mode: MixBlend; in fac, a, b; flag 1 clamp factor, 2 clamp result
  MixVector,      // per-component factor: in fac (vector), a, b
  Table,          // baked into data: extra + 2 RGBA entries; mode 0: a ColorRamp over [0, 1] (flag 1:
                  // interpolate), 1: RGB/Vector Curves, 2: Float Curve, over [lo, hi] stored before
  MapRange,       // mode: 0 linear, 1 stepped, 2 smoothstep, 3 smootherstep; flag 1: clamp; vector: flag 2
  Clamp,          // mode: 0 min-max, 1 range
  Separate,       // mode: channel 0-2 of in[0]; 3-5: H, S, V; 6-8: H, S, L
  Combine,        // mode: 0 xyz/rgb, 1 hsv, 2 hsl
  Invert,         // in fac, colour
  Gamma,
  BrightContrast,
  HueSaturation,  // in hue, saturation, value, fac, colour
  Mapping,        // mode: 0 point, 1 texture, 2 vector, 3 normal; in vector, location, rotation, scale
  VectorRotate,   // mode: axis kind; flag 1 invert
  Image,          // data: texture index (flag 1: the offset of a UDIM table: count, then (tile, texture)
                  // pairs); mode: interpolation | extension << 2; extra: projection (0 flat,
                  // 1 box: in[1] the object-space normal, in[2] the blend; 2 sphere, 3 tube); out colour, alpha
  Noise,          // mode: NoiseKind; dims in `extra`; see textures/noise.h
  Voronoi,
  WhiteNoise,
  Checker,
  Gradient,
  Wave,
  Brick,
  Magic,
  Fresnel,        // in ior, normal
  LayerWeight,    // in blend, normal; out[0] fresnel, out[1] facing
  BumpOffset,     // mode: 0 centre, 1 dx, 2 dy: where the next height is read; in filter width
  Bump,           // in strength, distance, height centre, dx, dy, normal, filter width; flag 1 invert
  NormalMap,      // mode: 0 tangent, 1 object, 2 world; in strength, colour; flag 1: normalise first (3.x)
  EnvironmentUv,  // Environment Texture: a direction -> the image's (u, v, 0); mode 0 equirectangular, 1 mirror ball
  VectorTransform,  // mode: from * 3 + to (0 world, 1 object, 2 camera); flags: 0 point, 1 vector, 2 normal
  Transform,      // in[0] by the 3 x 4 matrix at data (rows); mode 0: a point, 1: a direction
  Wavelength,     // in[0] nm; data: XYZ -> scene linear (3 x 3, rows), then 81 XYZ triples from 380 nm by 5
  Blackbody,      // in[0] kelvin; data: Rec.709 -> scene linear (3 x 3, rows), then the fit (kBlackbodyFit)
  Gabor,          // see textures/procedural.cpp
  Grid,           // the object's voxel grid in slot `data` at in[0] (its to_index maps it): out colour, fac (the
                  // colour's mean), alpha; an object without it reads 0, or with flag 1 reads 1 (the
                  // Principled Volume's attributes multiply only where Cycles finds them)
};

// The floats of a Blackbody instruction's fit, after its matrix (export/blackbody.py lays them out):
// the 6 interval starts, the coldest and hottest temperature fitted, the colours held beyond them
// (3 + 3), then per interval (7) the red (3), green (3) and blue (4) coefficients.
inline constexpr size_t kBlackbodyFit = 6 + 2 + 6 + 7 * 10;

enum class CoordKind : uint8_t {
  Generated, Normal, Uv, Object, Camera, Window, Reflection,  // Texture Coordinate
  Position, ShadingNormal, TrueNormal, Incoming, Backfacing,   // Geometry
  Tangent,                                                     // Tangent (the UV map's)
  ObjectLocation, ObjectRandom, ObjectIndex,                   // Object Info
  Attribute, AttributeAlpha, AttributeMean,                    // Attribute (colour, alpha, fac)
  ObjectColor, ObjectAlpha,                                    // Object Info
  ObjectAttribute, ObjectAttributeAlpha, ObjectAttributeMean,  // Attribute, object: the slot in data
  IsCameraRay, IsShadowRay, IsDiffuseRay, IsGlossyRay, IsSingularRay, IsReflectionRay,  // Light Path
  IsTransmissionRay, RayLength, RayDepth, DiffuseDepth, GlossyDepth, TransmissionDepth,
};

struct NodeInstruction {
  NodeOp op = NodeOp::Math;
  uint8_t mode = 0, flags = 0, extra = 0;
  std::array<uint16_t, 3> out{};
  std::array<uint16_t, 10> in{};
  uint32_t data = 0;  // an offset into NodeProgram::data, or a texture index
};

class NodeProgram {
 public:
  // Register 0 is scratch (outputs nobody reads go there); registers 1 .. constants.size() hold these.
  std::vector<Vec3f> constants;
  std::vector<NodeInstruction> code;
  std::vector<float> data;                   // baked tables
  std::vector<uint16_t> outputs;             // the registers a material reads as its inputs
  // Per output, the largest value it may give (+inf: as computed); a finite one also keeps it >= 0.
  // Set for colours whose range the program cannot bound (Scene::check_lobes).
  std::vector<float> output_max;
  int registers = 1;                         // registers used (scratch and constants included)

  bool empty() const { return outputs.empty(); }
  // Throws std::invalid_argument (naming `what`) for a register, texture or table out of range.
  void validate(size_t texture_count, const std::string& what) const;
  // Runs the program at `ctx`; writes each output into `results` (outputs.size() of them).
  void run(const ShadingContext& ctx, const std::vector<Texture>& textures, Vec3f* results) const;
  // The largest value output `i` can take in any channel (for the energy bound); +inf: unknown.
  // With `object`, for that object (its grids' largest values); without, grids are unbounded.
  // With `region` too (a box in world space), at points in it: a grid read at the Object or
  // Generated coordinate is bounded by its largest value there (a medium's majorant grid, scene/majorant_grid.h).
  double output_bound(size_t i, const std::vector<Texture>& textures, const ObjectInfo* object = nullptr,
                      const Aabb* region = nullptr) const;
  // What running it reads beyond a hit's record: UV gradients (a Bump's steps), the mesh attribute.
  struct Needs {
    bool uv_gradients = false, attribute = false;
  };
  Needs needs() const { return needs_; }
  void find_needs();  // after the code is complete (Scene::add_material)
  // Appends an output: the image `texture` read at the UV (bilinear, repeating) in `channel`.
  void add_image_output(int texture, TextureChannel channel);

 private:
  void step(const NodeInstruction& ins, ShadingContext& at, const ShadingContext& base,
            const std::vector<Texture>& textures, Vec3f* r) const;
  Needs needs_;
};

}  // namespace ppm
