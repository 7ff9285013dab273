#include "fluid/kernel_isa.h"

#include <atomic>
#include <cstdlib>

namespace lbsolid::fluid {
namespace {

KernelIsa best_for_this_cpu() {
#ifdef LBSOLID_KERNEL_DISPATCH
  __builtin_cpu_init();
  // The levels the paths are compiled for (GCC's -march=x86-64-v3, -v4), checked whole.
  if (__builtin_cpu_supports("x86-64-v4")) return KernelIsa::kAvx512;
  if (__builtin_cpu_supports("x86-64-v3")) return KernelIsa::kAvx2;
#endif
  return KernelIsa::kBaseline;
}

KernelIsa from_environment(KernelIsa best) {
  const char* wanted = std::getenv("LBSOLID_KERNEL_ISA");
  const std::optional<KernelIsa> isa = wanted ? parse_kernel_isa(wanted) : std::nullopt;
  if (!isa) return best;  // unset, or a name it does not know: every path is correct
  return *isa < best ? *isa : best;
}

std::atomic<int>& chosen() {
  static std::atomic<int> isa{static_cast<int>(from_environment(best_for_this_cpu()))};
  return isa;
}

}  // namespace

const char* kernel_isa_name(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::kBaseline: return "baseline";
    case KernelIsa::kAvx2: return "avx2";
    case KernelIsa::kAvx512: return "avx512";
  }
  return "?";
}

std::optional<KernelIsa> parse_kernel_isa(std::string_view name) {
  for (KernelIsa isa : {KernelIsa::kBaseline, KernelIsa::kAvx2, KernelIsa::kAvx512})
    if (name == kernel_isa_name(isa)) return isa;
  return std::nullopt;
}

std::string kernel_isa_environment_error() {
  const char* wanted = std::getenv("LBSOLID_KERNEL_ISA");
  if (!wanted || parse_kernel_isa(wanted)) return "";
  return std::string("LBSOLID_KERNEL_ISA: unknown instruction set '") + wanted + "'; use baseline, avx2 or avx512";
}

KernelIsa kernel_isa() { return static_cast<KernelIsa>(chosen().load(std::memory_order_relaxed)); }

void limit_kernel_isa(KernelIsa most) {
  const KernelIsa best = best_for_this_cpu();
  chosen().store(static_cast<int>(most < best ? most : best), std::memory_order_relaxed);
}

}  // namespace lbsolid::fluid
