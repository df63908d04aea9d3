// Blender's colour nodes in float as Cycles evaluates them: the Mix node's blend modes (and the
// older MixRGB's), HSV and HSL conversions, Hue/Saturation/Value, Invert, Gamma, Bright/Contrast.
#pragma once

#include "math/types.h"

#include <algorithm>
#include <cmath>

namespace ppm::nodes {

enum class MixBlend : uint8_t {
  Mix, Add, Multiply, Screen, Overlay, Subtract, Divide, Difference, Exclusion, Darken, Lighten,
  Dodge, Burn, Hue, Saturation, Value, Color, SoftLight, LinearLight,
};

inline Vec3f rgb_to_hsv(const Vec3f& rgb) {
  const float cmax = std::max(rgb.x, std::max(rgb.y, rgb.z));
  const float cmin = std::min(rgb.x, std::min(rgb.y, rgb.z));
  const float delta = cmax - cmin;
  const float s = cmax != 0.0f ? delta / cmax : 0.0f;
  float h = 0.0f;
  if (s != 0.0f) {
    const Vec3f c = (Vec3f(cmax) - rgb) / delta;
    if (rgb.x == cmax) h = c.z - c.y;
    else if (rgb.y == cmax) h = 2.0f + c.x - c.z;
    else h = 4.0f + c.y - c.x;
    h /= 6.0f;
    if (h < 0.0f) h += 1.0f;
  }
  return Vec3f(h, s, cmax);
}

inline Vec3f hsv_to_rgb(const Vec3f& hsv) {
  float h = hsv.x;
  const float s = hsv.y, v = hsv.z;
  if (s == 0.0f) return Vec3f(v);
  if (h == 1.0f) h = 0.0f;
  h *= 6.0f;
  const float i = std::floor(h), f = h - i;
  const float p = v * (1.0f - s), q = v * (1.0f - s * f), t = v * (1.0f - s * (1.0f - f));
  switch (static_cast<int>(i)) {
    case 0: return Vec3f(v, t, p);
    case 1: return Vec3f(q, v, p);
    case 2: return Vec3f(p, v, t);
    case 3: return Vec3f(p, q, v);
    case 4: return Vec3f(t, p, v);
    default: return Vec3f(v, p, q);
  }
}

inline Vec3f rgb_to_hsl(const Vec3f& rgb) {
  const float cmax = std::max(rgb.x, std::max(rgb.y, rgb.z));
  const float cmin = std::min(rgb.x, std::min(rgb.y, rgb.z));
  const float l = std::min(1.0f, (cmax + cmin) / 2.0f);
  if (cmax == cmin) return Vec3f(0.0f, 0.0f, l);
  const float d = cmax - cmin;
  const float s = l > 0.5f ? d / (2.0f - cmax - cmin) : d / (cmax + cmin);
  float h;
  if (cmax == rgb.x) h = (rgb.y - rgb.z) / d + (rgb.y < rgb.z ? 6.0f : 0.0f);
  else if (cmax == rgb.y) h = (rgb.z - rgb.x) / d + 2.0f;
  else h = (rgb.x - rgb.y) / d + 4.0f;
  return Vec3f(h / 6.0f, s, l);
}

inline Vec3f hsl_to_rgb(const Vec3f& hsl) {
  const float h = hsl.x, s = hsl.y, l = hsl.z;
  const Vec3f n(std::clamp(std::fabs(h * 6.0f - 3.0f) - 1.0f, 0.0f, 1.0f),
                std::clamp(2.0f - std::fabs(h * 6.0f - 2.0f), 0.0f, 1.0f),
                std::clamp(2.0f - std::fabs(h * 6.0f - 4.0f), 0.0f, 1.0f));
  const float chroma = (1.0f - std::fabs(2.0f * l - 1.0f)) * s;
  return (n - 0.5f) * chroma + l;
}

inline Vec3f dodge(const Vec3f& a, const Vec3f& b, float t) {
  Vec3f out = a;
  for (int k = 0; k < 3; ++k) {
    if (a[k] == 0.0f) continue;
    const float tmp = 1.0f - t * b[k];
    out[k] = tmp <= 0.0f ? 1.0f : std::min(a[k] / tmp, 1.0f);
  }
  return out;
}

inline Vec3f burn(const Vec3f& a, const Vec3f& b, float t) {
  Vec3f out;
  for (int k = 0; k < 3; ++k) {
    const float tmp = (1.0f - t) + t * b[k];
    out[k] = tmp <= 0.0f ? 0.0f : std::clamp(1.0f - (1.0f - a[k]) / tmp, 0.0f, 1.0f);
  }
  return out;
}

// a with the HSV components of b where `take` says (hue, saturation), mixed by t.
inline Vec3f blend_hue_saturation(const Vec3f& a, const Vec3f& b, float t, bool saturation_too) {
  const Vec3f hb = rgb_to_hsv(b);
  if (hb.y == 0.0f) return a;
  Vec3f ha = rgb_to_hsv(a);
  ha.x = hb.x;
  if (saturation_too) ha.y = hb.y;
  return glm::mix(a, hsv_to_rgb(ha), t);
}

inline Vec3f mix_blend(MixBlend mode, float t, const Vec3f& a, const Vec3f& b) {
  const float tm = 1.0f - t;
  switch (mode) {
    case MixBlend::Mix: return glm::mix(a, b, t);
    case MixBlend::Add: return a + t * b;
    case MixBlend::Multiply: return a * (Vec3f(tm) + t * b);
    case MixBlend::Screen: return Vec3f(1.0f) - (Vec3f(tm) + t * (Vec3f(1.0f) - b)) * (Vec3f(1.0f) - a);
    case MixBlend::Overlay: {
      Vec3f out;
      for (int k = 0; k < 3; ++k)
        out[k] = a[k] < 0.5f ? a[k] * (tm + 2.0f * t * b[k]) : 1.0f - (tm + 2.0f * t * (1.0f - b[k])) * (1.0f - a[k]);
      return out;
    }
    case MixBlend::Subtract: return a - t * b;
    case MixBlend::Divide: {
      Vec3f out = a;
      for (int k = 0; k < 3; ++k)
        if (b[k] != 0.0f) out[k] = tm * a[k] + t * a[k] / b[k];
      return out;
    }
    case MixBlend::Difference: return glm::mix(a, glm::abs(a - b), t);
    case MixBlend::Exclusion: return glm::max(glm::mix(a, a + b - 2.0f * a * b, t), Vec3f(0.0f));
    case MixBlend::Darken: return glm::mix(a, glm::min(a, b), t);
    case MixBlend::Lighten: return glm::mix(a, glm::max(a, b), t);
    case MixBlend::Dodge: return dodge(a, b, t);
    case MixBlend::Burn: return burn(a, b, t);
    case MixBlend::Hue: return blend_hue_saturation(a, b, t, false);
    case MixBlend::Saturation: {
      Vec3f ha = rgb_to_hsv(a);
      if (ha.y == 0.0f) return a;
      ha.y = tm * ha.y + t * rgb_to_hsv(b).y;
      return hsv_to_rgb(ha);
    }
    case MixBlend::Value: {
      Vec3f ha = rgb_to_hsv(a);
      ha.z = tm * ha.z + t * rgb_to_hsv(b).z;
      return hsv_to_rgb(ha);
    }
    case MixBlend::Color: return blend_hue_saturation(a, b, t, true);
    case MixBlend::SoftLight: {
      const Vec3f screen = Vec3f(1.0f) - (Vec3f(1.0f) - b) * (Vec3f(1.0f) - a);
      return tm * a + t * ((Vec3f(1.0f) - a) * b * a + a * screen);
    }
    case MixBlend::LinearLight: return a + t * (2.0f * b - Vec3f(1.0f));
  }
  return a;
}

// Hue/Saturation/Value node: hue shifted (0.5 = none), saturation and value scaled, mixed by fac.
inline Vec3f hue_saturation_value(float hue, float saturation, float value, float fac, const Vec3f& color) {
  Vec3f hsv = rgb_to_hsv(color);
  hsv.x = hsv.x + hue + 0.5f;
  hsv.x -= std::floor(hsv.x);
  hsv.y = std::clamp(hsv.y * saturation, 0.0f, 1.0f);
  hsv.z *= value;
  const Vec3f out = hsv_to_rgb(hsv);
  return glm::max(fac * out + (1.0f - fac) * color, Vec3f(0.0f));
}

inline Vec3f invert(float fac, const Vec3f& color) { return glm::mix(color, Vec3f(1.0f) - color, fac); }

inline Vec3f gamma(const Vec3f& color, float g) {
  if (g == 0.0f) return Vec3f(1.0f);
  Vec3f out = color;
  for (int k = 0; k < 3; ++k)
    if (color[k] > 0.0f) out[k] = std::pow(color[k], g);
  return out;
}

inline Vec3f bright_contrast(const Vec3f& color, float bright, float contrast) {
  const float a = 1.0f + contrast, b = bright - contrast * 0.5f;
  return glm::max(a * color + Vec3f(b), Vec3f(0.0f));
}

// Cycles' colour-to-float conversion: the Y row of Blender's scene-linear (Rec. 709, D65) to XYZ
// matrix, which Blender 5.0's colour configuration gives more precisely than 3.x-4.x's (fitted to
// each Cycles' RGB to BW: 0.212639, 0.715169, 0.072193 in 5.0; 0.212673, 0.715152, 0.072175 in 3.4,
// 4.2 and 4.5).
inline float rgb_to_grey(const Vec3f& c) {
  return 0.2126390059f * c.x + 0.7151686788f * c.y + 0.0721923154f * c.z;
}
inline float rgb_to_grey_before_5(const Vec3f& c) {
  return 0.2126729f * c.x + 0.7151522f * c.y + 0.0721750f * c.z;
}

}  // namespace ppm::nodes
