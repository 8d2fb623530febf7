#pragma once
// The continuation machinery shared by response.cc (a response followed in
// one parameter) and curve.cc (a special point followed in two). Internal.
//
// A point is xi = (u scaled, lambda scaled): the response problem's k
// unknowns u (forced_orbit.h: phi / 2 pi, tau_i / P0, rigid shifts c / d)
// and p parameters (1 or 2), each divided by its range's width. The
// equations are the k impact conditions H (scaled by the least gap struck)
// and, with two parameters, a defining condition g of the special point
// followed (Condition): p - 1 + k equations in k + p unknowns, a curve.
// Tangent: the kernel of the Jacobian (central differences); corrector:
// Newton on [F(xi); n'(xi - xi0)] = 0.
#include <Eigen/Dense>
#include <complex>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "nsmodal/forced_orbit.h"

namespace nsmodal::detail {

using Vec = Eigen::VectorXd;

// The response problem of m impacts (the sequence (0, ..., 0)) or of
// `sequence` when it is not empty, in n forcing periods, at (w, a): throws
// ForcedProblem's InputError where it cannot be posed.
std::unique_ptr<ForcedProblem> MakeForcedProblem(const Model& model, int impacts, const std::vector<int>& sequence,
                                                 int periods, double w, double a);
// The same, null where it cannot be posed or has another number of unknowns
// than `unknowns` (a parameter's value outside a continuation's domain).
std::unique_ptr<ForcedProblem> PosedProblem(const Model& model, int impacts, const std::vector<int>& sequence,
                                            int periods, double w, double a, int unknowns);

// The defining condition of a point followed in two parameters:
//   fold             det dH/du = 0 (u scaled; central differences, step 1e-5:
//                    truncation ~1e-10, round-off ~1e-11);
//   period-doubling  prod (1 + mu_i) = 0 (PeriodDoublingTest);
//   grazing          max_interior_gap / d = 0 (an interior maximum of a
//                    contact's n.x at its wall; d the least gap struck).
enum class Condition { kNone, kFold, kPeriodDoubling, kGrazing };

struct TracerSetup {
  // The response problem at the parameters' values (m >= 1); null outside
  // the continuation's domain.
  std::function<std::unique_ptr<ForcedProblem>(const Vec& lambda)> problem;
  // m = 0 (the linear response, no unknowns): the orbit at the parameters'
  // values; nullopt outside the domain.
  std::function<std::optional<ForcedOrbit>(const Vec& lambda)> linear;
  int impacts = 1;   // m
  int unknowns = 1;  // k = m + rigid-body modes
  Vec lambda_scale;  // one per parameter: the range's width
  double period_scale = 1.0, gap_scale = 1.0;
  // A parameter column one-sided where the other side leaves the domain (a
  // model parameter at the end of its valid range, e = 1).
  bool one_sided = false;
  Condition condition = Condition::kNone;
  double jacobian_step = 1e-7;  // central differences of F in xi
  // Newton converged: the step below step_tol (1 + |xi|), |H| <= 1e-12 and
  // |g| <= condition_tol.
  double step_tol = 1e-12, condition_tol = 1e-12;
};

class Tracer {
 public:
  explicit Tracer(TracerSetup setup);
  int dim() const { return k_ + params(); }
  int params() const { return static_cast<int>(s_.lambda_scale.size()); }
  int unknowns() const { return k_; }
  double Lambda(const Vec& xi, int i = 0) const { return xi[k_ + i] * s_.lambda_scale[i]; }
  Vec Lambdas(const Vec& xi) const { return xi.tail(params()).cwiseProduct(s_.lambda_scale); }
  double LambdaScale(int i = 0) const { return s_.lambda_scale[i]; }
  Condition condition() const { return s_.condition; }
  // (m >= 1.)
  std::unique_ptr<ForcedProblem> Problem(const Vec& lambda) const { return s_.problem(lambda); }
  std::unique_ptr<ForcedProblem> Problem(double lambda) const { return Problem(Vec::Constant(1, lambda)); }
  Vec U(const Vec& xi) const;
  Vec Xi(const Vec& u, const Vec& lambda) const;
  Vec Xi(const Vec& u, double lambda) const { return Xi(u, Vec::Constant(1, lambda)); }
  // F(xi): the impact conditions, then the defining condition; false outside
  // the domain.
  bool H(const Vec& xi, Vec& r) const;
  // dF/dxi, (dim - 1) x dim, by central differences (jacobian_step); on the
  // edge of the domain the parameters' columns one-sided (one_sided).
  bool Jacobian(const Vec& xi, Eigen::MatrixXd& j) const;
  // The unit kernel vector of J, oriented along `along`.
  static Vec Tangent(const Eigen::MatrixXd& j, const Vec& along);
  // Newton on [F(xi); n'(xi - xi0)] = 0: the curve's crossing of the
  // hyperplane through xi0 normal to n.
  std::optional<Vec> Correct(Vec xi, const Vec& xi0, const Vec& n) const;
  // A corrected step from xi along t (predictor pred, step h) is taken when
  // it moves forward along the curve and did not jump to another: within
  // h / 2 of the predictor.
  static bool Accepted(const Vec& xi, const Vec& t, const Vec& pred, const std::optional<Vec>& next, double h) {
    return next && (*next - xi).dot(t) > 0.0 && (*next - pred).norm() <= 0.5 * h;
  }
  // The orbit at a fixed value of the one parameter from a guess (p = 1).
  std::optional<Vec> SolveAt(double lambda, const Vec& guess) const;
  // (At a solution: inside the domain.)
  ForcedOrbit Orbit(const Vec& xi) const;
  // A defining condition's value at xi (any of them, whichever one the
  // tracer follows): nullopt outside the domain or where it is undefined
  // (fold with no unknowns; grazing with no interior maximum).
  std::optional<double> ConditionAt(Condition c, const Vec& xi) const { return Value(c, xi, nullptr); }
  // The same with the orbit at xi known.
  std::optional<double> ConditionAt(Condition c, const Vec& xi, const ForcedOrbit& orbit) const {
    return Value(c, xi, &orbit);
  }

