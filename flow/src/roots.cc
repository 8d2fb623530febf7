#include "nsmodal/roots.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_min.h>
#include <gsl/gsl_roots.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include "gsl_call.h"
#include "nsmodal/check.h"

namespace nsmodal {
namespace {

struct SolverDeleter {
  void operator()(gsl_root_fsolver* s) const { gsl_root_fsolver_free(s); }
};

struct MinimizerDeleter {
  void operator()(gsl_min_fminimizer* m) const { gsl_min_fminimizer_free(m); }
};

}  // namespace

double MinimizeOn(const std::function<double(double)>& f_in, double lo, double mid, double hi, double rel_tol) {
  internal::FiniteFunction finite(f_in, std::numeric_limits<double>::max());
  gsl_function f = finite.Gsl();
  // GSL needs f(mid) below both ends (gsl_call.h): else mid is the answer.
  const double f_mid = f.function(mid, f.params);
  if (!(f_mid < f.function(lo, f.params) && f_mid < f.function(hi, f.params))) return mid;
  std::unique_ptr<gsl_min_fminimizer, MinimizerDeleter> m(gsl_min_fminimizer_alloc(gsl_min_fminimizer_goldensection));
  if (gsl_min_fminimizer_set(m.get(), &f, mid, lo, hi) != GSL_SUCCESS) return mid;
  for (int iter = 0; iter < 200; ++iter) {  // 0.618^80 < 1e-16
    if (gsl_min_fminimizer_iterate(m.get()) != GSL_SUCCESS) break;
    const double a = gsl_min_fminimizer_x_lower(m.get()), c = gsl_min_fminimizer_x_upper(m.get());
    if (gsl_min_test_interval(a, c, 0.0, rel_tol) == GSL_SUCCESS) break;
  }
  return finite.saw_non_finite() ? mid : gsl_min_fminimizer_x_minimum(m.get());
}

double PolishRoot(const std::function<double(double)>& g, double lo, double hi) {
  const double glo = g(lo);
  const double ghi = g(hi);
  if (glo == 0.0) return lo;
  if (ghi == 0.0) return hi;
  // A bracket of finite values (GSL's error handler is never reached, gsl_call.h).
  NSMODAL_CHECK(std::isfinite(glo) && std::isfinite(ghi) && (glo < 0.0) != (ghi < 0.0));
  std::unique_ptr<gsl_root_fsolver, SolverDeleter> solver(gsl_root_fsolver_alloc(gsl_root_fsolver_brent));
  internal::FiniteFunction finite(g, 0.0);
  gsl_function f = finite.Gsl();
  if (gsl_root_fsolver_set(solver.get(), &f, lo, hi) != GSL_SUCCESS) return 0.5 * (lo + hi);
  double root = 0.5 * (lo + hi);
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  for (int iter = 0; iter < 200; ++iter) {
    if (gsl_root_fsolver_iterate(solver.get()) != GSL_SUCCESS) break;
    if (finite.saw_non_finite()) return 0.5 * (lo + hi);
    root = gsl_root_fsolver_root(solver.get());
    const double a = gsl_root_fsolver_x_lower(solver.get());
    const double b = gsl_root_fsolver_x_upper(solver.get());
    if (gsl_root_test_interval(a, b, 0.0, 4.0 * kEps) == GSL_SUCCESS) break;
  }
  return root;
}

std::vector<double> IsolateRoots(const std::function<std::pair<double, double>(double)>& g_dg, double l1,
                                 double l2, double a, double b, double min_width, long max_cells, bool* complete) {
  if (complete != nullptr) *complete = true;
  long cells = 0;
  std::vector<double> roots;
  struct Cell {
    double p, q, gp, gq, dp, dq;
  };
  auto opposite = [](double x, double y) { return (x < 0.0) != (y < 0.0); };
  auto g = [&g_dg](double t) { return g_dg(t).first; };
  auto make = [](double p, double q, std::pair<double, double> at_p, std::pair<double, double> at_q) {
    return Cell{p, q, at_p.first, at_q.first, at_p.second, at_q.second};
  };
  std::vector<Cell> stack{make(a, b, g_dg(a), g_dg(b))};
  while (!stack.empty()) {
    if (++cells > max_cells) {
      if (complete != nullptr) *complete = false;
      break;
    }
    const Cell c = stack.back();
    stack.pop_back();
    const bool zero_p = c.gp == 0.0, zero_q = c.gq == 0.0;
    if (zero_p) roots.push_back(c.p);
    if (zero_q) roots.push_back(c.q);
    const double width = c.q - c.p;
    const bool sign_change = !zero_p && !zero_q && opposite(c.gp, c.gq);
    // No root inside: |g(t)| >= |g(p)| - L1 (t - p) and >= |g(q)| - L1 (q - t).
    if (!sign_change && std::abs(c.gp) + std::abs(c.gq) > l1 * width) continue;
    // g monotone: g' keeps its sign, by the same argument with L2.
    const bool monotone = !opposite(c.dp, c.dq) && std::abs(c.dp) + std::abs(c.dq) > l2 * width;
    if (monotone || width < min_width) {
      if (sign_change) {
        roots.push_back(PolishRoot(g, c.p, c.q));
      } else if (!monotone && !zero_p && !zero_q) {
        roots.push_back(0.5 * (c.p + c.q));  // a tangency to within min_width
      }
      continue;
    }
    const double m = 0.5 * (c.p + c.q);
    const std::pair<double, double> at_m = g_dg(m);
    stack.push_back(make(m, c.q, at_m, {c.gq, c.dq}));
    stack.push_back(make(c.p, m, {c.gp, c.dp}, at_m));
  }
  std::sort(roots.begin(), roots.end());
  // A root on a shared cell boundary, or a tangency seen by adjacent cells, is one root.
  std::vector<double> unique;
  for (double r : roots) {
    if (unique.empty() || r - unique.back() > 2.0 * min_width) unique.push_back(r);
  }
  return unique;
}

}  // namespace nsmodal
