#include "nsmodal/stability.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "nsmodal/flow.h"
#include "nsmodal/roots.h"
#include "nsmodal/simd.h"

namespace nsmodal {
namespace {

using Complex = std::complex<double>;

// f(y) = G y: u_i' = w_i s_i, s_i' = -w_i u_i.
Eigen::VectorXd Field(const ModalBasis& b, const Eigen::VectorXd& y) {
  Eigen::VectorXd f(2 * b.n);
  f.head(b.n) = b.omega.cwiseProduct(y.tail(b.n));
  f.tail(b.n) = -b.omega.cwiseProduct(y.head(b.n));
  f.head(b.rigid) = y.segment(b.n, b.rigid);  // a rigid-body mode drifts: u_i' = s_i (u_i = q_i)
  return f;
}

// |v_c-| below this fraction of |r| |y| (the largest contact velocity a state
// of that energy can have) is a graze: no linearisation.
constexpr double kGrazeFraction = 1e-9;

bool Grazes(const AnalysisBasis& b, const ModalContact& c, const Eigen::VectorXd& y_minus, double speed_scale) {
  return !(std::abs(ContactVelocity(b, c, y_minus)) > kGrazeFraction * speed_scale);
}

// The contact of the impact ending flight k (0-based; the last flight ends
// with the impact at T, the first of the sequence).
int ContactEnding(const Orbit& orbit, int k) {
  return orbit.sequence.empty() ? 0 : orbit.sequence[(k + 1) % orbit.impacts];
}

// The monodromy by products of flows and saltation matrices; false if an
// impact grazes.
bool DenseMonodromy(const AnalysisBasis& b, const Orbit& orbit, Eigen::MatrixXd& m) {
  const int dim = 2 * b.n;
  m = Eigen::MatrixXd::Identity(dim, dim);
  Eigen::VectorXd y = orbit.y0;
  double prev = 0.0;
  std::vector<double> ends = orbit.times;
  ends.push_back(orbit.period);
  bool defined = true;
  for (int k = 0; k < static_cast<int>(ends.size()); ++k) {
    const double t = ends[k];
    const int j = ContactEnding(orbit, k);
    const ModalContact& c = b.contacts[j];
    Flow(b, t - prev, y);
    if (Grazes(b, c, y, c.r.norm() * orbit.y0.norm())) defined = false;
    for (int col = 0; col < dim; ++col) Flow(b, t - prev, m.col(col));
    m = SaltationMatrix(b, y, j) * m;
    Impact(b, c, AnalysisBasis::kRestitution, y);
    prev = t;
  }
  return defined;
}

Stability Undefined(int dim) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Stability out;
  out.defined = false;
  out.multipliers = Eigen::VectorXcd::Constant(dim, Complex(nan, nan));
  out.max_modulus = out.growth_per_period = nan;
  return out;
}

// Sorts the multipliers (the trivial pair appended here) and fills the verdict.
Stability Finish(std::vector<Complex> mu, bool complete, double max_modulus, double tol) {
  mu.push_back(1.0);
  mu.push_back(1.0);
  std::stable_sort(mu.begin(), mu.end(), [](Complex x, Complex y) { return std::abs(x) > std::abs(y); });
  Stability out;
  out.multipliers = Eigen::Map<Eigen::VectorXcd>(mu.data(), static_cast<Eigen::Index>(mu.size()));
  out.complete = complete;
  out.max_modulus = std::max(max_modulus, std::abs(mu.front()));
  out.growth_per_period = std::log(out.max_modulus);
  out.stable = out.max_modulus <= 1.0 + tol;
  return out;
}

// The nontrivial multipliers from the dense monodromy: eig(U' M U) with U an
// orthonormal basis of {y0, f(y0)}-perp (stability.h).
Stability DenseStability(const AnalysisBasis& b, const Orbit& orbit, double tol) {
  const int dim = 2 * b.n;
  Eigen::MatrixXd m;
  if (!DenseMonodromy(b, orbit, m)) return Undefined(dim);
  Eigen::MatrixXd pair(dim, 2);
  // The energy's gradient (y0 itself, less the rigid-body positions, which
  // store no energy: flow.h Energy) is the left eigenvector.
  Eigen::VectorXd gradient = orbit.y0;
  gradient.head(b.rigid).setZero();
  pair << gradient, Field(b, orbit.y0);
  const Eigen::MatrixXd q = Eigen::HouseholderQR<Eigen::MatrixXd>(pair).householderQ();
  const Eigen::MatrixXd u = q.rightCols(dim - 2);
  const Eigen::MatrixXd reduced = u.transpose() * m * u;
  // One dof: the trivial pair is all there is (Eigen's eigenvalues of a 0 x 0
  // matrix bind a reference to its null data: UBSan, found by fuzz_scene).
  std::vector<Complex> nontrivial;
  if (reduced.size() > 0) {
    const Eigen::VectorXcd ev = reduced.eigenvalues();
    nontrivial.assign(ev.data(), ev.data() + ev.size());
  }
  return Finish(std::move(nontrivial), true, 0.0, tol);
}

// The sums over the coupled modes behind Gt, Gt' and Gt'' at x = xr + i xi,
// with e_i = 1 / (x - z_i). Most of a large sweep's time is here: the loop is
// written for the vectoriser (real and imaginary parts apart, the sums
// reassociated by omp simd) and has an AVX2 + FMA copy taken when the
// processor has it; with it, the N = 1,000 chain's multipliers took 2.2 times
// less time than with the loop on std::complex (a sweep: 422 s -> 196 s).
struct PoleSums {
  Complex sa, sb, sc;  // S_X = sum X_i e_i
  Complex da, db, dc;  // S_X' = -sum X_i e_i^2
  Complex ta, tb, tc;  // S_X'' = 2 sum X_i e_i^3 (complex x only)
  Complex e1, e2;      // sum e_i, sum e_i^2: the poles' share of P'/P (complex x only)
};

template <bool kComplex>
[[gnu::always_inline]] inline PoleSums PoleSumsBody(const OneImpactSecular& s, double xr, double xi) {
  const double *z = s.z.data(), *a = s.a.data(), *b = s.b.data(), *c = s.c.data();
  const int n = static_cast<int>(s.z.size());
  double sar = 0, sbr = 0, scr = 0, dar = 0, dbr = 0, dcr = 0, tar = 0, tbr = 0, tcr = 0, e1r = 0, e2r = 0;
  double sai = 0, sbi = 0, sci = 0, dai = 0, dbi = 0, dci = 0, tai = 0, tbi = 0, tci = 0, e1i = 0, e2i = 0;
  if constexpr (kComplex) {
#pragma omp simd reduction(+ : sar, sbr, scr, dar, dbr, dcr, tar, tbr, tcr, e1r, e2r, sai, sbi, sci, dai, dbi, dci, tai, \
                               tbi, tci, e1i, e2i)
    for (int i = 0; i < n; ++i) {
      // 1 / (x - z_i) without libgcc's guarded complex division (__divdc3):
      // |x - z_i| here is never near under- or overflow.
      const double dr = xr - z[i];
      const double inv = 1.0 / (dr * dr + xi * xi);
      const double pr = dr * inv, pi = -xi * inv;                        // e
      const double qr = pr * pr - pi * pi, qi = 2.0 * pr * pi;           // e^2
      const double cr = 2.0 * (qr * pr - qi * pi), ci = 2.0 * (qr * pi + qi * pr);  // 2 e^3
      e1r += pr;
      e1i += pi;
      e2r += qr;
      e2i += qi;
      sar += a[i] * pr;
      sai += a[i] * pi;
      sbr += b[i] * pr;
      sbi += b[i] * pi;
      scr += c[i] * pr;
      sci += c[i] * pi;
      dar -= a[i] * qr;
      dai -= a[i] * qi;
      dbr -= b[i] * qr;
      dbi -= b[i] * qi;
      dcr -= c[i] * qr;
      dci -= c[i] * qi;
      tar += a[i] * cr;
      tai += a[i] * ci;
      tbr += b[i] * cr;
      tbi += b[i] * ci;
      tcr += c[i] * cr;
      tci += c[i] * ci;
    }
  } else {
#pragma omp simd reduction(+ : sar, sbr, scr, dar, dbr, dcr)
    for (int i = 0; i < n; ++i) {
      const double e = 1.0 / (xr - z[i]), e2 = e * e;
      sar += a[i] * e;
      sbr += b[i] * e;
      scr += c[i] * e;
      dar -= a[i] * e2;
      dbr -= b[i] * e2;
      dcr -= c[i] * e2;
    }
  }
  return {{sar, sai}, {sbr, sbi}, {scr, sci}, {dar, dai}, {dbr, dbi}, {dcr, dci},
          {tar, tai}, {tbr, tbi}, {tcr, tci}, {e1r, e1i}, {e2r, e2i}};
}

