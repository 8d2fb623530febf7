#include "nsmodal/forced_orbit.h"

#include <gsl/gsl_integration.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "nsmodal/check.h"
#include "nsmodal/error.h"
#include "nsmodal/first_rise.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"
#include "nsmodal/roots.h"

namespace nsmodal {
namespace {

// The model with its harmonic force rescaled to max_i |f_i| = amplitude at w.
Model ScaledModel(const Model& model, double frequency, double amplitude) {
  if (!model.forcing.HasHarmonic()) {
    throw InputError("forcing.amplitude", "is needed: a forced response needs a harmonic force f cos(w t) "
                                          "(its direction; the level is the response's amplitude)");
  }
  if (!(frequency > 0.0) || !std::isfinite(frequency)) {
    throw InputError("forcing.frequency", "must be positive and finite for a response, got " + FormatValue(frequency));
  }
  if (!(amplitude >= 0.0) || !std::isfinite(amplitude)) {
    throw InputError("forcing.amplitude", "the response's amplitude must be >= 0 and finite, got " +
                                              FormatValue(amplitude));
  }
  Model m = model;
  m.source.reset();  // (edited below: its keys are no longer the model's)
  m.forcing.amplitude = model.forcing.amplitude * (amplitude / model.forcing.amplitude.cwiseAbs().maxCoeff());
  m.forcing.frequency = frequency;
  if (amplitude == 0.0) {
    // A zero force is no force: keep the direction with a zero level.
    m.forcing.amplitude.setZero();
  }
  Validate(m);
  return m;
}

// Gauss-Legendre nodes and weights on [-1, 1] (GSL's fixed tables).
struct Quadrature {
  static constexpr int kNodes = 10;
  double x[kNodes], w[kNodes];
  Quadrature() {
    std::unique_ptr<gsl_integration_glfixed_table, void (*)(gsl_integration_glfixed_table*)> t(
        gsl_integration_glfixed_table_alloc(kNodes), gsl_integration_glfixed_table_free);
    NSMODAL_CHECK(t != nullptr);
    for (int i = 0; i < kNodes; ++i) NSMODAL_CHECK(gsl_integration_glfixed_point(-1.0, 1.0, i, &x[i], &w[i], t.get()) == 0);
  }
};

// The one-contact sequence (0, ..., 0) of m impacts, m checked.
std::vector<int> OnFirstContact(int impacts) {
  if (impacts < 1 || impacts > kMaxResponseImpacts) {
    throw InputError("impacts", "must be between 1 and " + std::to_string(kMaxResponseImpacts) +
                                    " for an impacting response (0: the linear response), got " +
                                    std::to_string(impacts));
  }
  return std::vector<int>(impacts, 0);
}

}  // namespace

double LeastGapStruck(const Model& model, const std::vector<int>& sequence) {
  if (sequence.empty()) return model.contacts[0].gap;
  double d = std::numeric_limits<double>::infinity();
  for (int c : sequence) d = std::min(d, model.contacts[c].gap);
  return d;
}

ForcedProblem::ForcedProblem(const Model& model, int impacts, int periods, double frequency, double amplitude)
    : ForcedProblem(model, OnFirstContact(impacts), periods, frequency, amplitude) {}

ForcedProblem::ForcedProblem(const Model& model, const std::vector<int>& sequence, int periods, double frequency,
                             double amplitude)
    : model_(ScaledModel(model, frequency, amplitude)),
      sequence_(sequence),
      m_(static_cast<int>(sequence.size())),
      n_(periods),
      w_(frequency),
      amplitude_(amplitude),
      period_(periods * 2.0 * M_PI / frequency),
      fastest_(0.0),
      flow_(model_) {
  if (m_ < 1 || m_ > kMaxResponseImpacts) {
    throw InputError("sequence", "must list between 1 and " + std::to_string(kMaxResponseImpacts) +
                                     " impacts, got " + std::to_string(m_));
  }
  const int contacts = static_cast<int>(model_.contacts.size());
  for (int c : sequence_) {
    if (c < 0 || c >= contacts) {
      throw InputError("sequence", "names contact " + std::to_string(c + 1) + ", but the model has " +
                                       std::to_string(contacts) + (contacts == 1 ? " contact" : " contacts") +
                                       " (numbered from 1)");
    }
  }
  if (periods < 1 || periods > kMaxResponsePeriods) {
    throw InputError("periods", "must be between 1 and " + std::to_string(kMaxResponsePeriods) + ", got " +
                                    std::to_string(periods));
  }
  // As for free orbits (AnalysisBasis::kMaxPeriodRatio): a period longer than
  // 1e5 of the flow's fastest time scale 2 pi / max|lambda| would make NC3 and
  // the quadrature scan more than 1e5 of them per period. For a damped flow
  // that scale can be far shorter than the shortest linear period (an
  // overdamped mode decays at up to 2 zeta w_k).
  const Eigen::VectorXcd lambda = flow_.Eigenvalues();  // (empty when every mode is rigid)
  fastest_ = std::max(lambda.size() > 0 ? lambda.cwiseAbs().maxCoeff() : 0.0, w_);
  if (!(period_ * fastest_ <= 2.0 * M_PI * AnalysisBasis::kMaxPeriodRatio)) {
    throw InputError("forcing.frequency", "w = " + FormatValue(frequency) + " with n = " + std::to_string(periods) +
                                              " gives a response period of " + FormatValue(period_) +
                                              ", more than " + FormatValue(AnalysisBasis::kMaxPeriodRatio) +
                                              " times the flow's fastest time scale 2 pi / max|lambda| = " +
                                              FormatValue(2.0 * M_PI / fastest_));
  }
  bool elastic = true;  // every contact struck has e = 1
  for (int c : sequence_) elastic = elastic && model_.contacts[c].restitution == 1.0;
  gap_scale_ = LeastGapStruck(model_, sequence_);
  if (elastic && !model_.HasDamping()) {
    throw InputError("system", "has no damping and e = 1 on every contact struck: its forced periodic responses are "
                               "not isolated (the return map keeps the multiplier 1 of the free orbits, paper "
                               "section 2); give damping or e < 1");
  }
  const int n = model_.dofs();
  const Eigen::LDLT<Eigen::MatrixXd> m_ldlt(model_.mass);
  for (const Contact& contact : model_.contacts) {
    const Eigen::VectorXd minv_n = m_ldlt.solve(contact.normal);
    Eigen::MatrixXd r = Eigen::MatrixXd::Identity(2 * n, 2 * n);
    r.bottomRightCorner(n, n) -= ((1.0 + contact.restitution) / contact.Along(minv_n)) * minv_n *
                                 contact.normal.transpose();
    impact_.push_back(std::move(r));
  }
  rigid_ = flow_.rigid_modes();
  if (rigid_ > 0) {
    // The rigid modes scaled to a largest displacement of 1: the shifts c and
    // the drifts sigma P are lengths, comparable with the gaps.
    const Eigen::MatrixXd& phi_m = flow_.rigid_basis();  // M-orthonormal
    const Eigen::VectorXd scale = phi_m.cwiseAbs().colwise().maxCoeff().transpose();
    rigid_len_ = phi_m * scale.cwiseInverse().asDiagonal();
    rigid_coord_ = scale.asDiagonal() * (phi_m.transpose() * model_.mass);  // rigid_coord_ * rigid_len_ = I
    const Eigen::MatrixXd& phi0 = rigid_len_;
    kick_ = Eigen::MatrixXd::Zero(2 * n, rigid_);
    kick_.bottomRows(n) = phi0;
    gauge_ = Eigen::MatrixXd::Zero(rigid_, 2 * n);
    gauge_.leftCols(n) = rigid_coord_;
    gap_shift_.resize(m_, rigid_);
    for (int i = 0; i < m_; ++i) gap_shift_.row(i) = model_.contacts[sequence_[i]].normal.transpose() * phi0;
    const Eigen::FullPivLU<Eigen::MatrixXd> g(gap_shift_);
    if (g.rank() < rigid_) {
      throw InputError("sequence", "strikes no contact that moves " +
                                       std::string(rigid_ == 1 ? "the rigid-body mode" : "every rigid-body mode") +
                                       " (the free part's position is left undetermined): a free mass's response "
                                       "must strike a wall that stops it");
    }
  }
  minv_k_ = m_ldlt.solve(model_.stiffness);
  minv_d_ = m_ldlt.solve(model_.DampingMatrix());
  minv_f0_ = m_ldlt.solve(model_.ConstantForce());
  minv_f_ = m_ldlt.solve(model_.ForceAmplitude());
}

Eigen::VectorXd ForcedProblem::Field(double t, const Eigen::VectorXd& z) const {
  const int n = model_.dofs();
  Eigen::VectorXd f(2 * n);
  f.head(n) = z.tail(n);
  f.tail(n) = -minv_k_ * z.head(n) - minv_d_ * z.tail(n) + minv_f0_ + std::cos(w_ * t) * minv_f_;
  return f;
}

bool ForcedProblem::Run(const Eigen::VectorXd& u, Pass& pass) const {
  NSMODAL_CHECK(u.size() == unknowns());
  if (!u.allFinite()) return false;
  std::vector<double> tau(m_);
  double used = 0.0;
  for (int i = 1; i < m_; ++i) {
    tau[i - 1] = u[i];
    used += u[i];
  }
  tau[m_ - 1] = period_ - used;
  for (double t : tau) {
    if (!(t > 1e-12 * period_)) return false;
  }
  pass.times.assign(m_, u[0] / w_);
  for (int i = 1; i < m_; ++i) pass.times[i] = pass.times[i - 1] + tau[i - 1];
  // The affine map z_1+ -> z_1+ over one period.
  const int dim = 2 * model_.dofs();
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(dim, dim);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(dim);
  std::vector<Eigen::MatrixXd> e(m_);
  for (int i = 0; i < m_; ++i) {
    e[i] = flow_.Transition(tau[i]);
    const double t0 = pass.times[i];
    // Flight i ends at impact i + 1 (mod m).
    const Eigen::MatrixXd& r = impact_[sequence_[(i + 1) % m_]];
    a = r * (e[i] * a);
    b = r * (e[i] * (b - flow_.Particular(t0)) + flow_.Particular(t0 + tau[i]));
  }
  Eigen::VectorXd z;
  if (rigid_ == 0) {
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(Eigen::MatrixXd::Identity(dim, dim) - a);
    if (!(lu.rcond() > 1e-14)) return false;
    z = lu.solve(b);
  } else {
    Eigen::MatrixXd bordered = Eigen::MatrixXd::Zero(dim + rigid_, dim + rigid_);
    bordered.topLeftCorner(dim, dim) = Eigen::MatrixXd::Identity(dim, dim) - a;
    bordered.topRightCorner(dim, rigid_) = kick_;
    bordered.bottomLeftCorner(rigid_, dim) = gauge_;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(dim + rigid_);
    rhs.head(dim) = b;
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(bordered);
    if (!(lu.rcond() > 1e-14)) return false;
    const Eigen::VectorXd sol = lu.solve(rhs);
    z = sol.head(dim);
    z.head(model_.dofs()) += rigid_len_ * u.tail(rigid_);
    pass.drift = sol.tail(rigid_) * period_;
  }
  pass.before.assign(m_, Eigen::VectorXd());
  pass.after.assign(m_, Eigen::VectorXd());
  pass.after[0] = z;
  for (int i = 0; i < m_; ++i) {
    const double t0 = pass.times[i];
    const Eigen::VectorXd zb = flow_.Particular(t0 + tau[i]) + e[i] * (z - flow_.Particular(t0));
    const int next = (i + 1) % m_;
    pass.before[next] = zb;
    z = impact_[sequence_[next]] * zb;
    if (next != 0) pass.after[next] = z;
  }
  return true;
}

bool ForcedProblem::Residual(const Eigen::VectorXd& u, Eigen::VectorXd& r) const {
  Pass pass;
  if (!Run(u, pass)) return false;
  r.resize(unknowns());
  const int n = model_.dofs();
  for (int i = 0; i < m_; ++i) {
    const Contact& contact = model_.contacts[sequence_[i]];
    r[i] = contact.Along(pass.before[i].head(n)) - contact.gap;
  }
  if (rigid_ > 0) r.tail(rigid_) = pass.drift;
  return r.allFinite();
}

std::optional<Eigen::VectorXd> ForcedProblem::Solve(Eigen::VectorXd u, int max_iterations, double tol) const {
  const int k_count = unknowns();
  Eigen::VectorXd r(k_count), rp(k_count), rm(k_count);
  if (!Residual(u, r)) return std::nullopt;
  for (int it = 0; it < max_iterations; ++it) {
    if (r.cwiseAbs().maxCoeff() <= tol * gap_scale_) return u;
    // Central differences: the Jacobian to ~h^2, enough for Newton's
    // quadratic convergence to the residual's round-off.
    Eigen::MatrixXd j(k_count, k_count);
    for (int k = 0; k < k_count; ++k) {
      // (The residual is affine in a shift c: any step is exact.)
      const double h = 1e-6 * (k == 0 ? 1.0 : k < m_ ? period_ : gap_scale_);
      Eigen::VectorXd up = u, um = u;
      up[k] += h;
      um[k] -= h;
      if (!Residual(up, rp) || !Residual(um, rm)) return std::nullopt;
      j.col(k) = (rp - rm) / (2.0 * h);
    }
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(j);
    if (!lu.isInvertible()) return std::nullopt;
    const Eigen::VectorXd step = lu.solve(-r);
    // Backtracking: the full step unless it leaves the domain or does not
    // reduce the residual.
    double lambda = 1.0;
    bool moved = false;
    for (int k = 0; k < 12 && !moved; ++k, lambda *= 0.5) {
      const Eigen::VectorXd trial = u + lambda * step;
      if (Residual(trial, rp) && rp.norm() < r.norm()) {
        u = trial;
        r = rp;
        moved = true;
      }
    }
    if (!moved) return r.cwiseAbs().maxCoeff() <= 1e3 * tol * gap_scale_ ? std::optional(u) : std::nullopt;
  }
  return r.cwiseAbs().maxCoeff() <= tol * gap_scale_ ? std::optional(u) : std::nullopt;
}

Eigen::VectorXd ForcedProblem::Canonical(const Eigen::VectorXd& u) const {
  const double cycle = 2.0 * M_PI / w_;
  std::vector<double> tau(m_);
  double used = 0.0;
  for (int i = 1; i < m_; ++i) used += (tau[i - 1] = u[i]);
  tau[m_ - 1] = period_ - used;
  std::vector<double> t(m_, u[0] / w_);
  for (int i = 1; i < m_; ++i) t[i] = t[i - 1] + tau[i - 1];
  int best = 0;
  double best_phase = std::numeric_limits<double>::infinity();
  for (int k = 0; k < m_; ++k) {
    if (!SequenceKeptBy(sequence_, k)) continue;  // only a start that leaves the sequence as it is
    double p = std::fmod(t[k], cycle);
    if (p < 0.0) p += cycle;
    // Equal phases (1e-12 of a cycle) keep the earlier impact: n > 1 orbits
    // can meet the same forcing phase at two impacts.
    if (p < best_phase - 1e-12 * cycle) {
      best_phase = p;
      best = k;
    }
  }
  Eigen::VectorXd out(unknowns());
  out[0] = w_ * best_phase;
  for (int i = 1; i < m_; ++i) out[i] = tau[(best + i - 1) % m_];
  out.tail(rigid_) = u.tail(rigid_);
  if (rigid_ > 0 && best != 0) {
    // The shift is the free part's position just after the first impact:
    // started at impact `best`, it is the position there.
    Pass pass;
    if (Run(u, pass)) out.tail(rigid_) = rigid_coord_ * pass.after[best].head(model_.dofs());
  }
  return out;
}

std::vector<Eigen::VectorXd> ForcedProblem::FindAll() const {
  std::vector<Eigen::VectorXd> found;
  auto add = [&](const std::optional<Eigen::VectorXd>& sol) {
    if (!sol) return;
    const Eigen::VectorXd c = Canonical(*sol);
    for (const Eigen::VectorXd& f : found) {
      Eigen::VectorXd d = f - c;
      d[0] = std::remainder(d[0], 2.0 * M_PI);
      if (d.cwiseAbs().maxCoeff() <= 1e-7 * std::max(1.0, period_)) return;
    }
    found.push_back(c);
  };
  if (m_ == 1 && rigid_ == 0) {
    // r(phi) on 256 phases; Brent on each sign change, then Newton.
    constexpr int kScan = 256;
    Eigen::VectorXd r(1), u(1);
    double prev_phi = 0.0, prev_r = std::numeric_limits<double>::quiet_NaN();
    for (int k = 0; k <= kScan; ++k) {
      const double phi = 2.0 * M_PI * k / kScan;
      u[0] = phi;
      const double val = Residual(u, r) ? r[0] : std::numeric_limits<double>::quiet_NaN();
      if (std::isfinite(val) && std::isfinite(prev_r) && (val == 0.0 || (val > 0.0) != (prev_r > 0.0))) {
        auto g = [&](double p) {
          Eigen::VectorXd uu(1), rr(1);
          uu[0] = p;
          return Residual(uu, rr) ? rr[0] : std::numeric_limits<double>::quiet_NaN();
        };
        const double root = PolishRoot(g, prev_phi, phi);
        Eigen::VectorXd start(1);
        start[0] = root;
        add(Solve(start));
      }
      prev_phi = phi;
      prev_r = val;
    }
    return found;
  }
  // m >= 2 (or rigid-body modes): the residual on a grid of phases and
  // flight durations (K per axis, fewer as m grows), Newton from each local
  // minimum of |r| (over the grid neighbours, the phase periodic). The rigid
  // shifts c at a grid point: those that fit the gaps best (least squares;
  // the gaps are affine in c, the drifts do not depend on it).
  const int k_axis = m_ == 1 ? 64 : m_ == 2 ? 32 : (m_ == 3 ? 12 : 6);
  long cells = 1;
  for (int i = 0; i < m_; ++i) cells *= k_axis;
  const int k_count = unknowns();
  std::optional<Eigen::ColPivHouseholderQR<Eigen::MatrixXd>> fit;
  if (rigid_ > 0) fit.emplace(gap_shift_);
  auto point = [&](long index) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(k_count);
    for (int i = 0; i < m_; ++i, index /= k_axis) {
      const long k = index % k_axis;
      u[i] = i == 0 ? 2.0 * M_PI * (k + 0.5) / k_axis : period_ * (k + 0.5) / (k_axis * (m_ - 1) + 1);
    }
    Eigen::VectorXd r;
    if (fit && Residual(u, r)) u.tail(rigid_) = -fit->solve(r.head(m_));
    return u;
  };
  std::vector<double> norm(cells, std::numeric_limits<double>::infinity());
  Eigen::VectorXd r(k_count);
  for (long c = 0; c < cells; ++c) {
    if (Residual(point(c), r)) norm[c] = r.norm();
  }
  for (long c = 0; c < cells; ++c) {
    if (!std::isfinite(norm[c])) continue;
    bool minimum = true;
    long stride = 1;
    for (int i = 0; i < m_ && minimum; ++i, stride *= k_axis) {
      const long k = (c / stride) % k_axis;
      for (int dk : {-1, 1}) {
        long kk = k + dk;
        if (i == 0) kk = (kk + k_axis) % k_axis;  // the phase wraps
        if (kk < 0 || kk >= k_axis) continue;
        if (norm[c + (kk - k) * stride] < norm[c]) minimum = false;
      }
    }
    if (minimum) add(Solve(point(c)));
  }
  return found;
}

