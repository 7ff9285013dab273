#pragma once
// STREAM-style loops over arrays far larger than the last-level cache: the memory bandwidth a
// streaming kernel can hope for. Bytes are counted as STREAM does, 2 words per element, the same
// convention as the LB bytes per update. Two access patterns, one per streaming scheme:
//   copy   b[i] = a[i]      writes lines it did not read (the cache fetches them first), as the
//                           two-buffer kernel does;
//   update a[i] = s * a[i]  writes back the lines it read, as the in-place kernel does.
#include <cstddef>

namespace lbsolid::bench {

// Size of the last-level cache in bytes (from sysfs; 32 MiB when unknown).
std::size_t last_level_cache_bytes();

// Best-of-`repeats` copy bandwidth in bytes per second with `threads` threads.
double copy_bandwidth(std::size_t bytes_per_array, int threads, int repeats);

// Best-of-`repeats` in-place update bandwidth in bytes per second with `threads` threads.
double update_bandwidth(std::size_t bytes, int threads, int repeats);

}  // namespace lbsolid::bench
