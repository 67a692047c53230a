#pragma once
// PNG bytes decoded to RGB with stb_image, for tests that check pixels. The including file picks
// how stb_image is compiled (STB_IMAGE_IMPLEMENTATION, STB_IMAGE_STATIC) before including this.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <stb_image.h>

namespace clipray::testing {

// Rgb: the test's colour type, built from three channel values.
template <typename Rgb>
struct DecodedPng {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  // (x, y) with y from the top, as PNG stores rows.
  Rgb at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

// Fails the test (and returns an empty image) when the bytes are no PNG.
template <typename Rgb>
DecodedPng<Rgb> decodePng(const std::string& png) {
  DecodedPng<Rgb> out;
  int comp = 0;
  stbi_uc* data =
      stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(png.data()),
                            static_cast<int>(png.size()), &out.width, &out.height, &comp, 3);
  if (data == nullptr) {
    ADD_FAILURE() << "PNG did not decode: " << stbi_failure_reason();
    return out;
  }
  out.rgb.assign(data, data + static_cast<std::size_t>(out.width) * out.height * 3);
  stbi_image_free(data);
  return out;
}

}  // namespace clipray::testing
