#pragma once
// Root isolation that cannot step over a root, and root polishing (GSL Brent).
#include <functional>
#include <utility>
#include <vector>

namespace nsmodal {

// Brent's method (gsl_root_fsolver_brent) on a bracket with g(lo) g(hi) <= 0.
// Converges to |hi - lo| <= 4 eps (|lo| + |hi|) or an exact zero.
double PolishRoot(const std::function<double(double)>& g, double lo, double hi);

// The minimiser of f on [lo, hi] by golden-section search (GSL), from mid
// with f(mid) below f(lo) and f(hi) (else mid is returned, as it is when f
// is not finite somewhere), to a bracket of relative width rel_tol: the
// abscissa of a smooth minimum comes out to ~sqrt(eps) relative, its value
// to ~eps.
double MinimizeOn(const std::function<double(double)>& f, double lo, double mid, double hi, double rel_tol = 1e-15);

// Every root of g on [a, b], given g' and the bounds L1 >= sup |g'| and
// L2 >= sup |g''| on [a, b]. On a cell [p, q] of width h:
//   g(p), g(q) of one sign and |g(p)| + |g(q)| > L1 h   -> provably no root;
//   g'(p), g'(q) of one sign and |g'(p)| + |g'(q)| > L2 h -> g monotone: one root
//                                    if g changes sign (polished by Brent), else none;
//   otherwise the cell is halved. A cell narrower than min_width that is still
// undecided reports one root: the Brent root on a sign change, else its
// midpoint (a tangency, an even root, to within min_width). Roots come out sorted.
// g_dg(t) returns (g(t), g'(t)). An exact zero at a cell end is a root, and the
// cell's interior is still searched.
//
// Work limit: at most max_cells cells are examined; when the limit is hit the
// search stops, *complete (if given) is set false and the roots found so far
// are returned. Callers size the limit from the problem's scales.
std::vector<double> IsolateRoots(const std::function<std::pair<double, double>(double)>& g_dg, double l1,
                                 double l2, double a, double b, double min_width, long max_cells = 100000000,
                                 bool* complete = nullptr);

}  // namespace nsmodal
