#pragma once
// A STREAM-style copy (b[i] = a[i]) over arrays far larger than the last-level cache: the memory
// bandwidth a streaming kernel can hope for. Bytes are counted as STREAM does, 2 words per
// element (write-allocate traffic not counted), the same convention as the LB bytes per update.
#include <cstddef>

namespace lbsolid::bench {

// Size of the last-level cache in bytes (from sysfs; 32 MiB when unknown).
std::size_t last_level_cache_bytes();

// Best-of-`repeats` copy bandwidth in bytes per second with `threads` threads.
double copy_bandwidth(std::size_t bytes_per_array, int threads, int repeats);

}  // namespace lbsolid::bench
