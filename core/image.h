// Plain images for the interfaces between modules (no OpenCV in headers):
// row-major, interleaved channels, origin at the top-left pixel.
#pragma once

#include <cstdint>
#include <vector>

namespace aerograsp {

/// A width x height image with C interleaved channels of type T.
template <typename T, int C>
struct Image {
  static constexpr int kChannels = C;
  int width = 0;
  int height = 0;
  std::vector<T> data;  ///< width * height * C values, row after row

  Image() = default;
  Image(int w, int h, T fill = T{}) : width(w), height(h), data(std::size_t(w) * h * C, fill) {}

  bool empty() const { return data.empty(); }
  T* Row(int y) { return data.data() + std::size_t(y) * width * C; }
  const T* Row(int y) const { return data.data() + std::size_t(y) * width * C; }
  T& at(int x, int y, int c = 0) { return data[(std::size_t(y) * width + x) * C + c]; }
  const T& at(int x, int y, int c = 0) const { return data[(std::size_t(y) * width + x) * C + c]; }
  bool operator==(const Image& other) const {
    return width == other.width && height == other.height && data == other.data;
  }
};

using ColorImage = Image<std::uint8_t, 3>;   ///< RGB, 8 bits per channel
using DepthImage = Image<std::uint16_t, 1>;  ///< depth in units of a depth scale; 0 = no data
using FloatImage = Image<float, 1>;

}  // namespace aerograsp