// sum_j 1 / (x - r_j) and sum_j 1 / (x - r_j)^2 over the roots r_j = re_j + i im_j
// already located (the deflation's share of Q'/Q and its derivative).
struct RootSums {
  Complex q1, q2;
};
[[gnu::always_inline]] inline RootSums RootSumsBody(const std::vector<double>& re, const std::vector<double>& im,
                                                    Complex x) {
  double q1r = 0, q1i = 0, q2r = 0, q2i = 0;
  const double *pr = re.data(), *pi = im.data();
  const int n = static_cast<int>(re.size());
#pragma omp simd reduction(+ : q1r, q1i, q2r, q2i)
  for (int j = 0; j < n; ++j) {
    const double dr = x.real() - pr[j], di = x.imag() - pi[j];
    const double inv = 1.0 / (dr * dr + di * di);
    const double er = dr * inv, ei = -di * inv;
    q1r += er;
    q1i += ei;
    q2r += er * er - ei * ei;
    q2i += 2.0 * er * ei;
  }
  return {{q1r, q1i}, {q2r, q2i}};
}

using internal::HasAvx2;

template <bool kComplex>
NSMODAL_AVX2 PoleSums PoleSumsAvx2(const OneImpactSecular& s, double xr, double xi) {
  return PoleSumsBody<kComplex>(s, xr, xi);
}
template <bool kComplex>
PoleSums PoleSumsPlain(const OneImpactSecular& s, double xr, double xi) {
  return PoleSumsBody<kComplex>(s, xr, xi);
}
NSMODAL_AVX2 RootSums RootSumsAvx2(const std::vector<double>& re, const std::vector<double>& im, Complex x) {
  return RootSumsBody(re, im, x);
}
RootSums RootSumsPlain(const std::vector<double>& re, const std::vector<double>& im, Complex x) {
  return RootSumsBody(re, im, x);
}

