// Node programs from Python (see node_program_bindings.cpp).
#pragma once

#include "shading/node_program.h"

#include <pybind11/pybind11.h>

#include <string>

namespace ppm::py_convert {

// A program from its dict: constants (RGB triples, registers 1..), code (instruction dicts: op,
// mode, flags, extra, in, out, data), data (floats), outputs (registers), registers (count).
NodeProgram program_from(const pybind11::handle& value, const std::string& what);
pybind11::dict node_modes();

}  // namespace ppm::py_convert
