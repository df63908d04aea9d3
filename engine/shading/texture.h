// An RGBA image sampled bilinearly with repeat wrapping, kept in the compact
// form its source has (8-bit sRGB-encoded or linear bytes, or half floats) and
// decoded to linear colour on lookup: a 16k x 16k 8-bit texture takes 1 GiB,
// not the 4 GiB of float32. sRGB bytes are interpolated as encoded and the
// result decoded, as Cycles does (its NODE_IMAGE_COMPRESS_AS_SRGB): between
// texels of different colours that is darker than mixing linear colours. Row 0
// is the bottom of the image (Blender's convention), so v = 0 is row 0.
#pragma once

#include "math/half.h"
#include "math/types.h"


#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace ppm {

enum class TexelStorage : uint8_t {
  Srgb8,    // bytes, sRGB-encoded (Blender's byte images in the sRGB colour space)
  Linear8,  // bytes, linear (Non-Color and linear byte images)
  Half,     // half floats, linear (Blender's float images)
};

// A texel that cannot be used as it is: a colour channel that is NaN, infinite
// or negative, or an alpha that is not finite. Unless the scene refuses it, a
// texel with a value that is not finite is stored black, and negative colour
// channels are stored as 0 (HDR images often hold tiny negative values).
struct UnusableTexel {
  int x = 0, y = 0;
  float value = 0.0f;  // the offending channel
};

// What of a texture a material input reads (Blender's Image Texture outputs): its colour, its alpha,
// or grey (Cycles' colour-to-float conversion; NodeProgram::add_image_output).
enum class TextureChannel : uint8_t { Rgb, Alpha, Grey };

// Blender's Image Texture node: how texels are blended (Smart is Cubic, as Cycles renders it) and
// what lies outside [0, 1] (Clip: transparent black).
enum class TextureInterpolation : uint8_t { Linear, Closest, Cubic };
enum class TextureExtension : uint8_t { Repeat, Extend, Clip, Mirror };

class Texture {
 public:
  // `channels` (3 or 4) values per texel, rows bottom first. Bytes are stored
  // as they are. Floats are quantized to bytes for the 8-bit storages
  // (round(v * 255), exact for floats that came from bytes, as Blender's
  // Image.pixels of a byte image do) or converted to half (clamped to 65504).
  static Texture from_bytes(int width, int height, int channels, const uint8_t* texels, TexelStorage storage);
  static Texture from_floats(int width, int height, int channels, const float* texels, TexelStorage storage);

  int width() const { return width_; }
  size_t memory_bytes() const { return bytes_.capacity() + halves_.capacity() * sizeof(uint16_t); }
  int height() const { return height_; }
  TexelStorage storage() const { return storage_; }
  size_t bytes() const { return bytes_.size() + 2 * halves_.size(); }
  float max_rgb() const { return max_rgb_; }  // largest colour component (its gain as an albedo)
  size_t unusable_texels() const { return not_finite_ + negative_; }
  size_t not_finite_texels() const { return not_finite_; }  // stored black
  size_t negative_texels() const { return negative_; }      // negative channels stored as 0
  float most_negative() const { return most_negative_; }
  const UnusableTexel& first_unusable() const { return first_unusable_; }

  // Repeats in u; in v too, or with clamp_v (environment maps: the poles) clamps.
  Color lookup(const Vec2& uv, bool clamp_v = false) const {
    if (storage_ == TexelStorage::Srgb8)
      return srgb_to_linear(bilinear<Color>(uv, clamp_v, [this](int x, int y) { return encoded(x, y); }));
    return bilinear<Color>(uv, clamp_v, [this](int x, int y) { return texel(x, y); });
  }
  // The colour and alpha at uv as the Image Texture node reads it with these settings.
  glm::dvec4 sample(const Vec2& uv, TextureInterpolation interpolation, TextureExtension extension) const;

 private:
  Texture(int width, int height, TexelStorage storage);
  static int wrap(int i, int n) { return ((i % n) + n) % n; }
  template <class Value, class Texel>
  Value bilinear(const Vec2& uv, bool clamp_v, Texel&& at) const {
    const double x = (uv.x - std::floor(uv.x)) * width_ - 0.5;
    const double y = (clamp_v ? std::clamp(uv.y, 0.0, 1.0) : uv.y - std::floor(uv.y)) * height_ - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    const int x0 = wrap(static_cast<int>(fx), width_), x1 = wrap(x0 + 1, width_);
    int y0 = wrap(static_cast<int>(fy), height_), y1 = wrap(y0 + 1, height_);
    if (clamp_v) {
      y0 = std::clamp(static_cast<int>(fy), 0, height_ - 1);
      y1 = std::clamp(static_cast<int>(fy) + 1, 0, height_ - 1);
    }
    return (1 - ax) * (1 - ay) * at(x0, y0) + ax * (1 - ay) * at(x1, y0) + (1 - ax) * ay * at(x0, y1) +
           ax * ay * at(x1, y1);
  }
  size_t index(int x, int y) const { return (static_cast<size_t>(y) * width_ + x) * 4; }
  Color texel(int x, int y) const;
  Color encoded(int x, int y) const {  // the bytes / 255, for the 8-bit storages
    const size_t i = index(x, y);
    return Color(bytes_[i], bytes_[i + 1], bytes_[i + 2]) * (1.0 / 255.0);
  }
  static Color srgb_to_linear(const Color& c) {
    auto decode = [](double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
    return Color(decode(c.x), decode(c.y), decode(c.z));
  }
  double alpha(int x, int y) const {
    const size_t i = index(x, y) + 3;
    return storage_ == TexelStorage::Half ? from_half(halves_[i]) : bytes_[i] / 255.0;
  }
  void clear_unusable(size_t first_texel, std::vector<float>& row);  // see UnusableTexel
  void note_unusable(size_t texel, const float rgba[4]);
  uint8_t max_byte() const;  // of the colour channels
  float max_half() const;

  int width_ = 0, height_ = 0;
  TexelStorage storage_ = TexelStorage::Srgb8;
  const float* decode_ = nullptr;  // byte -> linear value, for the 8-bit storages
  std::vector<uint8_t> bytes_;     // RGBA, 8-bit storages
  std::vector<uint16_t> halves_;   // RGBA, Half
  float max_rgb_ = 0.0f;
  size_t not_finite_ = 0, negative_ = 0;
  float most_negative_ = 0.0f;
  UnusableTexel first_unusable_;
};

inline Color Texture::texel(int x, int y) const {
  const size_t i = index(x, y);
  if (storage_ == TexelStorage::Half)
    return Color(from_half(halves_[i]), from_half(halves_[i + 1]), from_half(halves_[i + 2]));
  return Color(decode_[bytes_[i]], decode_[bytes_[i + 1]], decode_[bytes_[i + 2]]);
}

}  // namespace ppm