template <bool kComplex>
PoleSums PoleSumsAt(const OneImpactSecular& s, double xr, double xi) {
  return HasAvx2() ? PoleSumsAvx2<kComplex>(s, xr, xi) : PoleSumsPlain<kComplex>(s, xr, xi);
}
RootSums RootSumsAt(const std::vector<double>& re, const std::vector<double>& im, Complex x) {
  return HasAvx2() ? RootSumsAvx2(re, im, x) : RootSumsPlain(re, im, x);
}

// Gt(x) and Gt'(x) from the sums.
template <typename T>
void SecularFrom(const PoleSums& p, T x, T* value, T* slope) {
  auto pick = [](Complex v) {
    if constexpr (std::is_same_v<T, Complex>) {
      return v;
    } else {
      return v.real();
    }
  };
  const T sa = pick(p.sa), sb = pick(p.sb), sc = pick(p.sc), da = pick(p.da), db = pick(p.db), dc = pick(p.dc);
  *value = (x + 2.0) * sa * sa - 2.0 * sb * sc;
  if (slope != nullptr) *slope = sa * sa + 2.0 * (x + 2.0) * sa * da - 2.0 * (db * sc + sb * dc);
}

void SecularAt(const OneImpactSecular& s, double x, double* value, double* slope) {
  SecularFrom<double>(PoleSumsAt<false>(s, x, 0.0), x, value, slope);
}

// The multipliers lambda, 1/lambda of a root z = lambda + 1/lambda.
void AddPair(Complex z, std::vector<Complex>& mu) {
  const Complex lambda = 0.5 * z + std::sqrt(0.25 * z * z - 1.0);
  mu.push_back(lambda);
  mu.push_back(1.0 / lambda);
}

int Sign(double v) { return v > 0.0 ? 1 : (v < 0.0 ? -1 : 0); }