double ForcedProblem::InteriorMaximum(const DampedSignal& g, double tau) const {
  // Interior maxima: g' from + to - between samples 1/16 of the fastest
  // time scale apart, polished by Brent on g'.
  double most = -std::numeric_limits<double>::infinity();
  const int samples = 16 + static_cast<int>(std::ceil(tau * fastest_ * 16.0 / (2.0 * M_PI)));
  double prev_s = 0.0, prev_v = g.Velocity(0.0);
  for (int k = 1; k <= samples; ++k) {
    const double s = tau * k / samples;
    const double v = g.Velocity(s);
    if (prev_v > 0.0 && v <= 0.0 && k < samples) {
      const double smax = PolishRoot([&](double x) { return g.Velocity(x); }, prev_s, s);
      most = std::max(most, g.Position(smax));
    }
    prev_s = s;
    prev_v = v;
  }
  return most;
}

std::optional<double> ForcedProblem::MaxInteriorGap(const Eigen::VectorXd& u) const {
  Pass pass;
  if (!Run(u, pass)) return std::nullopt;
  const int n = model_.dofs();
  double most = -std::numeric_limits<double>::infinity();
  DampedSignal g;
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(2 * n);
  for (int i = 0; i < m_; ++i) {
    const double t0 = pass.times[i];
    const double tau = (i + 1 < m_ ? pass.times[i + 1] : pass.times[0] + period_) - t0;
    for (const Contact& contact : model_.contacts) {
      row.head(n) = contact.normal.transpose();
      flow_.Observe(t0, pass.after[i], row, -contact.gap, 0.0, g);
      most = std::max(most, InteriorMaximum(g, tau));
    }
  }
  return most;
}

