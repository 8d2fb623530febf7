#include "nsmodal/flow.h"

#include <algorithm>
#include <cmath>

#include "nsmodal/simd.h"

#if NSMODAL_X86 && defined(NSMODAL_HAVE_MVEC)
#include <immintrin.h>
// glibc's vector math library (libmvec): sin and cos of 4 doubles, AVX2.
extern "C" NSMODAL_AVX2 __m256d _ZGVdN4v_sin(__m256d);
extern "C" NSMODAL_AVX2 __m256d _ZGVdN4v_cos(__m256d);
#endif

namespace nsmodal {
namespace {

// c_i = cos(w_i t), s_i = sin(w_i t), i < n. Most of the time of a sum of
// many sinusoids (NC3 of a large system's orbit, the exact integrator's
// search steps): with libmvec's AVX2 sin and cos, 2.2 ns a mode instead of
// 24 ns (measured on 1,000 modes; the results agree with libm's to 3e-16).
#if NSMODAL_X86 && defined(NSMODAL_HAVE_MVEC)
NSMODAL_AVX2 void CosSinAvx2(const double* w, double t, int n, double* c, double* s) {
  const __m256d vt = _mm256_set1_pd(t);
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d x = _mm256_mul_pd(_mm256_loadu_pd(w + i), vt);
    _mm256_storeu_pd(c + i, _ZGVdN4v_cos(x));
    _mm256_storeu_pd(s + i, _ZGVdN4v_sin(x));
  }
  for (; i < n; ++i) {
    c[i] = std::cos(w[i] * t);
    s[i] = std::sin(w[i] * t);
  }
}
#endif

}  // namespace

void internal::CosSin(const double* w, double t, int n, double* c, double* s) {
  if (t == 0.0) {  // the start of every flight: no sin or cos needed
    std::fill(c, c + n, 1.0);
    std::fill(s, s + n, 0.0);
    return;
  }
#if NSMODAL_X86 && defined(NSMODAL_HAVE_MVEC)
  if (internal::HasAvx2()) {
    CosSinAvx2(w, t, n, c, s);
    return;
  }
#endif
  for (int i = 0; i < n; ++i) {
    c[i] = std::cos(w[i] * t);
    s[i] = std::sin(w[i] * t);
  }
}

namespace {

// body(first, count, c, s) on consecutive blocks of the n frequencies w, with
// c, s the cosines and sines of that block at t (on the stack: no allocation,
// and the const methods below stay safe to call from several threads).
template <typename Body>
void ForEachBlock(const Eigen::VectorXd& w, double t, Body body) {
  constexpr int kBlock = 128;
  double c[kBlock], s[kBlock];
  const int n = static_cast<int>(w.size());
  for (int first = 0; first < n; first += kBlock) {
    const int count = std::min(kBlock, n - first);
    internal::CosSin(w.data() + first, t, count, c, s);
    body(first, count, c, s);
  }
}

}  // namespace

void Flow(const ModalBasis& b, double t, Eigen::Ref<Eigen::VectorXd> y) {
  for (int i = 0; i < b.rigid; ++i) y[i] += t * y[b.n + i];  // free drift, u_i = q_i
  // (rigid modes have w_i = 0: cos 1, sin 0 would leave them as they are,
  // but they drift, above)
  ForEachBlock(b.omega, t, [&](int first, int count, const double* c, const double* s) {
    for (int j = 0; j < count; ++j) {
      const int i = first + j;
      if (i < b.rigid) continue;
      const double u = y[i];
      const double w = y[b.n + i];
      y[i] = c[j] * u + s[j] * w;
      y[b.n + i] = -s[j] * u + c[j] * w;
    }
  });
}

void Impact(const ModalBasis& b, double e, Eigen::Ref<Eigen::VectorXd> y) {
  const double vc = b.r.dot(y.tail(b.n));
  y.tail(b.n) -= ((1.0 + e) * vc / b.r_norm2) * b.r;
}

void Impact(const ModalBasis& b, const ModalContact& c, double e, Eigen::Ref<Eigen::VectorXd> y) {
  const double vc = c.r.dot(y.tail(b.n));
  y.tail(b.n) -= ((1.0 + e) * vc / c.r_norm2) * c.r;
}

