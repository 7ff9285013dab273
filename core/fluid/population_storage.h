#pragma once
// One or two buffers of Q populations per cell, 64-byte aligned, in one of two layouts:
// - arrays: Q arrays of cells (structure of arrays), each padded so that successive arrays
//   start on different cache sets;
// - blocks: the cells in blocks of W = 64 / sizeof(T) (one cache line of one population), a
//   block's Q lines side by side: population i of cell c at (c / W) Q W + i W + c mod W. The
//   D3Q19 in-place kernels run faster on it (blocked_kernel.h); the cell count must be a
//   multiple of W, and one block of margin lies before and after the cells (the pulling step's
//   first and last rows read one slot there, and put it back).
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

enum class PopulationLayout { kArrays, kBlocks };

template <class T>
class PopulationStorage {
 public:
  static constexpr int kBlockCells = 64 / static_cast<int>(sizeof(T));  // W

  PopulationStorage(int buffers, int q, long cells, PopulationLayout layout = PopulationLayout::kArrays)
      : buffers_(buffers), q_(q), blocks_(layout == PopulationLayout::kBlocks),
        stride_(blocks_ ? cells + 2 * kBlockCells : padded_stride(cells)) {
    // Zeroed by calloc: a large block comes as fresh pages that are zero already, so the cells are
    // first written (and the pages faulted in) by the lattice's initialization, not by a memset
    // before it (a quarter of building a 192^3 D3Q19 lattice). aligned_alloc has no zeroing form:
    // the block is over-allocated and its first 64-byte boundary taken.
    block_.reset(std::calloc(bytes() + kAlign, 1));
    if (!block_) throw std::bad_alloc();
    const std::uintptr_t address = reinterpret_cast<std::uintptr_t>(block_.get());
    data_ = reinterpret_cast<T*>((address + kAlign - 1) / kAlign * kAlign);
  }

  PopulationLayout layout() const { return blocks_ ? PopulationLayout::kBlocks : PopulationLayout::kArrays; }
  // Arrays: the distance in elements between population i and i+1 of one buffer.
  long stride() const { return stride_; }
  // Where population i of `cell` lies in a buffer; the two below for code that knows the layout.
  long index(int i, long cell) const { return blocks_ ? index_in_blocks(i, cell) : index_in_arrays(i, cell); }
  long index_in_arrays(int i, long cell) const { return i * stride_ + cell; }
  long index_in_blocks(int i, long cell) const {
    return (cell / kBlockCells) * q_ * kBlockCells + i * kBlockCells + cell % kBlockCells;
  }
  // index_in_blocks(i, c + delta) less that of c's block start, for any cell c at `lane` (c mod W)
  // with c + delta a cell: a function of (i, delta, lane) alone, which callers tabulate.
  long offset_in_blocks(int i, long delta, int lane) const {
    const long from_start = lane + delta;  // cells from c's block start to c + delta
    const long blocks = from_start >= 0 ? from_start / kBlockCells : -((kBlockCells - 1 - from_start) / kBlockCells);
    return blocks * q_ * kBlockCells + i * kBlockCells + (from_start - blocks * kBlockCells);
  }
  std::size_t bytes() const { return static_cast<std::size_t>(buffers_) * q_ * stride_ * sizeof(T); }
  // The buffer's cell 0 (blocks: after the margin).
  T* buffer(int which) { return data_ + static_cast<std::size_t>(which) * q_ * stride_ + margin(); }
  const T* buffer(int which) const { return data_ + static_cast<std::size_t>(which) * q_ * stride_ + margin(); }

 private:
  static constexpr std::size_t kAlign = 64;
  // Round the array up to 64 KiB, then add 17 cache lines: array k starts 17 k lines past a 64 KiB
  // boundary, a distinct set for every k < 64 in a 4 KiB-way L1 and k < 1024 in a 64 KiB-way L2.
  static long padded_stride(long cells) {
    const long per_64k = 65536 / static_cast<long>(sizeof(T));
    const long lines = 17 * 64 / static_cast<long>(sizeof(T));
    return (cells + per_64k - 1) / per_64k * per_64k + lines;
  }
  long margin() const { return blocks_ ? static_cast<long>(q_) * kBlockCells : 0; }
  struct Free {
    void operator()(void* p) const { std::free(p); }
  };
  int buffers_;
  int q_;
  bool blocks_;
  long stride_;  // blocks: a buffer's length in elements over q_
  std::unique_ptr<void, Free> block_;
  T* data_ = nullptr;  // block_'s first 64-byte boundary
};

}  // namespace lbsolid::fluid
