// The procedural texture instructions of a node program: how each reads its operands from the
// registers and writes its outputs (the layouts the add-on's compiler emits; see procedural.cpp).
#pragma once

#include "shading/node_program.h"

namespace ppm::textures {

// Runs a Noise, Voronoi, White Noise, Checker, Gradient, Wave, Brick or Magic instruction.
void run(const NodeInstruction& ins, const std::vector<float>& data, Vec3f* r);
// Whether the instruction's modes and, for those that keep settings in the data, its offset are valid.
bool valid(const NodeInstruction& ins, size_t data_size, int registers);

}  // namespace ppm::textures
