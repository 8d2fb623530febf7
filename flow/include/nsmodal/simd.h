#pragma once
// Run-time choice of the AVX2 + FMA copy of an inner loop (the pole sums of
// stability.cc, the sinusoid sums of flow.cc): a function marked NSMODAL_AVX2
// is compiled for those instructions and must only be called when HasAvx2().
// Elsewhere than x86 both are no-ops and the plain copy runs.
#if defined(__x86_64__) || defined(__i386__)
#define NSMODAL_X86 1
#define NSMODAL_AVX2 [[gnu::target("avx2,fma")]]
#else
#define NSMODAL_X86 0
#define NSMODAL_AVX2
#endif

namespace nsmodal::internal {

inline bool HasAvx2() {
#if NSMODAL_X86
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return has;
#else
  return false;
#endif
}

// c_i = cos(w_i t), s_i = sin(w_i t), i < n (flow.cc): libmvec's AVX2 sin and
// cos where there are, libm's otherwise.
void CosSin(const double* w, double t, int n, double* c, double* s);

}  // namespace nsmodal::internal
