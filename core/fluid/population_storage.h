#pragma once
// One or two structure-of-arrays buffers of Q populations per cell, 64-byte aligned, with each
// population's array padded so that successive arrays start on different cache sets.
//
// Without the padding, a cell count times sizeof(real) that is a multiple of a large power of two
// (96^3 doubles, 2^21 floats, ...) puts all 2Q arrays on the same cache sets, and the kernel
// thrashes: measured on a D3Q19 in-place sweep over 96^3 doubles, 51 MLUPS unpadded, 133 padded.
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>

namespace lbsolid::fluid {

template <class T>
class PopulationStorage {
 public:
  PopulationStorage(int buffers, int q, long cells)
      : buffers_(buffers), q_(q), stride_(padded_stride(cells)) {
    const std::size_t bytes = this->bytes();
    data_.reset(static_cast<T*>(std::aligned_alloc(kAlign, bytes)));
    if (!data_) throw std::bad_alloc();
    for (std::size_t k = 0; k < bytes / sizeof(T); ++k) data_.get()[k] = T(0);
  }

  // Distance in elements between population i and i+1 of one buffer.
  long stride() const { return stride_; }
  std::size_t bytes() const { return static_cast<std::size_t>(buffers_) * q_ * stride_ * sizeof(T); }
  T* buffer(int which) { return data_.get() + static_cast<std::size_t>(which) * q_ * stride_; }
  const T* buffer(int which) const { return data_.get() + static_cast<std::size_t>(which) * q_ * stride_; }

 private:
  static constexpr std::size_t kAlign = 64;
  // Round the array up to 64 KiB, then add 17 cache lines: array k starts 17 k lines past a 64 KiB
  // boundary, a distinct set for every k < 64 in a 4 KiB-way L1 and k < 1024 in a 64 KiB-way L2.
  static long padded_stride(long cells) {
    const long per_64k = 65536 / static_cast<long>(sizeof(T));
    const long lines = 17 * 64 / static_cast<long>(sizeof(T));
    return (cells + per_64k - 1) / per_64k * per_64k + lines;
  }
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  int buffers_;
  int q_;
  long stride_;
  std::unique_ptr<T, Free> data_;
};

}  // namespace lbsolid::fluid