// The structured path (stability.h). False when the roots could not all be
// accounted for (the caller falls back to the dense monodromy).
bool StructuredStability(const OneImpactSecular& s, const StabilityOptions& options, Stability& out) {
  const int k = static_cast<int>(s.z.size());
  if (k == 0) return false;
  // Sorted poles, distinct and inside (-2, 2).
  std::vector<int> order(k);
  for (int i = 0; i < k; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int x, int y) { return s.z[x] < s.z[y]; });
  std::vector<double> pole(k);
  for (int i = 0; i < k; ++i) pole[i] = s.z[order[i]];
  constexpr double kPoleSeparation = 1e-13;
  if (!(pole.front() > -2.0 + kPoleSeparation) || !(pole.back() < 2.0 - kPoleSeparation)) return false;
  for (int i = 1; i < k; ++i) {
    if (!(pole[i] - pole[i - 1] > kPoleSeparation)) return false;
  }
  // Residues: O(K^2) sums over the other poles.
  std::vector<double> residue(k);
  double residue_sum = 0.0, residue_abs = 0.0;
  for (int i = 0; i < k; ++i) {
    const int p = order[i];
    double sa = 0.0, sb = 0.0, sc = 0.0;
    for (int j = 0; j < k; ++j) {
      if (j == p) continue;
      const double e = 1.0 / (s.z[p] - s.z[j]);
      sa += s.a[j] * e;
      sb += s.b[j] * e;
      sc += s.c[j] * e;
    }
    residue[i] = 2.0 * (s.z[p] + 2.0) * s.a[p] * sa + s.a[p] * s.a[p] - 2.0 * (s.b[p] * sc + s.c[p] * sb);
    residue_sum += residue[i];
    residue_abs += std::abs(residue[i]);
  }
  // Gt ~ (sum of residues) / z at infinity, and sum a_i = 1: the two agree
  // unless round-off ate the residues.
  if (!(std::abs(residue_sum - 1.0) < 1e-6 * std::max(1.0, residue_abs))) return false;
  // Every root lies in |z| <= 2 + 2 sum |g_i| (stability.h: Gt = sum g_i / (z - z_i)).
  const double reach = 2.0 + 2.0 * residue_abs + 1.0;
  // Segments [lo, hi] between consecutive breakpoints -reach, -2, poles, 2, reach,
  // with the sign of Gt just inside each end.
  struct Segment {
    double lo, hi;
    int pole_lo, pole_hi;  // index into pole[] or -1
    int sign_lo, sign_hi;
  };
  const double at_minus2 = s.Value(-2.0), at_plus2 = s.Value(2.0);
  const double at_minus_reach = s.Value(-reach), at_reach = s.Value(reach);
  if (Sign(at_minus2) == 0 || Sign(at_plus2) == 0 || Sign(at_minus_reach) >= 0 || Sign(at_reach) <= 0) return false;
  std::vector<Segment> segments;
  segments.push_back({-reach, -2.0, -1, -1, Sign(at_minus_reach), Sign(at_minus2)});
  segments.push_back({-2.0, pole[0], -1, 0, Sign(at_minus2), -Sign(residue[0])});
  for (int i = 0; i + 1 < k; ++i) segments.push_back({pole[i], pole[i + 1], i, i + 1, Sign(residue[i]), -Sign(residue[i + 1])});
  segments.push_back({pole[k - 1], 2.0, k - 1, -1, Sign(residue[k - 1]), Sign(at_plus2)});
  segments.push_back({2.0, reach, -1, -1, Sign(at_plus2), Sign(at_reach)});
  // H = Gt times the distance to the segment's poles: finite on the closed segment.
  auto h_of = [&](const Segment& g) {
    return [&s, &residue, g](double x) {
      if (g.pole_lo >= 0 && x <= g.lo) return residue[g.pole_lo] * (g.hi - g.lo);
      if (g.pole_hi >= 0 && x >= g.hi) return -residue[g.pole_hi] * (g.hi - g.lo);
      double v = s.Value(x);
      if (g.pole_lo >= 0) v *= x - g.lo;
      if (g.pole_hi >= 0) v *= g.hi - x;
      return v;
    };
  };
  // The root of H in [a, c] (H(a), H(c) of opposite signs): Newton on H with
  // H' from Gt', kept inside the bracket (bisection when a step leaves it or
  // does not halve it), to 4 eps. A pole-free secular function converges in a
  // few steps where Brent needs a dozen (most of a large sweep's time).
  auto polish = [&](const Segment& g, double a, double c) {
    const auto h = h_of(g);
    // Orient so that H(lo) < 0 < H(hi) (Numerical Recipes' rtsafe).
    double lo = a, hi = c;
    if (h(a) > 0.0) std::swap(lo, hi);
    double x = 0.5 * (a + c), dx_old = std::abs(c - a), dx = dx_old;
    const double eps = std::numeric_limits<double>::epsilon();
    for (int it = 0; it < 200; ++it) {
      double hx, dh;
      SecularAt(s, x, &hx, &dh);
      if (g.pole_lo >= 0) {
        dh = dh * (x - g.lo) + hx;
        hx *= x - g.lo;
      }
      if (g.pole_hi >= 0) {
        dh = dh * (g.hi - x) - hx;
        hx *= g.hi - x;
      }
      if (hx == 0.0) return x;
      if (hx < 0.0) {
        lo = x;
      } else {
        hi = x;
      }
      if (((x - hi) * dh - hx) * ((x - lo) * dh - hx) > 0.0 || std::abs(2.0 * hx) > std::abs(dx_old * dh)) {
        dx_old = dx;
        dx = 0.5 * (hi - lo);
        x = lo + dx;
      } else {
        dx_old = dx;
        dx = hx / dh;
        x -= dx;
      }
      if (std::abs(dx) <= 2.0 * eps * std::abs(x) || std::abs(hi - lo) <= 4.0 * eps * (std::abs(lo) + std::abs(hi))) {
        return x;
      }
    }
    return x;
  };
  // Stage 1: the real roots the signs prove: one in each segment whose ends
  // differ in sign; in the others, two where the extremum towards zero crosses it.
  struct RealRoots {
    const Segment* segment;
    int count;       // 1, or 2 (on either side of split)
    double split;    // the extremum, for count = 2
    double value[2]; // polished roots (NaN until polished)
  };
  std::vector<RealRoots> real;
  struct Start {
    Complex z;
    const Segment* segment;
  };
  std::vector<Start> starts;  // near the extrema of segments without roots: where complex pairs left the axis
  int found = 0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Segment& g : segments) {
    if (g.sign_lo != g.sign_hi) {
      real.push_back({&g, 1, nan, {nan, nan}});
      ++found;
    }
  }
  // A segment without a sign change holds two roots where its extremum
  // towards zero crosses it (golden section from the best of the samples).
  auto real_pair = [&](const Segment& g, double best_x) {
    const auto h = h_of(g);
    const double step = (g.hi - g.lo) / 8;
    // Only the sign at the extremum matters: 1e-9 of the segment is plenty.
    const double x_min = MinimizeOn([&](double x) { return g.sign_lo * h(x); }, std::max(g.lo, best_x - step),
                                    best_x, std::min(g.hi, best_x + step), 1e-9);
    if (!(g.sign_lo * h(x_min) < 0.0)) return false;
    real.push_back({&g, 2, x_min, {nan, nan}});
    found += 2;
    return true;
  };
  for (const Segment& g : segments) {
    if (g.sign_lo != g.sign_hi || found >= k - 1) continue;
    const auto h = h_of(g);
    const int sign = g.sign_lo;
    // Seven samples: one of the other sign splits two roots at once.
    constexpr int kSamples = 8;
    double x[kSamples + 1], v[kSamples + 1];
    int best = 1;
    bool split = false;
    for (int j = 0; j <= kSamples && !split; ++j) {
      x[j] = g.lo + (g.hi - g.lo) * j / kSamples;
      v[j] = sign * h(x[j]);
      if (j > 0 && j < kSamples && v[j] < 0.0) {
        real.push_back({&g, 2, x[j], {nan, nan}});
        found += 2;
        split = true;
      }
      if (j > 0 && j < kSamples && v[j] < v[best]) best = j;
    }
    if (split) continue;
    // The parabola through the best sample and its neighbours: a vertex below
    // zero calls for the golden section; above, its complex roots
    // x0 +- i sqrt(2 H0 / H'') are where a pair left the axis, the start for the search.
    const double hstep = (g.hi - g.lo) / kSamples;
    const double curvature = (v[best - 1] - 2.0 * v[best] + v[best + 1]) / (hstep * hstep);
    const double slope = (v[best + 1] - v[best - 1]) / (2.0 * hstep);
    double x0 = x[best], h0 = v[best];
    if (curvature > 0.0) {
      x0 = std::clamp(x[best] - slope / curvature, x[best] - hstep, x[best] + hstep);
      h0 = v[best] - 0.5 * slope * slope / curvature;
    }
    if (!(curvature > 0.0) || !(h0 > 0.0)) {
      if (real_pair(g, x[best])) continue;
      h0 = v[best];
    }
    const double im = curvature > 0.0 && h0 > 0.0 ? std::sqrt(2.0 * h0 / curvature) : 0.25 * (g.hi - g.lo);
    starts.push_back({Complex(x0, std::isfinite(im) && im > 0.0 ? im : 0.25 * (g.hi - g.lo)), &g});
  }
  std::vector<Complex> mu;
  double max_modulus = 1.0;
  bool complete = true;
  // The roots located, for the deflation: real and imaginary parts apart (RootSums).
  std::vector<double> known_re, known_im;
  auto remember = [&](Complex r) {
    known_re.push_back(r.real());
    known_im.push_back(r.imag());
  };
  auto add_real_root = [&](double x) {
    remember(x);
    if (std::abs(x) <= 2.0) {
      const double theta = std::acos(std::clamp(0.5 * x, -1.0, 1.0));
      mu.push_back(std::polar(1.0, theta));
      mu.push_back(std::polar(1.0, -theta));
    } else {
      AddPair(x, mu);
      max_modulus = std::max(max_modulus, std::abs(mu[mu.size() - 2]));
    }
  };
  // A root already located (the deflation keeps the search off them, but not
  // exactly: round-off), to the search's own accuracy.
  auto is_known = [&](Complex z) {
    const double tol2 = 1e-16 * std::max(1.0, std::norm(z));  // (1e-8 max(1, |z|))^2, without hypot
    for (std::size_t j = 0; j < known_re.size(); ++j) {
      if (std::norm(Complex(known_re[j], known_im[j]) - z) <= tol2) return true;
    }
    return false;
  };
  auto add_complex_root = [&](Complex z) {
    if (z.imag() < 0.0) z = std::conj(z);
    if (is_known(z)) return;
    remember(z);
    remember(std::conj(z));
    found += 2;
    AddPair(z, mu);
    AddPair(std::conj(z), mu);
    for (std::size_t j = mu.size() - 4; j < mu.size(); ++j) max_modulus = std::max(max_modulus, std::abs(mu[j]));
  };
  // Stage 3: polish the real roots: those off the circle always, all of them
  // for the full spectrum or to deflate them while roots are still missing.
  auto polish_real = [&](bool missing) {
    for (RealRoots& rr : real) {
      if (!std::isnan(rr.value[0])) continue;  // done
      const Segment& g = *rr.segment;
      const bool off_circle = g.hi <= -2.0 || g.lo >= 2.0;
      if (!(off_circle || options.all_multipliers || missing)) {
        complete = false;
        continue;
      }
      if (rr.count == 1) {
        rr.value[0] = polish(g, g.lo, g.hi);
      } else {
        rr.value[0] = polish(g, g.lo, rr.split);
        rr.value[1] = polish(g, rr.split, g.hi);
      }
      for (int j = 0; j < rr.count; ++j) add_real_root(rr.value[j]);
    }
  };
  // A real root the signs did not show, unless known already or on a pole
  // (where round-off in Q'/Q can fake convergence). In a segment without
  // roots on record, the pair there is polished at once; if the extremum
  // does not split one, the root alone goes on record for the segment (a
  // later pair search there would count it twice). Else it is a third root
  // of a segment with a sign change.
  auto add_real_found = [&](double x) {
    const auto near = std::lower_bound(pole.begin(), pole.end(), x);
    const double scale = 1e-12 * std::max(1.0, std::abs(x));
    if ((near != pole.end() && *near - x <= scale) || (near != pole.begin() && x - *std::prev(near) <= scale)) return;
    if (is_known(x)) return;
    const auto next = std::upper_bound(segments.begin(), segments.end(), x,
                                       [](double v, const Segment& g) { return v < g.lo; });
    if (next != segments.begin() && x > std::prev(next)->lo && x < std::prev(next)->hi) {
      const Segment& g = *std::prev(next);
      if (std::none_of(real.begin(), real.end(), [&](const RealRoots& rr) { return rr.segment == &g; })) {
        if (real_pair(g, x)) {
          polish_real(true);
          return;
        }
        real.push_back({&g, 1, nan, {x, nan}});
      }
    }
    ++found;
    add_real_root(x);
  };
  // Laguerre's iteration on the deflated polynomial Q = P / prod (z - known)
  // of degree n = K - 1 - #known, with
  //   G = Q'/Q = Gt'/Gt + sum_i 1 / (z - z_i) - sum_known 1 / (z - r),
  //   H = -G' = (Gt'/Gt)^2 - Gt''/Gt + sum_i 1 / (z - z_i)^2 - sum_known 1 / (z - r)^2,
  //   z <- z - n / (G +- sqrt((n - 1) (n H - G^2))) (the sign that makes the step shortest).
  // At most kMaxSteps steps; a root of Gt itself (the step there at
  // round-off and Gt small against Gt'), or nothing. Measured on the N = 1,000
  // chain (11 orbits, T = 5 to 58.7): Newton's step (Newton-Maehly) needed
  // 214,000 steps, two thirds of them in 2,347 runs that never converged;
  // Laguerre's, 25,500, every run converging.
  constexpr int kMaxSteps = 60;
  auto laguerre = [&](Complex z) -> std::optional<Complex> {
    for (int it = 0; it < kMaxSteps; ++it) {
      const PoleSums p = PoleSumsAt<true>(s, z.real(), z.imag());
      const RootSums q = RootSumsAt(known_re, known_im, z);
      Complex v, d1;
      SecularFrom<Complex>(p, z, &v, &d1);
      const Complex d2 = 4.0 * p.sa * p.da + 2.0 * (z + 2.0) * (p.da * p.da + p.sa * p.ta) -
                         2.0 * (p.tb * p.sc + 2.0 * p.db * p.dc + p.sb * p.tc);
      const Complex l1 = d1 / v, l2 = d2 / v;
      const Complex g = l1 + p.e1 - q.q1;
      const Complex h = l1 * l1 - l2 + p.e2 - q.q2;
      const double n = std::max(1, k - 1 - static_cast<int>(known_re.size()));
      const Complex root = std::sqrt((n - 1.0) * (n * h - g * g));
      const Complex denominator = std::abs(g + root) >= std::abs(g - root) ? g + root : g - root;
      const Complex dz = n / denominator;
      if (!std::isfinite(dz.real()) || !std::isfinite(dz.imag())) return std::nullopt;
      z -= dz;
      if (std::abs(dz) <= 1e-14 * std::max(1.0, std::abs(z))) {
        SecularFrom<Complex>(PoleSumsAt<true>(s, z.real(), z.imag()), z, &v, &d1);
        if (!(std::abs(v) <= 1e-8 * std::max(1.0, std::abs(z)) * std::abs(d1))) return std::nullopt;
        return z;
      }
    }
    return std::nullopt;
  };
  // A root the search found: real (within 1e-10 of the axis) or a complex pair.
  auto add_found = [&](Complex z) {
    if (std::abs(z.imag()) <= 1e-10 * std::max(1.0, std::abs(z))) {
      add_real_found(z.real());
    } else {
      add_complex_root(z);
    }
  };
  // Roots missing after the signs: polish the real ones now, so that the
  // search, deflating them, does not find them again (it did, thousands of
  // times an orbit of the N = 1,000 chain).
  if (found < k - 1) polish_real(true);
  // Stage 2: complex pairs near the rootless segments' extrema (where two
  // real roots met and left the axis, at the quadratic estimate).
  for (const Start& start : starts) {
    if (found >= k - 1) break;
    if (const std::optional<Complex> z = laguerre(start.z)) add_found(*z);
  }
  polish_real(found < k - 1);
  // Stage 4: Laguerre from the extrema again (the deflation now holds more
  // roots) and then from points on circles around the poles: at most as many
  // starts as there are rootless segments plus 3 per missing root.
  const int max_starts = static_cast<int>(starts.size()) + 3 * std::max(0, k - 1 - found);
  for (int attempt = 0; found < k - 1 && attempt < max_starts; ++attempt) {
    const Complex start = attempt < static_cast<int>(starts.size())
                              ? starts[attempt].z
                              : std::polar(1.0 + 0.5 * (attempt % 3), 2.0 * M_PI * (attempt + 0.5) / 7.0);
    if (const std::optional<Complex> z = laguerre(start)) add_found(*z);
  }
  if (found != k - 1) return false;
  for (double z : s.uncoupled) add_real_root(z);  // on the circle: |z_j| <= 2
  out = Finish(std::move(mu), complete, max_modulus, options.tol);
  return true;
}

