// A node program run at given points of a scene, outside a render (Scene.run_program: the
// add-on's constant folding, tests against Cycles).
#pragma once

#include "math/types.h"
#include "scene/scene.h"
#include "shading/node_program.h"

#include <vector>

namespace ppm {

struct ProgramPoints {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals, incomings;  // one per position: the normal, the direction towards the viewer
  std::vector<Vec2> uvs;                 // one per position
  std::vector<double> tangents;          // x, y, z and the bitangent's sign per position; empty: none
};

// Runs `program` (the caller has validated it against the scene's textures) at every point, as
// object `object` (its info), with the scene's camera and textures, a camera footprint of
// `footprint` and the arrival of a ray of kind `ray_kind` (a RayKind; 0: a light's emission) as the
// Light Path node reads it. Writes 3 floats for each of the program's outputs at each point, point
// after point.
void run_program_at(const Scene& scene, const NodeProgram& program, const ProgramPoints& points, uint32_t object,
                    double footprint, uint8_t ray_kind, float* out);

}  // namespace ppm
