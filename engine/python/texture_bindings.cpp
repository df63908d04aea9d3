// Python bindings of the scene's textures: images from numpy arrays or memoryviews (bytes kept as
// bytes, anything else as float32), what the scene made of them, and their removal.
#include "python/bindings.h"
#include "python/convert.h"

namespace py = pybind11;
using namespace ppm;
using namespace ppm::py_convert;

namespace {

// The pixels' shape and type checked before anything is copied.
py::array checked_pixels(const py::object& pixels, const std::string& what) {
  const py::array raw = array_or_null<py::array>(pixels);
  // Shape first, before a copy to float32 of something that cannot be a texture.
  if (!raw) fail(what, "pixels must be an array of shape (H, W, 4) or (H, W, 3)");
  if (raw.ndim() != 3 || (raw.shape(2) != 4 && raw.shape(2) != 3))
    fail(what, "pixels must have shape (H, W, 4) or (H, W, 3)");
  if (raw.shape(0) < 1 || raw.shape(1) < 1) fail(what, "width and height must be positive");
  if (raw.shape(0) > (1 << 20) || raw.shape(1) > (1 << 20)) fail(what, "width and height must be at most 1048576 pixels");
  const char kind = raw.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    fail(what, std::string("pixels must be real numbers, not dtype kind '") + kind + "'");
  return raw;
}

// The storage asked for, or the default: bytes for byte pixels, half floats for others.
TexelStorage storage_from(const py::object& storage_name, bool bytes, const std::string& what) {
  if (!storage_name.is_none() && !py::isinstance<py::str>(storage_name))
    fail(what, "storage must be 'srgb8', 'linear8' or 'half'");
  const TexelStorage storage =
      storage_name.is_none() ? (bytes ? TexelStorage::Srgb8 : TexelStorage::Half)
                             : choice<TexelStorage>(py::cast<std::string>(storage_name),
                                                    {{"srgb8", TexelStorage::Srgb8},
                                                     {"linear8", TexelStorage::Linear8},
                                                     {"half", TexelStorage::Half}},
                                                    what, "storage");
  if (bytes && storage == TexelStorage::Half) fail(what, "byte pixels are stored as bytes: storage 'srgb8' or 'linear8'");
  return storage;
}

// Byte pixels are kept as bytes (a memoryview of a Blender ImBuf, or uint8 numpy); anything else
// becomes float32 (no copy if it already is) and is converted to the storage. The conversion runs
// without the GIL.
uint32_t add_texture(Scene& s, const std::string& name, const py::object& pixels, const py::object& storage_name,
                     bool clear_unusable) {
  using ByteArray = py::array_t<uint8_t, py::array::c_style>;
  using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
  const std::string what = "texture '" + checked_name(name, "texture") + "'";
  const py::array raw = checked_pixels(pixels, what);
  const bool bytes = raw.dtype().is(py::dtype::of<uint8_t>());
  const TexelStorage storage = storage_from(storage_name, bytes, what);
  const int width = static_cast<int>(raw.shape(1)), height = static_cast<int>(raw.shape(0));
  const int channels = static_cast<int>(raw.shape(2));
  if (bytes) {
    const ByteArray a = ByteArray::ensure(raw);  // a copy only if not C-contiguous
    py::gil_scoped_release unlocked;
    return s.add_texture(name, Texture::from_bytes(width, height, channels, a.data(), storage), clear_unusable);
  }
  const FloatArray a = array_or_null<FloatArray>(raw);
  if (!a) fail(what, "pixels must be an array of numbers");
  py::gil_scoped_release unlocked;
  return s.add_texture(name, Texture::from_floats(width, height, channels, a.data(), storage), clear_unusable);
}

py::dict texture_info(const Scene& s, uint32_t index) {
  if (index >= s.textures().size()) throw py::index_error("texture index out of range");
  const Texture& t = s.textures()[index];
  const char* storage = t.storage() == TexelStorage::Half    ? "half"
                        : t.storage() == TexelStorage::Srgb8 ? "srgb8"
                                                             : "linear8";
  py::dict d;
  d["width"] = t.width(), d["height"] = t.height(), d["storage"] = storage, d["bytes"] = t.bytes();
  d["max_rgb"] = t.max_rgb(), d["not_finite_texels"] = t.not_finite_texels();
  d["negative_texels"] = t.negative_texels(), d["most_negative"] = t.most_negative();
  return d;
}

}  // namespace

namespace ppm::python {

void bind_textures(SceneClass& c) {
  c.def("add_texture", &add_texture, py::arg("name"), py::arg("pixels"), py::arg("storage") = py::none(),
        py::arg("clear_unusable") = false,
        "Adds an RGBA or RGB texture of shape (H, W, 4) or (H, W, 3), row 0 at the bottom; returns its "
        "index. storage: 'srgb8' (sRGB-encoded bytes; the default for uint8 pixels), 'linear8', or 'half' "
        "(linear half floats; the default for other pixels). Float pixels stored as bytes are quantized "
        "(round(v * 255)). A texel with a negative, NaN or Inf colour (or a NaN or Inf alpha) is an "
        "error; with clear_unusable=True a texel with NaN or Inf is stored black and negative colour "
        "channels as 0, counted in texture_info().");
  c.def("texture_info", &texture_info, py::arg("index"),
        "width, height, storage, bytes, max_rgb, not_finite_texels, negative_texels and most_negative "
        "of texture `index`.");
  c.def("remove_textures_from", &Scene::remove_textures_from, py::arg("count"),
        "Removes the textures from index `count` on (a world's, to be exported again); refused "
        "(ValueError) while a material uses one. The world is black until set again; a built scene keeps "
        "its BVH.");
  c.def_property_readonly("texture_count", [](const Scene& s) { return s.textures().size(); },
                          "How many textures the scene holds.");
}

}  // namespace ppm::python
