// Texture storage and lookup (see texture.h).
#include "shading/texture.h"

#include "math/half.h"

#include <algorithm>
#include <array>
#include <limits>

namespace ppm {
namespace {

const std::array<float, 256>& srgb_decode() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[i] = static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table;
}

const std::array<float, 256>& linear_decode() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = static_cast<float>(i / 255.0);
    return t;
  }();
  return table;
}

uint8_t to_byte(float v) { return static_cast<uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); }

// Comparisons with NaN are false, so these also refuse NaN.
bool usable_colour(float v) { return v >= 0.0f && v <= std::numeric_limits<float>::max(); }
bool usable_alpha(float v) { return std::fabs(v) <= std::numeric_limits<float>::max(); }

bool usable_row(const std::vector<float>& rgba) {
  bool usable = true;
  for (size_t j = 0; j < rgba.size(); ++j) usable &= (j % 4 == 3) ? usable_alpha(rgba[j]) : usable_colour(rgba[j]);
  return usable;
}

}  // namespace

Texture::Texture(int width, int height, TexelStorage storage) : width_(width), height_(height), storage_(storage) {
  const size_t values = static_cast<size_t>(width) * height * 4;
  if (storage == TexelStorage::Half) {
    halves_.resize(values);
  } else {
    bytes_.resize(values);
    decode_ = (storage == TexelStorage::Srgb8 ? srgb_decode() : linear_decode()).data();
  }
}

Texture Texture::from_bytes(int width, int height, int channels, const uint8_t* texels, TexelStorage storage) {
  Texture t(width, height, storage == TexelStorage::Half ? TexelStorage::Linear8 : storage);
  const size_t count = static_cast<size_t>(width) * height;
  if (channels == 4) {
    std::copy(texels, texels + count * 4, t.bytes_.begin());
  } else {
    for (size_t i = 0; i < count; ++i) {
      std::copy(texels + i * channels, texels + i * channels + 3, &t.bytes_[i * 4]);
      t.bytes_[i * 4 + 3] = 255;
    }
  }
  t.max_rgb_ = t.decode_[t.max_byte()];
  return t;
}

Texture Texture::from_floats(int width, int height, int channels, const float* texels, TexelStorage storage) {
  Texture t(width, height, storage);
  const size_t count = static_cast<size_t>(width) * height;
  // Row by row: a check and a conversion that the compiler vectorizes, and a
  // slow pass over the rare row that holds an unusable texel.
  std::vector<float> row(static_cast<size_t>(width) * 4);
  for (size_t first = 0; first < count; first += width) {
    const float* in = texels + first * channels;
    if (channels == 4) {
      std::copy(in, in + row.size(), row.begin());
    } else {
      for (int x = 0; x < width; ++x) std::copy(in + x * 3, in + x * 3 + 3, &row[x * 4]), row[x * 4 + 3] = 1.0f;
    }
    if (!usable_row(row)) t.clear_unusable(first, row);
    if (storage == TexelStorage::Half) {
      uint16_t* out = &t.halves_[first * 4];
      for (size_t j = 0; j < row.size(); ++j) out[j] = to_half(row[j]);
    } else {
      uint8_t* out = &t.bytes_[first * 4];
      for (size_t j = 0; j < row.size(); ++j) out[j] = to_byte(row[j]);
    }
  }
  t.max_rgb_ = storage == TexelStorage::Half ? t.max_half() : t.decode_[t.max_byte()];
  return t;
}

void Texture::clear_unusable(size_t first, std::vector<float>& row) {
  for (size_t x = 0; x < row.size() / 4; ++x) {
    float* rgba = &row[x * 4];
    if (usable_colour(rgba[0]) && usable_colour(rgba[1]) && usable_colour(rgba[2]) && usable_alpha(rgba[3]))
      continue;
    note_unusable(first + x, rgba);
    if (std::isfinite(rgba[0]) && std::isfinite(rgba[1]) && std::isfinite(rgba[2]) && std::isfinite(rgba[3])) {
      ++negative_;
      for (int c = 0; c < 3; ++c) most_negative_ = std::min(most_negative_, rgba[c]), rgba[c] = std::fmax(rgba[c], 0.0f);
    } else {
      ++not_finite_;
      rgba[0] = rgba[1] = rgba[2] = 0.0f, rgba[3] = 1.0f;
    }
  }
}

