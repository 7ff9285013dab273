#pragma once
// One or two structure-of-arrays buffers of Q populations per cell, 64-byte aligned, with each
// population's array padded so that successive arrays start on different cache sets.
//
// Without the padding, a cell count times sizeof(real) that is a multiple of a large power of two
// (96^3 doubles, 2^21 floats, ...) puts all 2Q arrays on the same cache sets, and the kernel
// thrashes: measured on a D3Q19 in-place sweep over 96^3 doubles, 51 MLUPS unpadded, 133 padded.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>

namespace lbsolid::fluid {

template <class T>
class PopulationStorage {
 public:
  PopulationStorage(int buffers, int q, long cells)
      : buffers_(buffers), q_(q), stride_(padded_stride(cells)) {
    // Zeroed by calloc: a large block comes as fresh pages that are zero already, so the cells are
    // first written (and the pages faulted in) by the lattice's initialization, not by a memset
    // before it (a quarter of building a 192^3 D3Q19 lattice). aligned_alloc has no zeroing form:
    // the block is over-allocated and its first 64-byte boundary taken.
    block_.reset(std::calloc(bytes() + kAlign, 1));
    if (!block_) throw std::bad_alloc();
    const std::uintptr_t address = reinterpret_cast<std::uintptr_t>(block_.get());
    data_ = reinterpret_cast<T*>((address + kAlign - 1) / kAlign * kAlign);
  }

  // Distance in elements between population i and i+1 of one buffer.
  long stride() const { return stride_; }
  std::size_t bytes() const { return static_cast<std::size_t>(buffers_) * q_ * stride_ * sizeof(T); }
  T* buffer(int which) { return data_ + static_cast<std::size_t>(which) * q_ * stride_; }
  const T* buffer(int which) const { return data_ + static_cast<std::size_t>(which) * q_ * stride_; }

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
    void operator()(void* p) const { std::free(p); }
  };
  int buffers_;
  int q_;
  long stride_;
  std::unique_ptr<void, Free> block_;
  T* data_ = nullptr;  // block_'s first 64-byte boundary
};

}  // namespace lbsolid::fluid
