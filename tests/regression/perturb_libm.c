// How the tolerant mode's tolerances were checked (README.md): an LD_PRELOAD
// library that moves every result of libm's and libmvec's functions that
// nsmodal (and CVODE, and GSL) call by one ulp up, one ulp down or not at
// all, chosen by a hash of the argument and of PERTURB (a seed; 0: off). It
// stands in for a build whose last bits differ (clang's FMA contraction,
// another summation order, another libm): run
//   gcc -O2 -shared -fPIC -o /tmp/perturb_libm.so tests/regression/perturb_libm.c -ldl
//   LD_PRELOAD=/tmp/perturb_libm.so PERTURB=1 tests/regression/run.sh BIN SRC --mode tolerant --margins
// (exact mode then fails, as it must). Not built by CMake: a tool, not a test.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <immintrin.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint64_t seed(void) {
  static int read = 0;
  static uint64_t s = 1;
  if (!read) {
    const char* e = getenv("PERTURB");
    s = e ? strtoull(e, NULL, 10) : 1;
    read = 1;
  }
  return s;
}

static double nudge(double r, double x) {
  if (!seed() || !isfinite(r) || r == 0.0) return r;
  uint64_t b;
  memcpy(&b, &x, 8);
  b ^= seed() * 0x9E3779B97F4A7C15ull;
  b *= 0xff51afd7ed558ccdull;
  b ^= b >> 33;
  b *= 0xc4ceb9fe1a85ec53ull;
  b ^= b >> 33;
  return b % 3 == 0 ? nextafter(r, INFINITY) : b % 3 == 1 ? nextafter(r, -INFINITY) : r;
}

#define ONE(name)                                          \
  double name(double x) {                                  \
    static double (*f)(double);                            \
    if (!f) f = (double (*)(double))dlsym(RTLD_NEXT, #name); \
    return nudge(f(x), x);                                 \
  }
#define TWO(name)                                                    \
  double name(double x, double y) {                                  \
    static double (*f)(double, double);                              \
    if (!f) f = (double (*)(double, double))dlsym(RTLD_NEXT, #name); \
    return nudge(f(x, y), x + 3.1 * y);                              \
  }
ONE(sin) ONE(cos) ONE(acos) ONE(log) TWO(atan2) TWO(hypot) TWO(pow)

void sincos(double x, double* s, double* c) {
  static void (*f)(double, double*, double*);
  if (!f) f = (void (*)(double, double*, double*))dlsym(RTLD_NEXT, "sincos");
  f(x, s, c);
  *s = nudge(*s, x);
  *c = nudge(*c, -x);
}

// libmvec's AVX2 sin and cos (flow.cc calls them by name): libm's, nudged.
__attribute__((target("avx2"))) __m256d _ZGVdN4v_sin(__m256d v) {
  double a[4];
  _mm256_storeu_pd(a, v);
  for (int i = 0; i < 4; ++i) a[i] = sin(a[i]);
  return _mm256_loadu_pd(a);
}
__attribute__((target("avx2"))) __m256d _ZGVdN4v_cos(__m256d v) {
  double a[4];
  _mm256_storeu_pd(a, v);
  for (int i = 0; i < 4; ++i) a[i] = cos(a[i]);
  return _mm256_loadu_pd(a);
}