ForcedOrbit ForcedProblem::Orbit(const Eigen::VectorXd& u) const {
  Pass pass;
  const bool ok = Run(u, pass);
  NSMODAL_CHECK(ok);
  const int n = model_.dofs();
  const int contacts = static_cast<int>(model_.contacts.size());
  ForcedOrbit o;
  o.impacts = m_;
  o.periods = n_;
  o.sequence = sequence_;
  o.frequency = w_;
  o.amplitude = amplitude_;
  o.period = period_;
  o.u = u;
  o.times = pass.times;
  o.before = pass.before;
  o.after = pass.after;
  o.min_impact_velocity = std::numeric_limits<double>::infinity();
  // Contact 1's largest n_1 . x: at its own impacts d_1, elsewhere where the
  // flights take it.
  double max_x1 = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < m_; ++i) {
    const Contact& contact = model_.contacts[sequence_[i]];
    o.residual = std::max(o.residual, std::abs(contact.Along(pass.before[i].head(n)) - contact.gap));
    o.min_impact_velocity = std::min(o.min_impact_velocity, contact.Along(pass.before[i].tail(n)));
    o.impact_loss += MechanicalEnergy(model_, pass.before[i]) - MechanicalEnergy(model_, pass.after[i]);
    const Contact& first = model_.contacts[0];
    max_x1 = std::max(max_x1, sequence_[i] == 0 ? first.gap : first.Along(pass.before[i].head(n)));
  }
  // Flights: energy integrals by Gauss-Legendre panels no longer than an
  // eighth of the fastest time scale (the integrands are smooth there: the
  // quadrature is exact to round-off); interior maxima of each contact's
  // n_j . x; NC3 on every contact.
  static const Quadrature q;
  std::vector<Eigen::RowVectorXd> gap_row(contacts, Eigen::RowVectorXd::Zero(2 * n));
  for (int j = 0; j < contacts; ++j) gap_row[j].head(n) = model_.contacts[j].normal.transpose();
  o.max_interior_gap = -std::numeric_limits<double>::infinity();
  o.verdict = "admissible";
  o.admissible = true;
  double energy_integral = 0.0;
  DampedSignal g;
  for (int i = 0; i < m_; ++i) {
    const double t0 = pass.times[i];
    const double tau = (i + 1 < m_ ? pass.times[i + 1] : pass.times[0] + period_) - t0;
    const Eigen::VectorXd& z0 = pass.after[i];
    const int panels = 1 + static_cast<int>(std::ceil(tau * fastest_ / (M_PI / 4.0)));
    const double hp = tau / panels;
    for (int p = 0; p < panels; ++p) {
      for (int k = 0; k < Quadrature::kNodes; ++k) {
        const double s = hp * (p + 0.5 * (q.x[k] + 1.0));
        Eigen::VectorXd z = z0;
        flow_.Advance(t0, s, z);
        const double wt = 0.5 * hp * q.w[k];
        const Eigen::VectorXd v = z.tail(n);
        energy_integral += wt * MechanicalEnergy(model_, z);
        o.work += wt * v.dot(model_.ConstantForce() + std::cos(w_ * (t0 + s)) * model_.ForceAmplitude());
        o.dissipated += wt * v.dot(model_.DampingMatrix() * v);
      }
    }
    const int next = (i + 1) % m_;
    for (int j = 0; j < contacts; ++j) {
      const Contact& contact = model_.contacts[j];
      const double d = contact.gap;
      flow_.Observe(t0, z0, gap_row[j], -d, 0.0, g);
      const double excess = InteriorMaximum(g, tau);
      o.max_interior_gap = std::max(o.max_interior_gap, excess);
      if (j == 0) max_x1 = std::max(max_x1, d + excess);
      // NC3, exactly: the guaranteed search finds the first time the flight
      // meets contact j; only the contact struck at its end may be met, and
      // only there.
      if (o.admissible) {
        const double tol = 1e-13 * std::max(d, g.bound[0]);
        const FirstRiseResult r = FirstRise(g, tau, tol);
        // The contact struck at the flight's end is met there, within the
        // search's band (tol / v_c in time); any other contact must not be met
        // at all before it (1e-9 P: the same instant).
        double window = 1e-9 * period_;
        if (j == sequence_[next]) {
          window += 4.0 * tol / std::max(std::abs(contact.Along(pass.before[next].tail(n))), 1e-300);
        }
        if (r.found && r.s < tau - window) {
          o.admissible = false;
          o.verdict = (contacts == 1 ? std::string("NC3: x_c reaches d") : "NC3: contact " + std::to_string(j + 1) + " (" +
                                                                                contact.Describe() + ") is reached") +
                      " inside flight " + std::to_string(i + 1) + " at t = " + FormatValue(t0 + r.s);
        }
      }
    }
  }
  o.energy = energy_integral / period_;
  o.max_xc = max_x1;
  if (o.admissible && !(o.min_impact_velocity > 0.0)) {
    o.admissible = false;
    o.verdict = "an impact arrives moving away from the obstacle (v_c = " + FormatValue(o.min_impact_velocity) + ")";
  }
  // Monodromy just after the first impact, with the saltation matrices.
  const int dim = 2 * n;
  Eigen::MatrixXd phi = Eigen::MatrixXd::Identity(dim, dim);
  for (int i = 0; i < m_; ++i) {
    const double tau = (i + 1 < m_ ? pass.times[i + 1] : pass.times[0] + period_) - pass.times[i];
    const int next = (i + 1) % m_;
    const int j = sequence_[next];
    const Eigen::MatrixXd& r = impact_[j];
    const double t_imp = pass.times[next] + (next == 0 ? period_ : 0.0);
    const Eigen::VectorXd& zm = pass.before[next];
    const Eigen::VectorXd zp = r * zm;
    Eigen::MatrixXd s = r;
    const double vc = model_.contacts[j].Along(zm.tail(n));
    if (vc != 0.0) s += (Field(t_imp, zp) - r * Field(t_imp, zm)) * gap_row[j] / vc;
    phi = s * (flow_.Transition(tau) * phi);
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(phi, false);
  o.multipliers = eig.eigenvalues();
  o.max_multiplier = o.multipliers.cwiseAbs().maxCoeff();
  o.stable = o.max_multiplier < 1.0;
  return o;
}