void Texture::note_unusable(size_t texel, const float rgba[4]) {
  if (not_finite_ + negative_ > 0) return;
  int c = 0;
  while (c < 3 && usable_colour(rgba[c])) ++c;
  first_unusable_ = UnusableTexel{static_cast<int>(texel % width_), static_cast<int>(texel / width_), rgba[c]};
}

float Texture::max_half() const {
  // Colours are not negative (-0 at most): without the sign bit, the largest bits are the largest value.
  uint32_t h = 0;
  for (size_t i = 0; i < halves_.size(); ++i)
    if (i % 4 != 3) h = std::max<uint32_t>(h, halves_[i] & 0x7fffu);
  return from_half(static_cast<uint16_t>(h));
}

uint8_t Texture::max_byte() const {
  uint8_t b = 0;
  for (size_t i = 0; i < bytes_.size(); i += 4) b = std::max({b, bytes_[i], bytes_[i + 1], bytes_[i + 2]});
  return b;
}

}  // namespace ppm

namespace ppm {
namespace {

// Texel indices and weights along one axis at coordinate u: up to 4 taps; an index of -1 is
// outside a clipped image and reads as transparent black, so a clipped image fades out over the
// half texel beyond its edge, as in Cycles.
struct Taps {
  int count = 0;
  std::array<int, 4> index{};
  std::array<double, 4> weight{};
};

int extend_index(int i, int n, TextureExtension extension) {
  switch (extension) {
    case TextureExtension::Repeat: return ((i % n) + n) % n;
    case TextureExtension::Extend: return std::clamp(i, 0, n - 1);
    case TextureExtension::Clip: return i >= 0 && i < n ? i : -1;
    case TextureExtension::Mirror: {
      const int period = 2 * n, m = ((i % period) + period) % period;
      return m < n ? m : period - 1 - m;
    }
  }
  return 0;
}

Taps taps(double u, int n, TextureInterpolation interpolation, TextureExtension extension) {
  Taps t;
  if (!std::isfinite(u)) u = 0.0;
  if (extension == TextureExtension::Repeat) u -= std::floor(u);
  const double x = u * n;
  if (interpolation == TextureInterpolation::Closest) {
    t.count = 1;
    t.index[0] = extend_index(static_cast<int>(std::floor(std::clamp(x, -1e9, 1e9))), n, extension);
    t.weight[0] = 1.0;
    return t;
  }
  const double c = std::clamp(x - 0.5, -1e9, 1e9), f = std::floor(c), a = c - f;
  const int i = static_cast<int>(f);
  if (interpolation == TextureInterpolation::Linear) {
    t.count = 2;
    t.index = {extend_index(i, n, extension), extend_index(i + 1, n, extension), 0, 0};
    t.weight = {1.0 - a, a, 0.0, 0.0};
    return t;
  }
  // Cubic B-spline, as Cycles' cubic interpolation.
  const double a2 = a * a, a3 = a2 * a;
  t.count = 4;
  for (int k = 0; k < 4; ++k) t.index[k] = extend_index(i - 1 + k, n, extension);
  t.weight = {(1.0 - a) * (1.0 - a) * (1.0 - a) / 6.0, (3.0 * a3 - 6.0 * a2 + 4.0) / 6.0,
              (-3.0 * a3 + 3.0 * a2 + 3.0 * a + 1.0) / 6.0, a3 / 6.0};
  return t;
}

}  // namespace

glm::dvec4 Texture::sample(const Vec2& uv, TextureInterpolation interpolation, TextureExtension extension) const {
  const Taps tx = taps(uv.x, width_, interpolation, extension), ty = taps(uv.y, height_, interpolation, extension);
  const bool srgb = storage_ == TexelStorage::Srgb8;
  glm::dvec4 sum(0.0);
  for (int j = 0; j < ty.count; ++j) {
    if (ty.index[j] < 0) continue;
    for (int i = 0; i < tx.count; ++i) {
      if (tx.index[i] < 0) continue;
      const int x = tx.index[i], y = ty.index[j];
      const Color c = srgb ? encoded(x, y) : texel(x, y);
      sum += tx.weight[i] * ty.weight[j] * glm::dvec4(c, alpha(x, y));
    }
  }
  return srgb ? glm::dvec4(srgb_to_linear(glm::max(Color(sum), Color(0.0))), sum.w) : sum;
}

}  // namespace ppm
