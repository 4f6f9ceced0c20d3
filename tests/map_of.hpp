// Synthetic environment maps for the envmap and probe tests.
#pragma once

#include <cstddef>

#include "envmap/envmap.hpp"

namespace sglab::test {

// A width × width/2 map whose pixels hold f(pixel centre direction), RGB.
template <class F>
envmap::Map map_of(std::size_t width, F f) {
  envmap::Map m;
  m.width = width;
  m.height = width / 2;
  m.rgb.resize(m.width * m.height * 3);
  for (std::size_t j = 0; j < m.height; ++j)
    for (std::size_t i = 0; i < m.width; ++i) {
      const envmap::Vec3 v = f(envmap::pixel_direction(m, i, j));
      for (std::size_t ch = 0; ch < 3; ++ch)
        m.rgb[(j * m.width + i) * 3 + ch] = static_cast<float>(v[ch]);
    }
  return m;
}

}  // namespace sglab::test