Eigen::VectorXd ForcedProblem::StateAt(const ForcedOrbit& orbit, double t) const {
  // The last impact at or before t (times repeat with the period).
  const double shift = std::floor((t - orbit.times[0]) / period_) * period_;
  int k = 0;
  for (int i = 0; i < m_; ++i) {
    if (orbit.times[i] + shift <= t) k = i;
  }
  Eigen::VectorXd z = orbit.after[k];
  flow_.Advance(orbit.times[k] + shift, t - (orbit.times[k] + shift), z);
  return z;
}

ForcedOrbit LinearResponse(const Model& model, double frequency, double amplitude) {
  const Model m = ScaledModel(model, frequency, amplitude);
  const ForcedFlow flow(m);
  const Contact& contact = m.contacts[0];
  const double w = frequency, d = contact.gap;
  ForcedOrbit o;
  o.impacts = 0;
  o.periods = 1;
  o.frequency = w;
  o.amplitude = amplitude;
  o.period = 2.0 * M_PI / w;
  const std::complex<double> xc = contact.normal.cast<std::complex<double>>().dot(flow.harmonic_response());
  // x_c(t) = x_s,c + |X_c| cos(w t + arg X_c): largest at w t = -arg X_c.
  double t_max = std::fmod(-std::arg(xc) / w, o.period);
  if (t_max < 0.0) t_max += o.period;
  // Each contact's largest excess n_j . x_s + |n_j . X| - d_j.
  const int k = static_cast<int>(m.contacts.size());
  Eigen::VectorXd excess(k), moves(k);
  for (int j = 0; j < k; ++j) {
    const Contact& cj = m.contacts[j];
    const std::complex<double> xj = cj.normal.cast<std::complex<double>>().dot(flow.harmonic_response());
    excess[j] = cj.Along(flow.static_response()) + std::abs(xj) - cj.gap;
    moves[j] = flow.rigid_modes() == 1 ? cj.Along(flow.rigid_basis().col(0)) : 0.0;
  }
  // A wall the free part does not move shows round-off of the eigenvectors
  // (~1e-16): below 1e-12 of the largest it is none.
  const double largest_move = moves.cwiseAbs().maxCoeff();
  for (int j = 0; j < k; ++j) {
    if (std::abs(moves[j]) <= 1e-12 * largest_move) moves[j] = 0.0;
  }
  // One rigid-body mode leaves the free part anywhere: x + Phi_0 c is a
  // steady state for every c, and the response is admissible when some c
  // keeps every wall open. c is taken where the largest excess
  // max_j (e_j + g_j c), g_j = n_j . Phi_0, is least: where a wall that c
  // closes meets one that it opens. When c moves walls one way only, the
  // free part is taken a largest gap clear of them. (Two or more rigid-body
  // modes: the free parts at rest at 0.)
  double c = 0.0;
  if (largest_move > 0.0) {
    if ((moves.array() > 0.0).any() && (moves.array() < 0.0).any()) {
      double best = INFINITY;
      for (int j = 0; j < k; ++j) {
        for (int l = 0; l < k; ++l) {
          if (!(moves[j] > 0.0 && moves[l] < 0.0)) continue;
          const double at = (excess[l] - excess[j]) / (moves[j] - moves[l]);
          const double worst = (excess + at * moves).maxCoeff();
          if (worst < best) {
            best = worst;
            c = at;
          }
        }
      }
    } else {
      // Each moving wall's e_j + g_j c <= -L (L the largest gap): c at the
      // bound of the wall that binds.
      double largest = 0.0;
      for (const Contact& cj : m.contacts) largest = std::max(largest, cj.gap);
      const bool opens_up = (moves.array() < 0.0).any();  // c increasing opens them
      c = opens_up ? -INFINITY : INFINITY;
      for (int j = 0; j < k; ++j) {
        if (moves[j] == 0.0) continue;
        const double bound = (-largest - excess[j]) / moves[j];
        c = opens_up ? std::max(c, bound) : std::min(c, bound);
      }
    }
  }
  const Eigen::VectorXd shift = flow.rigid_modes() == 1 ? Eigen::VectorXd(c * flow.rigid_basis().col(0))
                                                         : Eigen::VectorXd::Zero(m.dofs());
  o.times = {t_max};
  o.after = {flow.Particular(t_max)};
  o.after[0].head(m.dofs()) += shift;
  o.before = o.after;
  o.max_xc = contact.Along(flow.static_response() + shift) + std::abs(xc);
  o.max_interior_gap = (excess + c * moves).maxCoeff();
  o.min_impact_velocity = std::numeric_limits<double>::quiet_NaN();
  // Means over a period of x'Kx/2 and v'Mv/2 for x = x_s + Re[X e^{i w t}].
  const Eigen::VectorXd xr = flow.harmonic_response().real(), xi = flow.harmonic_response().imag();
  const Eigen::VectorXd& xs = flow.static_response();
  o.energy = 0.5 * xs.dot(m.stiffness * xs) + 0.25 * (xr.dot(m.stiffness * xr) + xi.dot(m.stiffness * xi)) +
             0.25 * w * w * (xr.dot(m.mass * xr) + xi.dot(m.mass * xi));
  o.dissipated = 0.5 * o.period * w * w * (xr.dot(m.DampingMatrix() * xr) + xi.dot(m.DampingMatrix() * xi));
  o.work = o.dissipated;  // the steady state's balance, exactly
  // (x - d <= 0 exactly when x <= d: the one-contact test as it was.)
  o.admissible = o.max_interior_gap <= 0.0;
  o.verdict = o.admissible        ? "admissible"
              : o.max_xc > d      ? "x_c exceeds d (max x_c = " + FormatValue(o.max_xc) + ")"
                                  : "another contact's wall is passed (by " + FormatValue(o.max_interior_gap) + ")";
  // Multipliers e^{lambda P} of the flight's modes (both of each pair).
  const Eigen::VectorXcd lambda = flow.Eigenvalues();
  std::vector<std::complex<double>> mult;
  for (int k = 0; k < lambda.size(); ++k) {
    mult.push_back(std::exp(lambda[k] * o.period));
    if (lambda[k].imag() > 0.0) mult.push_back(std::conj(mult.back()));
  }
  // A rigid-body mode drifts: the multiplier 1, twice (a Jordan block).
  for (int k = 0; k < 2 * flow.rigid_modes(); ++k) mult.push_back(1.0);
  o.multipliers = Eigen::Map<Eigen::VectorXcd>(mult.data(), static_cast<Eigen::Index>(mult.size()));
  o.max_multiplier = o.multipliers.cwiseAbs().maxCoeff();
  o.stable = o.max_multiplier < 1.0;
  return o;
}

}  // namespace nsmodal