// Gt is derived for the symmetric 1-ipp orbit of one_impact.h,
// y0 = sigma (r_i cot(w_i T / 2), r_i): other members of a larger ker A_1 (at
// an internal resonance) take the dense path.
bool SymmetricOneImpact(const AnalysisBasis& b, const ModalContact& c, const Orbit& orbit) {
  const Eigen::VectorXd s = orbit.y0.tail(b.n);
  const double sigma = c.r.dot(s) / c.r_norm2;
  double defect = (s - sigma * c.r).norm();
  for (int i = 0; i < b.n; ++i) {
    const double h = 0.5 * b.omega[i] * orbit.period;
    defect = std::max(defect, std::abs(orbit.y0[i] - sigma * c.r[i] * std::cos(h) / std::sin(h)));
  }
  return defect <= 1e-9 * orbit.y0.norm();
}

}  // namespace

Eigen::MatrixXd SaltationMatrix(const AnalysisBasis& b, const Eigen::VectorXd& y_minus, int contact) {
  const ModalContact& c = b.contacts[contact];
  const Eigen::MatrixXd reset = ImpactMatrix(b, c, AnalysisBasis::kRestitution);
  const Eigen::VectorXd y_plus = reset * y_minus;
  Eigen::VectorXd normal = Eigen::VectorXd::Zero(2 * b.n);
  normal.head(b.n) = c.r_over_omega;  // gradient of x_c = n_j . x
  const Eigen::VectorXd f_minus = Field(b, y_minus);
  const double rate = normal.dot(f_minus);  // v_c just before the impact
  return reset + (Field(b, y_plus) - reset * f_minus) * normal.transpose() / rate;
}

