// CVODE event-driven integrator (SUNDIALS 6.4). Free flight:
// z' = (v, M^-1 (f0 + f cos(w t) - C v - K x))
// with two root functions, g0 = d - x_c (direction -1: x_c rising through d,
// an impact) and g1 = v_c (direction -1: a maximum of x_c). CVODE misses
// roots of even multiplicity and two crossings inside one step; a maximum of
// x_c at or above d reveals them, and the crossing is then located on CVODE's
// dense output within that step. Sticking: the RHS holds v_c' = 0 with the
// contact force lambda = a_c / (M^-1)_cc, and g0 = a_c (direction -1) releases.
// After every event CVodeReInit restarts the integration; a root function that
// is zero at the restart stays inactive until it moves away (CVODE's rule).
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "event_loop.h"
#include "integrators.h"
#include "nsmodal/roots.h"

namespace nsmodal::internal {
namespace {

struct UserData {
  const ContactModel* cm;
  bool sticking = false;
};

int Rhs(realtype t, N_Vector zv, N_Vector dzv, void* data) {
  const auto* ud = static_cast<const UserData*>(data);
  const ContactModel& cm = *ud->cm;
  const int n = cm.model.dofs();
  Eigen::Map<const Eigen::VectorXd> z(N_VGetArrayPointer(zv), 2 * n);
  Eigen::Map<Eigen::VectorXd> dz(N_VGetArrayPointer(dzv), 2 * n);
  dz.head(n) = z.tail(n);
  dz.tail(n).noalias() = -cm.minv_k * z.head(n);
  if (cm.model.HasDamping()) dz.tail(n).noalias() -= cm.minv_d * z.tail(n);
  if (cm.model.forcing.HasConstant()) dz.tail(n) += cm.minv_f0;
  if (cm.model.forcing.HasHarmonic()) dz.tail(n) += std::cos(cm.model.forcing.frequency * t) * cm.minv_f;
  if (ud->sticking) {
    const double lambda = dz[n + ud->cm->model.contact] / ud->cm->w_cc;
    dz.tail(n) -= lambda * ud->cm->minv_c;
  }
  return 0;
}

int Jac(realtype, N_Vector, N_Vector, SUNMatrix jm, void* data, N_Vector, N_Vector, N_Vector) {
  const auto* ud = static_cast<const UserData*>(data);
  const int n = ud->cm->model.dofs();
  // d(acceleration)/d(x, v) = [-M^-1 K, -M^-1 C], projected while sticking.
  Eigen::MatrixXd a(n, 2 * n);
  a << -ud->cm->minv_k, -ud->cm->minv_d;
  if (ud->sticking) {
    const Eigen::RowVectorXd row = a.row(ud->cm->model.contact) / ud->cm->w_cc;
    a -= ud->cm->minv_c * row;
  }
  SUNMatZero(jm);
  for (int i = 0; i < n; ++i) {
    SM_ELEMENT_D(jm, i, n + i) = 1.0;
    for (int j = 0; j < 2 * n; ++j) SM_ELEMENT_D(jm, n + i, j) = a(i, j);
  }
  return 0;
}

int Roots(realtype t, N_Vector zv, realtype* g, void* data) {
  const auto* ud = static_cast<const UserData*>(data);
  const Model& m = ud->cm->model;
  const int n = m.dofs();
  Eigen::Map<const Eigen::VectorXd> z(N_VGetArrayPointer(zv), 2 * n);
  if (ud->sticking) {
    g[0] = ud->cm->FreeContactAcceleration(t, z.head(n), z.tail(n));
    g[1] = 1.0;  // inactive
  } else {
    g[0] = m.gap - z[m.contact];
    g[1] = z[n + m.contact];
  }
  return 0;
}

// The post-impact state put back on the energy level e0 by scaling the
// velocities (the position, on the wall, stays): CVODE's energy error, a
// random walk over the flights, would otherwise turn into a phase drift that
// grows with time on a non-isochronous motion. No-op where the potential
// energy alone reaches e0.
void ProjectOnEnergy(const ContactModel& cm, double e0, Eigen::Ref<Eigen::VectorXd> z) {
  const int n = cm.model.dofs();
  const double kinetic = 0.5 * z.tail(n).dot(cm.model.mass * z.tail(n));
  const double target = e0 - 0.5 * z.head(n).dot(cm.model.stiffness * z.head(n));
  if (kinetic > 0.0 && target > 0.0) z.tail(n) *= std::sqrt(target / kinetic);
}

// The energy error below which no projection is made, in units of rtol E0:
// a projection moves the state by the energy error, and a state moved by more
// than CVODE's own accuracy can turn a graze (an orbit touching d, infinitely
// sensitive) into a spurious impact; the error of a few flights stays below
// this band (16 rtol E0 measured over the grazing orbit's first period),
// while a long run's drift is held at it.
constexpr double kProjectionBand = 100.0;

void Check(int flag, const char* call) {
  if (flag < 0) throw SolverError(std::string(call) + " failed with flag " + std::to_string(flag));
}

// Owns the CVODE memory block and its vectors, matrix and linear solver.
class Cvode {
 public:
  Cvode(const ContactModel& cm, const Eigen::VectorXd& z0, const SimulateOptions& opt) : n_(cm.model.dofs()) {
    ud_.cm = &cm;
    Check(SUNContext_Create(nullptr, &ctx_), "SUNContext_Create");
    y_ = N_VNew_Serial(2 * n_, ctx_);
    if (y_ == nullptr) throw SolverError("N_VNew_Serial failed");
    State() = z0;
    mem_ = CVodeCreate(opt.cvode_method == "adams" ? CV_ADAMS : CV_BDF, ctx_);
    if (mem_ == nullptr) throw SolverError("CVodeCreate failed");
    Check(CVodeInit(mem_, Rhs, 0.0, y_), "CVodeInit");
    Check(CVodeSStolerances(mem_, opt.rtol, opt.atol), "CVodeSStolerances");
    Check(CVodeSetUserData(mem_, &ud_), "CVodeSetUserData");
    a_ = SUNDenseMatrix(2 * n_, 2 * n_, ctx_);
    ls_ = SUNLinSol_Dense(y_, a_, ctx_);
    if (a_ == nullptr || ls_ == nullptr) throw SolverError("dense linear solver allocation failed");
    Check(CVodeSetLinearSolver(mem_, ls_, a_), "CVodeSetLinearSolver");
    Check(CVodeSetJacFn(mem_, Jac), "CVodeSetJacFn");
    Check(CVodeSetMaxNumSteps(mem_, -1), "CVodeSetMaxNumSteps");  // no limit per call; we count
    Check(CVodeRootInit(mem_, 2, Roots), "CVodeRootInit");
    int dirs[2] = {-1, -1};
    Check(CVodeSetRootDirection(mem_, dirs), "CVodeSetRootDirection");
    Check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn");
  }
  ~Cvode() {
    CVodeFree(&mem_);
    SUNLinSolFree(ls_);
    SUNMatDestroy(a_);
    N_VDestroy(y_);
    SUNContext_Free(&ctx_);
  }
  Cvode(const Cvode&) = delete;
  Cvode& operator=(const Cvode&) = delete;

