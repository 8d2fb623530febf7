#include "nsmodal/modal_basis.h"

#include <cmath>

#include "nsmodal/error.h"

namespace nsmodal {

Eigen::VectorXd ModalBasis::Periods() const {
  return (2.0 * M_PI) * omega.cwiseInverse();
}

ModalBasis MakeModalBasis(const Model& model) {
  const int rigid = Validate(model);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(model.stiffness, model.mass);
  ModalBasis b;
  b.n = model.dofs();
  b.rigid = rigid;
  // The generalized eigenvalues ascend: the rigid-body modes come first, at
  // round-off of either sign; their frequency is zero exactly.
  b.omega = ges.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  b.omega.head(b.rigid).setZero();
  const Eigen::VectorXd elastic = b.omega.tail(b.n - b.rigid);
  if (elastic.size() == 0 || !elastic.allFinite() || !(elastic.minCoeff() > 0.0) ||
      elastic.maxCoeff() > kMaxFrequencyRatio * elastic.minCoeff()) {
    throw InputError("system", "linear frequencies from " + FormatValue(elastic.minCoeff()) + " to " +
                                   FormatValue(elastic.maxCoeff()) + " rad/s: nsmodal honours a ratio up to " +
                                   FormatValue(kMaxFrequencyRatio));
  }
  b.u_scale = b.omega;
  b.u_scale.head(b.rigid).setOnes();
  b.phi = ges.eigenvectors();  // normalised so that Phi' M Phi = I
  b.phi_inv = b.phi.transpose() * model.mass;
  for (const Contact& c : model.contacts) {
    ModalContact mc;
    mc.r = c.RowOf(b.phi).transpose();
    mc.r_over_omega = mc.r.cwiseQuotient(b.u_scale);
    mc.r_norm2 = mc.r.squaredNorm();
    mc.gap = c.gap;
    for (int k = 0; k < static_cast<int>(b.contacts.size()) && mc.parallel < 0; ++k) {
      const ModalContact& o = b.contacts[k];
      if (std::abs(o.r.dot(mc.r)) >= (1.0 - 1e-14) * std::sqrt(o.r_norm2 * mc.r_norm2)) mc.parallel = k;
    }
    b.contacts.push_back(std::move(mc));
  }
  b.r = b.contacts.front().r;
  b.r_over_omega = b.contacts.front().r_over_omega;
  b.r_norm2 = b.contacts.front().r_norm2;
  b.gap = b.contacts.front().gap;
  return b;
}

namespace {
const Model& ElasticModel(const Model& model) {
  for (int j = 0; j < model.NumContacts(); ++j) {
    const Contact& c = model.contacts[j];
    if (c.restitution != AnalysisBasis::kRestitution) {
      throw InputError(ContactField(c, j, "restitution"),
                       "periodic orbits with impacts exist only for e = 1 (energy is lost at every impact "
                       "when e < 1, paper section 1); got " +
                           FormatValue(c.restitution));
    }
  }
  // The nonsmooth modes are those of the conservative system (paper eq. 1).
  if (model.HasDamping()) {
    throw InputError("system", "has damping: nonsmooth modes are the periodic orbits of the undamped system; "
                               "remove the damping key to compute them (forced, damped responses are a "
                               "separate computation)");
  }
  if (model.forcing.HasConstant() || model.forcing.HasHarmonic()) {
    throw InputError("forcing", "is given: nonsmooth modes are the free periodic orbits of the unforced system; "
                                "remove the [forcing] table to compute them");
  }
  return model;
}
}  // namespace

AnalysisBasis::AnalysisBasis(const Model& model) : ModalBasis(MakeModalBasis(ElasticModel(model))) {
  // One contact: each impact pushes the drift's momentum away from the
  // obstacle and no flight brings it back. Two or more (a cavity, a free body
  // between walls) can send it back: the (a, b) sequences (two_impact.h).
  if (rigid > 0 && contacts.size() < 2) RequireElastic("nonsmooth modes with one contact");
}

void AnalysisBasis::RequireElastic(const std::string& what) const {
  if (rigid == 0) return;
  throw InputError("system.stiffness_matrix",
                   "has " + std::to_string(rigid) + " rigid-body mode(s) (zero eigenvalues of K: a free-free " +
                       "structure, or a mass with no spring to ground): " + what + " need(s) a positive definite " +
                       "K (one contact: no periodic orbit has impacts, each impact pushes the drift's momentum " +
                       "away from the obstacle and no flight brings it back; several contacts: only the " +
                       "two-impact sequences of two different contacts, orbits --sequence a,b, are computed); " +
                       "simulate it, or ground it with a spring");
}

void AnalysisBasis::CheckPeriod(double period, const std::string& field) const {
  const double shortest = Periods().minCoeff();
  if (!std::isfinite(period) || !(period >= kMinPeriodRatio * shortest) || !(period <= kMaxPeriodRatio * shortest)) {
    throw InputError(field, "T = " + FormatValue(period) + " lies outside what the analysis honours: " +
                                FormatValue(kMinPeriodRatio) + " to " + FormatValue(kMaxPeriodRatio) +
                                " times the shortest linear period " + FormatValue(shortest) + ", i.e. [" +
                                FormatValue(kMinPeriodRatio * shortest) + ", " +
                                FormatValue(kMaxPeriodRatio * shortest) + "]");
  }
}

Eigen::VectorXd ToModal(const ModalBasis& b, const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
  Eigen::VectorXd y(2 * b.n);
  y.head(b.n) = b.u_scale.cwiseProduct(b.phi_inv * x);
  y.tail(b.n) = b.phi_inv * v;
  return y;
}

Eigen::VectorXd PositionOf(const ModalBasis& b, const Eigen::VectorXd& y) {
  return b.phi * y.head(b.n).cwiseQuotient(b.u_scale);
}

Eigen::VectorXd VelocityOf(const ModalBasis& b, const Eigen::VectorXd& y) { return b.phi * y.tail(b.n); }

Eigen::VectorXd PhysicalOf(const ModalBasis& b, const Eigen::VectorXd& y) {
  Eigen::VectorXd z(2 * b.n);
  z << PositionOf(b, y), VelocityOf(b, y);
  return z;
}

}  // namespace nsmodal