Eigen::MatrixXd Monodromy(const AnalysisBasis& b, const Orbit& orbit) {
  Eigen::MatrixXd m;
  if (!DenseMonodromy(b, orbit, m)) m.setConstant(std::numeric_limits<double>::quiet_NaN());
  return m;
}

double OneImpactSecular::Value(double x) const {
  double v = 0.0;
  SecularAt(*this, x, &v, nullptr);
  return v;
}

OneImpactSecular OneImpactSecularFunction(const AnalysisBasis& b, double period, int contact) {
  b.RequireElastic("1-impact orbits");
  const ModalContact& mc = b.contacts[contact];
  OneImpactSecular s;
  std::vector<double> z, a, bb, c, free;
  for (int i = 0; i < b.n; ++i) {
    const double rho = mc.r[i] * mc.r[i] / mc.r_norm2;
    const double h = 0.5 * b.omega[i] * period;
    if (rho == 0.0) {
      free.push_back(2.0 * std::cos(2.0 * h));
      continue;
    }
    z.push_back(2.0 * std::cos(2.0 * h));
    a.push_back(rho);
    bb.push_back(rho * std::sin(2.0 * h) / b.omega[i]);
    c.push_back(rho * b.omega[i] * std::cos(h) / std::sin(h));
  }
  auto vec = [](const std::vector<double>& v) {
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  };
  s.z = vec(z);
  s.a = vec(a);
  s.b = vec(bb);
  s.c = vec(c);
  s.uncoupled = vec(free);
  return s;
}

Stability OrbitStability(const AnalysisBasis& b, const Orbit& orbit, const StabilityOptions& options) {
  const int dim = 2 * b.n;
  if (orbit.impacts == 1) {
    // The pre-impact state is N y0 (the impact is an involution).
    const int j = ContactEnding(orbit, 0);
    const ModalContact& c = b.contacts[j];
    Eigen::VectorXd y_minus = orbit.y0;
    Impact(b, c, AnalysisBasis::kRestitution, y_minus);
    if (Grazes(b, c, y_minus, c.r.norm() * orbit.y0.norm())) return Undefined(dim);
    Stability out;
    if (SymmetricOneImpact(b, c, orbit) &&
        StructuredStability(OneImpactSecularFunction(b, orbit.period, j), options, out)) {
      return out;
    }
    out = DenseStability(b, orbit, options.tol);
    out.dense_fallback = true;
    return out;
  }
  return DenseStability(b, orbit, options.tol);
}

}  // namespace nsmodal