Eigen::MatrixXd FlowMatrix(const ModalBasis& b, double t) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(2 * b.n, 2 * b.n);
  for (int i = 0; i < b.rigid; ++i) {
    s(i, i) = s(b.n + i, b.n + i) = 1.0;
    s(i, b.n + i) = t;
  }
  for (int i = b.rigid; i < b.n; ++i) {
    const double c = std::cos(b.omega[i] * t);
    const double sn = std::sin(b.omega[i] * t);
    s(i, i) = c;
    s(i, b.n + i) = sn;
    s(b.n + i, i) = -sn;
    s(b.n + i, b.n + i) = c;
  }
  return s;
}

Eigen::MatrixXd ImpactMatrix(const ModalBasis& b, double e) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(2 * b.n, 2 * b.n);
  m.bottomRightCorner(b.n, b.n) -= ((1.0 + e) / b.r_norm2) * b.r * b.r.transpose();
  return m;
}

Eigen::MatrixXd ImpactMatrix(const ModalBasis& b, const ModalContact& c, double e) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(2 * b.n, 2 * b.n);
  m.bottomRightCorner(b.n, b.n) -= ((1.0 + e) / c.r_norm2) * c.r * c.r.transpose();
  return m;
}

SinusoidSum::SinusoidSum(double c, Eigen::VectorXd a_in, Eigen::VectorXd b_in, Eigen::VectorXd omega_in)
    : offset(c), a(std::move(a_in)), b(std::move(b_in)), omega(std::move(omega_in)) {
  UpdateBounds();
}

namespace {

// sum_i w_i^k sqrt(a_i^2 + b_i^2), k = 0..6, into bound; kHypot: with
// std::hypot, which cannot underflow or overflow, else with the square root,
// in a loop that vectorises (std::hypot is 10x slower: a flight of a
// 1,000-mode signal spent more in it than in its whole sweep). Returns
// whether every square root was safe (1e-150 < amplitude < 1e150, or 0).
template <bool kHypot>
bool SumBounds(int n, const double* pa, const double* pb, const double* pw, double bound[7]) {
  double b0 = 0.0, b1 = 0.0, b2 = 0.0, b3 = 0.0, b4 = 0.0, b5 = 0.0, b6 = 0.0;
  int unsafe = 0;
#pragma omp simd reduction(+ : b0, b1, b2, b3, b4, b5, b6, unsafe)
  for (int i = 0; i < n; ++i) {
    const double amp = kHypot ? std::hypot(pa[i], pb[i]) : std::sqrt(pa[i] * pa[i] + pb[i] * pb[i]);
    unsafe += !(amp > 1e-150 && amp < 1e150) && (pa[i] != 0.0 || pb[i] != 0.0);
    const double w = pw[i], w2 = w * w, w4 = w2 * w2;
    b0 += amp;
    b1 += w * amp;
    b2 += w2 * amp;
    b3 += w2 * w * amp;
    b4 += w4 * amp;
    b5 += w4 * w * amp;
    b6 += w4 * w2 * amp;
  }
  bound[0] = b0;
  bound[1] = b1;
  bound[2] = b2;
  bound[3] = b3;
  bound[4] = b4;
  bound[5] = b5;
  bound[6] = b6;
  return kHypot || unsafe == 0;
}

}  // namespace

void SinusoidSum::UpdateBounds() {
  const int n = static_cast<int>(omega.size());
  if (!SumBounds<false>(n, a.data(), b.data(), omega.data(), bound)) {
    SumBounds<true>(n, a.data(), b.data(), omega.data(), bound);
  }
  bound[1] += std::abs(slope);
}

ContactSignal::ContactSignal(const ModalBasis& basis, const Eigen::Ref<const Eigen::VectorXd>& y) {
  omega = basis.omega;
  Reset(basis, y);
}

ContactSignal::ContactSignal(const ModalBasis& basis, const ModalContact& contact,
                             const Eigen::Ref<const Eigen::VectorXd>& y) {
  omega = basis.omega;
  Reset(basis, contact, y);
}

void ContactSignal::Reset(const ModalBasis& basis, const Eigen::Ref<const Eigen::VectorXd>& y) {
  Reset(basis, basis.r_over_omega, y);
}

void ContactSignal::Reset(const ModalBasis& basis, const ModalContact& contact,
                          const Eigen::Ref<const Eigen::VectorXd>& y) {
  Reset(basis, contact.r_over_omega, y);
}

void ContactSignal::Reset(const ModalBasis& basis, const Eigen::VectorXd& r_over_omega,
                          const Eigen::Ref<const Eigen::VectorXd>& y) {
  a = r_over_omega.cwiseProduct(y.head(basis.n));
  b = r_over_omega.cwiseProduct(y.tail(basis.n));
  // A rigid-body mode (w_i = 0) drifts: its a_i = r_i q_i stays (cos 0 = 1),
  // its velocity term is the slope r_i s_i, not b_i sin(0).
  const int rigid = basis.rigid;
  slope = b.head(rigid).sum();
  b.head(rigid).setZero();
  UpdateBounds();
}

