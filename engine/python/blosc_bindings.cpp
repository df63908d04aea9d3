// Python binding of blosc_decompress (base/blosc.h): an OpenVDB file's Blosc chunks, which the
// add-on's reader (export/vdb.py) hands over; Blender's Python has no Blosc of its own.
#include "base/blosc.h"
#include "python/bindings.h"

#include <string>

namespace py = pybind11;

namespace ppm::python {

void bind_blosc(py::module_& m) {
  m.def(
      "blosc_decompress",
      [](const py::bytes& chunk) {
        const std::string in = chunk;  // (a copy: the GIL is released below)
        std::vector<uint8_t> out;
        {
          py::gil_scoped_release unlocked;
          out = blosc_decompress(reinterpret_cast<const uint8_t*>(in.data()), in.size());
        }
        return py::bytes(reinterpret_cast<const char*>(out.data()), out.size());
      },
      py::arg("chunk"),
      "A Blosc1 chunk of LZ4 blocks (as OpenVDB writes grid values) decompressed; ValueError for another "
      "codec or a corrupt chunk.");
}

}  // namespace ppm::python
