#include "tracer.h"

#include <cmath>
#include <limits>
#include <utility>

#include "nsmodal/check.h"
#include "nsmodal/error.h"
#include "nsmodal/roots.h"

namespace nsmodal::detail {

std::unique_ptr<ForcedProblem> MakeForcedProblem(const Model& model, int impacts, const std::vector<int>& sequence,
                                                 int periods, double w, double a) {
  return sequence.empty() ? std::make_unique<ForcedProblem>(model, impacts, periods, w, a)
                          : std::make_unique<ForcedProblem>(model, sequence, periods, w, a);
}

std::unique_ptr<ForcedProblem> PosedProblem(const Model& model, int impacts, const std::vector<int>& sequence,
                                            int periods, double w, double a, int unknowns) {
  std::unique_ptr<ForcedProblem> p;
  try {
    p = MakeForcedProblem(model, impacts, sequence, periods, w, a);
  } catch (const InputError&) {
    return nullptr;
  }
  return p->unknowns() == unknowns ? std::move(p) : nullptr;
}

Tracer::Tracer(TracerSetup setup) : s_(std::move(setup)), m_(s_.impacts), k_(s_.unknowns) {
  NSMODAL_CHECK(s_.lambda_scale.size() == 1 || s_.lambda_scale.size() == 2);
  NSMODAL_CHECK((s_.lambda_scale.size() == 2) == (s_.condition != Condition::kNone));
  NSMODAL_CHECK(m_ > 0 ? static_cast<bool>(s_.problem) : static_cast<bool>(s_.linear));
}

Vec Tracer::U(const Vec& xi) const {
  Vec u = xi.head(k_);
  if (k_ > 0) u[0] *= 2.0 * M_PI;
  for (int i = 1; i < m_; ++i) u[i] *= s_.period_scale;
  for (int i = m_; i < k_; ++i) u[i] *= s_.gap_scale;
  return u;
}

Vec Tracer::Xi(const Vec& u, const Vec& lambda) const {
  Vec xi(dim());
  xi.head(k_) = u;
  if (k_ > 0) xi[0] /= 2.0 * M_PI;
  for (int i = 1; i < m_; ++i) xi[i] /= s_.period_scale;
  for (int i = m_; i < k_; ++i) xi[i] /= s_.gap_scale;
  xi.tail(params()) = lambda.cwiseQuotient(s_.lambda_scale);
  return xi;
}

bool Tracer::Residual(const Vec& xi, Vec& r) const {
  if (m_ == 0) {
    r.resize(0);
    return true;
  }
  const std::unique_ptr<ForcedProblem> p = Problem(Lambdas(xi));
  if (!p || !p->Residual(U(xi), r)) return false;
  r /= p->gap_scale();
  return true;
}

std::optional<double> Tracer::Value(Condition c, const Vec& xi, const ForcedOrbit* orbit) const {
  switch (c) {
    case Condition::kNone: break;
    case Condition::kFold: {
      if (k_ == 0) return std::nullopt;
      // det dH/du (u scaled): central differences, h = 1e-5 (truncation
      // ~h^2 = 1e-10 relative, round-off ~1e-16 / h = 1e-11).
      const double h = 1e-5;
      Eigen::MatrixXd j(k_, k_);
      Vec rp, rm;
      for (int i = 0; i < k_; ++i) {
        Vec a = xi, b = xi;
        a[i] += h;
        b[i] -= h;
        if (!Residual(a, rp) || !Residual(b, rm)) return std::nullopt;
        j.col(i) = (rp - rm) / (2.0 * h);
      }
      return j.determinant();
    }
    case Condition::kPeriodDoubling:
    case Condition::kGrazing: {
      if (!orbit && c == Condition::kGrazing && m_ > 0) {
        // (Only the interior maxima: the rest of the orbit is not needed.)
        const std::unique_ptr<ForcedProblem> p = Problem(Lambdas(xi));
        const std::optional<double> gap = p ? p->MaxInteriorGap(U(xi)) : std::nullopt;
        if (!gap || !std::isfinite(*gap)) return std::nullopt;
        return *gap / s_.gap_scale;
      }
      std::optional<ForcedOrbit> own;
      if (!orbit) {
        if (m_ == 0) {
          own = s_.linear(Lambdas(xi));
        } else {
          // (One problem for the domain's check and the orbit.)
          const std::unique_ptr<ForcedProblem> p = Problem(Lambdas(xi));
          Vec r;
          if (p && p->Residual(U(xi), r)) own = p->Orbit(U(xi));
        }
        if (!own) return std::nullopt;
        orbit = &*own;
      }
      if (c == Condition::kPeriodDoubling) return PeriodDoublingTest(*orbit);
      if (!std::isfinite(orbit->max_interior_gap)) return std::nullopt;
      return orbit->max_interior_gap / s_.gap_scale;
    }
  }
  return std::nullopt;
}

bool Tracer::H(const Vec& xi, Vec& r) const {
  if (m_ == 0 && !s_.linear(Lambdas(xi))) return false;
  if (!Residual(xi, r)) return false;
  if (s_.condition == Condition::kNone) return true;
  const std::optional<double> g = Value(s_.condition, xi, nullptr);
  if (!g || !std::isfinite(*g)) return false;
  r.conservativeResize(r.size() + 1);
  r[r.size() - 1] = *g;
  return true;
}

bool Tracer::Jacobian(const Vec& xi, Eigen::MatrixXd& j) const {
  const int rows = dim() - 1;
  j.resize(rows, dim());
  Vec rp, rm, r0;
  for (int k = 0; k < dim(); ++k) {
    const double h = s_.jacobian_step;
    Vec a = xi, b = xi;
    a[k] += h;
    b[k] -= h;
    const bool up = H(a, rp), down = H(b, rm);
    if (up && down) {
      j.col(k) = (rp - rm) / (2.0 * h);
    } else if (k >= k_ && s_.one_sided && (up || down) && (r0.size() > 0 || H(xi, r0))) {
      j.col(k) = up ? (rp - r0) / h : (r0 - rm) / h;
    } else {
      return false;
    }
  }
  return true;
}

Vec Tracer::Tangent(const Eigen::MatrixXd& j, const Vec& along) {
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(j.transpose());
  Vec t = qr.householderQ() * Vec::Unit(j.cols(), j.cols() - 1);
  if (t.dot(along) < 0.0) t = -t;
  return t;
}

std::optional<Vec> Tracer::Correct(Vec xi, const Vec& xi0, const Vec& n) const {
  Vec r;
  Eigen::MatrixXd j;
  const bool extra = s_.condition != Condition::kNone;
  auto converged = [&](const Vec& res) {
    const int conditions = k_;  // the impact conditions' rows
    if (conditions > 0 && res.head(conditions).cwiseAbs().maxCoeff() > 1e-12) return false;
    return !extra || std::abs(res[conditions]) <= s_.condition_tol;
  };
  for (int it = 0; it < 12; ++it) {
    if (!H(xi, r) || !Jacobian(xi, j)) return std::nullopt;
    Eigen::MatrixXd a(dim(), dim());
    a << j, n.transpose();
    Vec f(dim());
    f << r, n.dot(xi - xi0);
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
    if (!lu.isInvertible()) return std::nullopt;
    const Vec step = lu.solve(-f);
    xi += step;
    if (!xi.allFinite()) return std::nullopt;
    if (step.norm() <= s_.step_tol * (1.0 + xi.norm())) {
      if (H(xi, r) && converged(r)) return xi;
    }
  }
  return std::nullopt;
}

std::optional<Vec> Tracer::SolveAt(double lambda, const Vec& guess) const {
  NSMODAL_CHECK(params() == 1 && m_ > 0);
  const std::unique_ptr<ForcedProblem> p = Problem(lambda);
  if (!p) return std::nullopt;
  const std::optional<Vec> u = p->Solve(U(guess));
  if (!u) return std::nullopt;
  return Xi(*u, lambda);
}

ForcedOrbit Tracer::Orbit(const Vec& xi) const {
  if (m_ == 0) {
    const std::optional<ForcedOrbit> o = s_.linear(Lambdas(xi));
    NSMODAL_CHECK(o.has_value());
    return *o;
  }
  const std::unique_ptr<ForcedProblem> p = Problem(Lambdas(xi));
  NSMODAL_CHECK(p != nullptr);
  return p->Orbit(U(xi));
}

bool UpperOfPair(const std::complex<double>& mu) { return mu.imag() > 1e-10 * std::abs(mu); }

int ComplexPairs(const ForcedOrbit& o) {
  int n = 0;
  for (int i = 0; i < o.multipliers.size(); ++i) n += UpperOfPair(o.multipliers[i]);
  return n;
}

std::optional<double> TorusTest(const ForcedOrbit& o) {
  double p = 1.0;
  bool any = false;
  for (int i = 0; i < o.multipliers.size(); ++i) {
    if (UpperOfPair(o.multipliers[i])) {
      p *= std::norm(o.multipliers[i]) - 1.0;
      any = true;
    }
  }
  return any ? std::optional<double>(p) : std::nullopt;
}

double PeriodDoublingTest(const ForcedOrbit& o) {
  std::complex<double> p = 1.0;
  for (int i = 0; i < o.multipliers.size(); ++i) p *= 1.0 + o.multipliers[i];
  return p.real();
}

std::optional<Vec> SegmentLocator::Root(const std::function<double(const Vec&, const Vec&)>& test) const {
  bool failed = false;
  auto g = [&](double sigma) {
    const std::optional<Vec> xi = At(sigma);
    Eigen::MatrixXd j;
    if (!xi || !tr_.Jacobian(*xi, j)) {
      failed = true;
      return std::numeric_limits<double>::quiet_NaN();
    }
    return test(*xi, Tracer::Tangent(j, n_));
  };
  const double g0 = g(0.0), g1 = g(1.0);
  if (failed || !((g0 < 0.0) != (g1 < 0.0))) return std::nullopt;
  const double sigma = PolishRoot(g, 0.0, 1.0);
  if (failed) return std::nullopt;
  return At(sigma);
}

std::optional<Vec> SegmentLocator::PeriodDoubling() const {
  const std::optional<Vec> xi = Root([&](const Vec& x, const Vec&) { return PeriodDoublingTest(tr_.Orbit(x)); });
  if (!xi || (tr_.Orbit(*xi).multipliers.array() + 1.0).abs().minCoeff() > 1e-6) return std::nullopt;
  return xi;
}

}  // namespace nsmodal::detail