// The sums over a block are reassociated (omp simd) so that they vectorise.
double SinusoidSum::Position(double t) const {
  double f = offset + slope * t;
  ForEachBlock(omega, t, [&](int first, int count, const double* c, const double* s) {
    const double *pa = a.data() + first, *pb = b.data() + first;
    double sum = 0.0;
#pragma omp simd reduction(+ : sum)
    for (int j = 0; j < count; ++j) sum += pa[j] * c[j] + pb[j] * s[j];
    f += sum;
  });
  return f;
}

double SinusoidSum::Velocity(double t) const {
  return VelocityAcceleration(t).first;
}

double SinusoidSum::Acceleration(double t) const {
  return VelocityAcceleration(t).second;
}

std::pair<double, double> SinusoidSum::VelocityAcceleration(double t) const {
  double v = slope, acc = 0.0;
  ForEachBlock(omega, t, [&](int first, int count, const double* c, const double* s) {
    const double *pa = a.data() + first, *pb = b.data() + first, *pw = omega.data() + first;
    double sv = 0.0, sacc = 0.0;
#pragma omp simd reduction(+ : sv, sacc)
    for (int j = 0; j < count; ++j) {
      sv += pw[j] * (pb[j] * c[j] - pa[j] * s[j]);
      sacc -= pw[j] * pw[j] * (pa[j] * c[j] + pb[j] * s[j]);
    }
    v += sv;
    acc += sacc;
  });
  return {v, acc};
}

namespace {

// The value and first three derivatives of sum_j a_j cos + b_j sin over one
// block (c, s: the cosines and sines at t), added to d. AVX2 + FMA where
// there are (simd.h): the exact integrator's conservative step at N = 1,000.
[[gnu::always_inline]] inline void DerivativesBody(int count, const double* pa, const double* pb, const double* pw,
                                                   const double* c, const double* s, double d[4]) {
  double d0 = 0.0, d1 = 0.0, d2 = 0.0, d3 = 0.0;
#pragma omp simd reduction(+ : d0, d1, d2, d3)
  for (int j = 0; j < count; ++j) {
    const double w = pw[j];
    const double p = pa[j] * c[j] + pb[j] * s[j];  // the term itself
    const double q = pb[j] * c[j] - pa[j] * s[j];  // its derivative divided by w
    d0 += p;
    d1 += w * q;
    d2 -= w * w * p;
    d3 -= w * w * w * q;
  }
  d[0] += d0;
  d[1] += d1;
  d[2] += d2;
  d[3] += d3;
}
void DerivativesPlain(int count, const double* pa, const double* pb, const double* pw, const double* c,
                      const double* s, double d[4]) {
  DerivativesBody(count, pa, pb, pw, c, s, d);
}
#if NSMODAL_X86
NSMODAL_AVX2 void DerivativesAvx2(int count, const double* pa, const double* pb, const double* pw, const double* c,
                                  const double* s, double d[4]) {
  DerivativesBody(count, pa, pb, pw, c, s, d);
}
#endif

// One block of Derivatives' sums, AVX2 + FMA where there are.
void DerivativesBlock(int count, const double* pa, const double* pb, const double* pw, const double* c,
                      const double* s, double d[4]) {
#if NSMODAL_X86
  if (internal::HasAvx2()) return DerivativesAvx2(count, pa, pb, pw, c, s, d);
#endif
  DerivativesPlain(count, pa, pb, pw, c, s, d);
}

}  // namespace

void SinusoidSum::Derivatives(double t, double out[4]) const {
  out[0] = offset + slope * t;
  out[1] = slope;
  out[2] = out[3] = 0.0;
  ForEachBlock(omega, t, [&](int first, int count, const double* c, const double* s) {
    DerivativesBlock(count, a.data() + first, b.data() + first, omega.data() + first, c, s, out);
  });
}

void SinusoidSum::Derivatives(double t, const double* cos_wt, const double* sin_wt, double out[4]) const {
  out[0] = offset + slope * t;
  out[1] = slope;
  out[2] = out[3] = 0.0;
  DerivativesBlock(static_cast<int>(omega.size()), a.data(), b.data(), omega.data(), cos_wt, sin_wt, out);
}

}  // namespace nsmodal