  Eigen::Map<Eigen::VectorXd> State() { return {N_VGetArrayPointer(y_), 2 * n_}; }
  void Restart(double t, bool sticking) {
    ud_.sticking = sticking;
    Check(CVodeReInit(mem_, t, y_), "CVodeReInit");
  }
  // One internal step towards tout, never past it (a stop time: roots and
  // samples stay inside the last step, where the dense output is valid);
  // returns CV_SUCCESS, CV_TSTOP_RETURN, CV_ROOT_RETURN or throws. One step
  // at a time, so that every step is checked for a crossing CVODE cannot
  // see (a penetration from a restart at the wall, where g0 is inactive):
  // in CV_NORMAL mode only the last of many steps could be searched.
  int Step(double tout, double* t) {
    Check(CVodeSetStopTime(mem_, tout), "CVodeSetStopTime");
    const int flag = CVode(mem_, tout, y_, t, CV_ONE_STEP);
    Check(flag, "CVode");
    return flag;
  }
  int RootInfo(int which) {
    int info[2];
    Check(CVodeGetRootInfo(mem_, info), "CVodeGetRootInfo");
    return info[which];
  }
  long Steps() {
    long s = 0;
    Check(CVodeGetNumSteps(mem_, &s), "CVodeGetNumSteps");
    return s;
  }
  // Dense output on the last step: the state at t in [tcur - hlast, tcur].
  Eigen::VectorXd Interpolate(double t) {
    N_Vector k = N_VClone(y_);
    Check(CVodeGetDky(mem_, t, 0, k), "CVodeGetDky");
    Eigen::VectorXd out = Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(k), 2 * n_);
    N_VDestroy(k);
    return out;
  }
  double LastStepStart() {
    double tcur = 0.0, h = 0.0;
    Check(CVodeGetCurrentTime(mem_, &tcur), "CVodeGetCurrentTime");
    Check(CVodeGetLastStep(mem_, &h), "CVodeGetLastStep");
    return tcur - h;
  }