 private:
  bool Residual(const Vec& xi, Vec& r) const;  // the impact conditions only
  std::optional<double> Value(Condition c, const Vec& xi, const ForcedOrbit* orbit) const;

  TracerSetup s_;
  int m_, k_;
};

// Test functions along a branch.
// The upper member of a complex pair of multipliers (Im mu > 0 counts each
// pair once; |Im| <= 1e-10 |mu| is real).
bool UpperOfPair(const std::complex<double>& mu);
int ComplexPairs(const ForcedOrbit& o);
// Neimark-Sacker: prod over the complex pairs of (|mu|^2 - 1), nullopt with
// no complex pair.
std::optional<double> TorusTest(const ForcedOrbit& o);
// Re prod (1 + mu_i): changes sign where a real multiplier crosses -1.
double PeriodDoublingTest(const ForcedOrbit& o);

// The location of a special point between two points of a curve: Brent on a
// test function along the chord's hyperplanes.
class SegmentLocator {
 public:
  SegmentLocator(const Tracer& tr, const Vec& a, const Vec& b) : tr_(tr), a_(a), chord_(b - a) {
    n_ = chord_.normalized();
  }
  std::optional<Vec> At(double sigma) const { return tr_.Correct(a_ + sigma * chord_, a_ + sigma * chord_, n_); }
  // The root of test(xi, tangent) on (0, 1); nullopt if the corrector fails
  // or the test has the same sign at both ends.
  std::optional<Vec> Root(const std::function<double(const Vec&, const Vec&)>& test) const;
  // The period doubling between the ends (PeriodDoublingTest's sign change):
  // nullopt when not located or when no multiplier is within 1e-6 of -1
  // there (at a zero-velocity impact the saltation's 1 / v_c sends the
  // multipliers through a pole, which changes the test's sign too).
  std::optional<Vec> PeriodDoubling() const;

 private:
  const Tracer& tr_;
  Vec a_, chord_, n_;
};

}  // namespace nsmodal::detail
