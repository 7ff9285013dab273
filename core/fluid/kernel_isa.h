#pragma once
// The instruction set the fluid kernels run with, chosen at run time. The default build targets
// any x86-64 CPU; the kernels alone are compiled three times (baseline, x86-64-v3 with AVX2,
// x86-64-v4 with AVX-512) and each step runs the best the CPU has, so one binary runs everywhere
// at about the speed of a -march=native build. Every path gives the same results bit for bit:
// the project compiles with -ffp-contract=off (no multiply-add is fused where another path would
// round twice) and no path reorders a sum.
//
// How: run_with_isa(isa, kernel) calls kernel() from a function compiled for that target. The
// kernel must be a lambda marked LBSOLID_FORCE_INLINE_LAMBDA, and everything it calls in its
// loops force-inlined too, so that its whole body is compiled into each target's function. A
// function not inlined there is compiled once, for the baseline, and stays safe to call anywhere.
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#include "fluid/force_inline.h"

namespace lbsolid::fluid {

enum class KernelIsa { kBaseline = 0, kAvx2 = 1, kAvx512 = 2 };
const char* kernel_isa_name(KernelIsa isa);
// The path of that name (baseline, avx2, avx512); none for any other text.
std::optional<KernelIsa> parse_kernel_isa(std::string_view name);

// The best instruction set this CPU and this build have, lowered by limit_kernel_isa().
KernelIsa kernel_isa();
// The most the kernels may use from now on (tests run each path; the environment variable
// LBSOLID_KERNEL_ISA=baseline|avx2|avx512, read once at the first kernel_isa(), does the same;
// a name it does not know asks for nothing, so programs check it first: kernel_isa_environment_error()).
void limit_kernel_isa(KernelIsa most);
// Empty when LBSOLID_KERNEL_ISA is unset or names a path; otherwise what is wrong with it.
std::string kernel_isa_environment_error();

// A kernel that takes an argument is told which path it was compiled for (IsaTag<isa>): code
// written with explicit vectors picks their width from it.
template <KernelIsa I>
using IsaTag = std::integral_constant<KernelIsa, I>;
template <KernelIsa I, class Kernel>
LBSOLID_FORCE_INLINE void call_kernel(const Kernel& kernel) {
  if constexpr (std::is_invocable_v<const Kernel&, IsaTag<I>>) kernel(IsaTag<I>{});
  else kernel();
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(LBSOLID_SINGLE_ISA)
#define LBSOLID_KERNEL_DISPATCH 1
template <class Kernel>
[[gnu::target("arch=x86-64-v4,prefer-vector-width=512")]] void run_avx512(const Kernel& kernel) {
  call_kernel<KernelIsa::kAvx512>(kernel);
}
template <class Kernel>
[[gnu::target("arch=x86-64-v3")]] void run_avx2(const Kernel& kernel) {
  call_kernel<KernelIsa::kAvx2>(kernel);
}
#endif

// The path this translation unit is compiled for: the baseline in the portable build, the
// building CPU's in a -march=native one (LBSOLID_NATIVE), where the kernels run unswitched.
#if defined(__AVX512F__)
inline constexpr KernelIsa kCompiledIsa = KernelIsa::kAvx512;
#elif defined(__AVX2__)
inline constexpr KernelIsa kCompiledIsa = KernelIsa::kAvx2;
#else
inline constexpr KernelIsa kCompiledIsa = KernelIsa::kBaseline;
#endif

template <class Kernel>
void run_with_isa(KernelIsa isa, const Kernel& kernel) {
#ifdef LBSOLID_KERNEL_DISPATCH
  switch (isa) {
    case KernelIsa::kAvx512: return run_avx512(kernel);
    case KernelIsa::kAvx2: return run_avx2(kernel);
    case KernelIsa::kBaseline: break;
  }
#else
  (void)isa;
#endif
  call_kernel<kCompiledIsa>(kernel);
}

}  // namespace lbsolid::fluid