 private:
  int n_;
  UserData ud_;
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr;
  SUNMatrix a_ = nullptr;
  SUNLinearSolver ls_ = nullptr;
  void* mem_ = nullptr;
};

}  // namespace

// CVODE's advance (event_loop.h's Stepper): one internal step towards the
// next sample time or the end, checked for a crossing CVODE did not report.
class CvodeStepper {
 public:
  CvodeStepper(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0, const SimulateOptions& opt)
      : cm_(cm),
        n_(cm.model.dofs()),
        c_(cm.model.contact),
        d_(cm.model.gap),
        t_end_(opt.t_end),
        zeno_flight_(opt.zeno_flight * 2.0 * M_PI / cm.basis.omega.maxCoeff()),
        // The contact band: CVODE's error control keeps x_c within ~atol + rtol d of
        // its true value, so contact decisions use that scale.
        xtol_(10.0 * (opt.atol + opt.rtol * d_)),
        vtol_floor_(10.0 * (opt.atol + opt.rtol * (std::sqrt(cm.EnergyScale(x0, v0) * 2.0 * cm.w_cc) + 1e-300))),
        // e = 1 without damping or forcing: the energy of the start is an
        // invariant; each restart is put back on it (simulate.h, cvode_energy_projection).
        e0_(cm.EnergyOf(x0, v0)),
        project_(opt.cvode_energy_projection && cm.model.restitution == 1.0 && cm.model.Conservative()),
        band_(kProjectionBand * opt.rtol * e0_),
        solver_(cm, Start(x0, v0), opt),
        z_(solver_.State()) {}

  bool Finished() const { return t_ >= t_end_; }
  double Time() const { return t_; }
  long Steps() { return base_steps_ + solver_.Steps(); }

  std::optional<int> InitialContact() {
    if (z_[c_] >= d_ - xtol_ && (z_[n_ + c_] > vtol_floor_ || (std::abs(z_[n_ + c_]) <= vtol_floor_ &&
                                                               Acceleration() > 0.0))) {
      return 0;
    }
    return std::nullopt;
  }

