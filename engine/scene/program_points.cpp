// A node program run point by point with a shading context made from each point.
#include "scene/program_points.h"

#include <array>

namespace ppm {

void run_program_at(const Scene& scene, const NodeProgram& program, const ProgramPoints& points, uint32_t object,
                    double footprint, uint8_t ray_kind, float* out) {
  LightPath path = kCameraPath;
  path.kind = ray_kind;
  path.depth = path.kind == kCameraRay || path.kind == 0 ? 0 : 1;
  std::array<Vec3f, kMaxInputs> values;
  for (size_t i = 0; i < points.positions.size(); ++i) {
    ShadingContext c;
    c.position = points.positions[i];
    c.normal = c.true_normal = points.normals[i];
    c.incoming = points.incomings[i];
    c.backfacing = glm::dot(c.incoming, c.normal) < 0.0;
    c.uv = points.uvs[i];
    if (!points.tangents.empty()) {
      c.tangent = Vec3(points.tangents[4 * i], points.tangents[4 * i + 1], points.tangents[4 * i + 2]);
      c.tangent_sign = points.tangents[4 * i + 3];
    }
    c.object = &scene.object_info(object);
    c.camera = scene.has_camera() ? &scene.camera() : nullptr;
    c.path = path;
    c.footprint = footprint;
    program.run(c, scene.textures(), values.data());
    for (size_t k = 0; k < program.outputs.size(); ++k)
      for (int j = 0; j < 3; ++j) *out++ = values[k][j];
  }
}

}  // namespace ppm