  Advance Step(Sampler& sampler) {
    Advance a;
    const double t0 = t_;
    // Samples within round-off of t take the current state; then return at
    // the next sample time (CVODE interpolates there) or at a root.
    sampler.Emit(t_ + 1e-12 * std::max(1.0, t_), [&](double) { return Eigen::VectorXd(z_); });
    double tout = t_end_;
    if (sampler.active()) tout = std::min(t_end_, sampler.NextTime());
    const int flag = solver_.Step(tout, &t_);
    if (held_) a.held = t_ - t0;
    if (!held_ && z_[c_] > d_ + xtol_) {
      // Beyond the obstacle with no root reported (two crossings in one
      // step): locate the rising crossing on the dense output of the step.
      // A step that starts at or beyond the wall is a restart there: after
      // an impact, which CVODE's root location leaves up to
      // (|t| + |h|) 100 uround |v_c| beyond d (1e-11 at t = 4e4, above the
      // band at rtol 1e-13), the mass moves away; after an impact with
      // e = 0 where nothing pushed yet (g0 = 0, inactive by CVODE's rule)
      // it is pushed in later. It penetrates only if x_c rises a band above
      // where the step started, and the contact is half a band above that.
      const double lo = solver_.LastStepStart();
      const double start = solver_.Interpolate(lo)[c_] - d_;
      if (start < 0.0 || z_[c_] - d_ > start + xtol_) {
        const double level = start < 0.0 ? 0.0 : start + 0.5 * xtol_;
        auto gap = [&](double ts) { return solver_.Interpolate(ts)[c_] - d_ - level; };
        t_ = PolishRoot(gap, lo, t_);
        z_ = solver_.Interpolate(t_);
        sampler.Emit(t_, [&](double ts) { return solver_.Interpolate(ts); });
        a.event = Advance::Event::kWitness;
        return a;
      }
    }
    sampler.Emit(t_, [&](double ts) {
      return std::abs(ts - t_) <= 1e-12 * std::max(1.0, t_) ? Eigen::VectorXd(z_) : solver_.Interpolate(ts);
    });
    if (flag != CV_ROOT_RETURN) return a;
    // Held: the contact force's root releases. Open: the gap's root, or a
    // maximum of x_c in the contact band (a graze, or held).
    if (held_ || solver_.RootInfo(0) != 0 || (solver_.RootInfo(1) != 0 && z_[c_] >= d_ - xtol_)) {
      a.event = Advance::Event::kWitness;
    }
    return a;
  }

  // contact.h's logic with CVODE's resolution: x_c is known to ~xtol, so a
  // crossing slower than sqrt(2 |a_c| xtol) cannot be told from a graze, and a
  // rebound lower than xtol would never move the root function away from zero
  // after the restart.
  ContactKinematics Contact(int) const {
    const double ac = Acceleration();
    return {z_[n_ + c_], ac, {std::max(vtol_floor_, std::sqrt(2.0 * std::abs(ac) * xtol_)), xtol_, zeno_flight_}};
  }
  Eigen::VectorXd Physical() const { return z_; }
  void Impact(int, double e) {
    cm_.ApplyImpact(e, z_.tail(n_));
    if (project_ && std::abs(cm_.EnergyOf(z_.head(n_), z_.tail(n_)) - e0_) > band_) ProjectOnEnergy(cm_, e0_, z_);
  }
  void Hold(int) {
    z_[n_ + c_] = 0.0;  // plastic: the held contact has no velocity
    cm_.ApplyImpact(0.0, z_.tail(n_));
    held_ = true;
  }
  void Release(int) { held_ = false; }
  void Restart() {
    base_steps_ += solver_.Steps();  // CVodeReInit resets the counters
    solver_.Restart(t_, held_);
  }
  void Finish(SimulationSummary& sum) {
    sum.steps = Steps();
    sum.final_time = t_;
    sum.final_state = z_;
  }

 private:
  static Eigen::VectorXd Start(const Eigen::VectorXd& x0, const Eigen::VectorXd& v0) {
    Eigen::VectorXd z0(x0.size() + v0.size());
    z0 << x0, v0;
    return z0;
  }
  double Acceleration() const { return cm_.FreeContactAcceleration(t_, z_.head(n_), z_.tail(n_)); }

  const ContactModel& cm_;
  const int n_, c_;
  const double d_, t_end_, zeno_flight_, xtol_, vtol_floor_, e0_;
  const bool project_;
  const double band_;  // the energy error below which no projection is made
  Cvode solver_;
  Eigen::Map<Eigen::VectorXd> z_;
  bool held_ = false;
  double t_ = 0.0;
  long base_steps_ = 0;
};

template NSMODAL_RUN_INTEGRATOR(CvodeStepper);

}  // namespace nsmodal::internal
