// CVODE event-driven integrator (SUNDIALS 6.4). Free flight:
// z' = (v, M^-1 (f0 + f cos(w t) - C v - K x))
// with two root functions per contact j, g_2j = d_j - x_c (x_c = n_j . x;
// direction -1: x_c rising through d_j, an impact) and g_2j+1 = v_c (n_j . v;
// direction -1: a maximum of x_c). CVODE misses roots of even multiplicity
// and two crossings inside one step; a maximum of x_c at or above d_j reveals
// them, and the crossing is then located on CVODE's dense output within that
// step. Sticking on contact j: the RHS holds v_c' = 0 with the contact force
// lambda = a_c / (n_j' M^-1 n_j), g_2j = a_c (direction -1) releases, and the
// other contacts keep their gap roots.
// After every event CVodeReInit restarts the integration; a root function that
// is zero at the restart stays inactive until it moves away (CVODE's rule).
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "event_loop.h"
#include "integrators.h"
#include "nsmodal/roots.h"

namespace nsmodal::internal {
namespace {

struct UserData {
  const ContactModel* cm;
  std::vector<int> held;    // the held contacts
  Eigen::MatrixXd g_inv;    // several held: (H M^-1 H')^-1 over them
  // The free contacts whose normal lies in the held normals' span (the other
  // wall of a held pair): their normal velocity is 0 while held, identically,
  // so their velocity root is inactive (CVODE refuses a root function that
  // stays at zero).
  std::vector<char> locked;
  void SetHeld(const std::vector<int>& set) {
    held = set;
    if (held.size() > 1) g_inv = cm->DelassusBlock(held).inverse();
  }
  // `locked` for the held set (the root functions' concern: the RHS and the
  // held kinematics need only SetHeld).
  void LockRoots() {
    locked.assign(cm->NumContacts(), 0);
    if (held.empty()) return;
    const int n = cm->model.dofs();
    Eigen::MatrixXd normals(n, static_cast<Eigen::Index>(held.size()));
    for (std::size_t i = 0; i < held.size(); ++i) normals.col(static_cast<Eigen::Index>(i)) = cm->contact(held[i]).normal;
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(normals);
    for (int k = 0; k < cm->NumContacts(); ++k) {
      const Eigen::VectorXd& nk = cm->contact(k).normal;
      const Eigen::VectorXd off = nk - normals * qr.solve(nk);
      locked[k] = off.norm() <= 1e-12 * nk.norm() ? 1 : 0;
    }
  }
  // The held contacts' forces from the free acceleration a: lambda = W H a
  // (one contact: a_j / w_j; several: G^-1 H a).
  Eigen::VectorXd Forces(const Eigen::Ref<const Eigen::VectorXd>& a) const {
    const int k = static_cast<int>(held.size());
    Eigen::VectorXd u(k);
    for (int i = 0; i < k; ++i) u[i] = cm->contact(held[i]).Along(a);
    if (k == 1) return Eigen::VectorXd::Constant(1, u[0] / cm->terms[held[0]].w);
    return g_inv * u;
  }
  // a <- a minus the held contacts' impulses per unit time: the constrained acceleration.
  void Project(Eigen::Ref<Eigen::VectorXd> a) const {
    if (held.empty()) return;
    const Eigen::VectorXd lambda = Forces(a);
    for (std::size_t i = 0; i < held.size(); ++i) a -= lambda[i] * cm->terms[held[i]].minv_n;
  }
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
  ud->Project(dz.tail(n));
  return 0;
}

int Jac(realtype, N_Vector, N_Vector, SUNMatrix jm, void* data, N_Vector, N_Vector, N_Vector) {
  const auto* ud = static_cast<const UserData*>(data);
  const int n = ud->cm->model.dofs();
  // d(acceleration)/d(x, v) = [-M^-1 K, -M^-1 C], projected while sticking.
  Eigen::MatrixXd a(n, 2 * n);
  a << -ud->cm->minv_k, -ud->cm->minv_d;
  const int k = static_cast<int>(ud->held.size());
  if (k == 1) {
    const ContactTerms& c = ud->cm->terms[ud->held[0]];
    const Eigen::RowVectorXd row = ud->cm->contact(ud->held[0]).RowOf(a) / c.w;
    a -= c.minv_n * row;
  } else if (k > 1) {
    Eigen::MatrixXd rows(k, 2 * n);
    for (int i = 0; i < k; ++i) rows.row(i) = ud->cm->contact(ud->held[i]).RowOf(a);
    const Eigen::MatrixXd lambda = ud->g_inv * rows;
    for (int i = 0; i < k; ++i) a -= ud->cm->terms[ud->held[i]].minv_n * lambda.row(i);
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
  const ContactModel& cm = *ud->cm;
  const int n = cm.model.dofs();
  Eigen::Map<const Eigen::VectorXd> z(N_VGetArrayPointer(zv), 2 * n);
  for (int j = 0; j < cm.NumContacts(); ++j) {
    g[2 * j] = cm.Gap(j, z.head(n));
    g[2 * j + 1] = ud->held.empty() || !ud->locked[j] ? cm.NormalVelocity(j, z.tail(n)) : 1.0;
  }
  // A held contact's root is its force (one: its free normal acceleration, a
  // positive multiple of it); its velocity root is inactive.
  if (ud->held.size() == 1) {
    const int j = ud->held[0];
    g[2 * j] = cm.FreeContactAcceleration(j, t, z.head(n), z.tail(n));
    g[2 * j + 1] = 1.0;
  } else if (!ud->held.empty()) {
    const Eigen::VectorXd lambda = ud->Forces(cm.FreeAcceleration(t, z.head(n), z.tail(n)));
    for (std::size_t i = 0; i < ud->held.size(); ++i) {
      g[2 * ud->held[i]] = lambda[i];
      g[2 * ud->held[i] + 1] = 1.0;
    }
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

// While held under a harmonic force, CVODE's steps are at most this fraction
// of its period (Cvode::Restart): a force negative on a window shorter than
// two of them (a twentieth of the period) can still be stepped over.
constexpr double kHeldStepsPerForcingPeriod = 40.0;

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
    Check(CVodeInit(mem_, Rhs, opt.t_start, y_), "CVodeInit");
    Check(CVodeSStolerances(mem_, opt.rtol, opt.atol), "CVodeSStolerances");
    Check(CVodeSetUserData(mem_, &ud_), "CVodeSetUserData");
    a_ = SUNDenseMatrix(2 * n_, 2 * n_, ctx_);
    ls_ = SUNLinSol_Dense(y_, a_, ctx_);
    if (a_ == nullptr || ls_ == nullptr) throw SolverError("dense linear solver allocation failed");
    Check(CVodeSetLinearSolver(mem_, ls_, a_), "CVodeSetLinearSolver");
    Check(CVodeSetJacFn(mem_, Jac), "CVodeSetJacFn");
    Check(CVodeSetMaxNumSteps(mem_, -1), "CVodeSetMaxNumSteps");  // no limit per call; we count
    roots_ = 2 * cm.NumContacts();
    Check(CVodeRootInit(mem_, roots_, Roots), "CVodeRootInit");
    std::vector<int> dirs(roots_, -1);
    Check(CVodeSetRootDirection(mem_, dirs.data()), "CVodeSetRootDirection");
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
  void Restart(double t, const std::vector<int>& held) {
    ud_.SetHeld(held);
    ud_.LockRoots();
    Check(CVodeReInit(mem_, t, y_), "CVodeReInit");
    // Held under a harmonic force, the release root (a held force) moves
    // with cos(w t) where the state may not move at all (every dof held: the
    // held flow is z' = 0, and CVODE's steps grow without bound, over a
    // whole window where the force is negative). CVODE sees a root only as a
    // sign change between its steps: at most 1/kHeldStepsPerForcingPeriod of
    // the forcing period apart while held (0: no bound, in free flight).
    const double w = ud_.cm->model.forcing.HasHarmonic() ? ud_.cm->model.forcing.frequency : 0.0;
    Check(CVodeSetMaxStep(mem_, held.empty() || !(w > 0.0) ? 0.0 : 2.0 * M_PI / w / kHeldStepsPerForcingPeriod),
          "CVodeSetMaxStep");
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
  // CVodeGetRootInfo after CV_ROOT_RETURN: nonzero where a root was found.
  std::vector<int> RootInfo() {
    std::vector<int> info(roots_, 0);
    Check(CVodeGetRootInfo(mem_, info.data()), "CVodeGetRootInfo");
    return info;
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
  int roots_ = 0;
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
        k_(cm.NumContacts()),
        t_end_(opt.t_end),
        zeno_flight_(ZenoFlightTime(cm, opt)),
        // e = 1 without damping or forcing: the energy of the start is an
        // invariant; each restart is put back on it (simulate.h, cvode_energy_projection).
        e0_(cm.EnergyOf(x0, v0)),
        project_(opt.cvode_energy_projection && cm.model.AllRestitution(1.0) && cm.model.Conservative()),
        band_(kProjectionBand * opt.rtol * e0_),
        solver_(cm, Start(x0, v0), opt),
        z_(solver_.State()) {
    const double energy = cm.EnergyScale(x0, v0);
    for (int j = 0; j < k_; ++j) {
      // Contact j's band: CVODE's error control keeps x_c = n_j . x within
      // ~atol + rtol d_j of its true value, so contact decisions use that scale.
      xtol_.push_back(10.0 * (opt.atol + opt.rtol * cm.contact(j).gap));
      vtol_floor_.push_back(10.0 * (opt.atol + opt.rtol * (std::sqrt(energy * 2.0 * cm.terms[j].w) + 1e-300)));
    }
    t_ = opt.t_start;
  }

  bool Finished() const { return t_ >= t_end_; }
  double Time() const { return t_; }
  long Steps() { return base_steps_ + solver_.Steps(); }

  std::optional<int> InitialContact() {
    for (int j = 0; j < k_; ++j) {
      const double vc = Velocity(j);
      if (Position(j) >= Gap(j) - xtol_[j] &&
          (vc > vtol_floor_[j] || (std::abs(vc) <= vtol_floor_[j] && Acceleration(j) > 0.0))) {
        return j;
      }
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
    if (!held_.empty()) a.held = t_ - t0;
    // Beyond a wall with no root reported (two crossings in one step): locate
    // the rising crossing on the dense output of the step. A step that starts
    // at or beyond the wall is a restart there: after an impact, which
    // CVODE's root location leaves up to (|t| + |h|) 100 uround |v_c| beyond
    // d (1e-11 at t = 4e4, above the band at rtol 1e-13), the mass moves away;
    // after an impact with e = 0 where nothing pushed yet (g = 0, inactive by
    // CVODE's rule) it is pushed in later. It penetrates only if x_c rises a
    // band above where the step started, and the contact is half a band above
    // that. With several walls crossed, the earliest crossing is the event.
    int first = -1;
    double lo = 0.0;
    for (int j = 0; j < k_; ++j) {
      if (IsHeld(j) || !(Position(j) > Gap(j) + xtol_[j])) continue;
      if (first < 0) lo = solver_.LastStepStart();
      const double start = cm_.contact(j).Along(solver_.Interpolate(lo).head(n_)) - Gap(j);
      if (start < 0.0 || Position(j) - Gap(j) > start + xtol_[j]) {
        const double level = start < 0.0 ? 0.0 : start + 0.5 * xtol_[j];
        auto gap = [&](double ts) {
          return cm_.contact(j).Along(solver_.Interpolate(ts).head(n_)) - Gap(j) - level;
        };
        const double tj = PolishRoot(gap, lo, t_);
        if (first < 0 || tj < crossing_) {
          first = j;
          crossing_ = tj;
        }
      }
    }
    if (first >= 0) {
      t_ = crossing_;
      z_ = solver_.Interpolate(t_);
      sampler.Emit(t_, [&](double ts) { return solver_.Interpolate(ts); });
      a.event = Advance::Event::kWitness;
      a.contact = first;
      return a;
    }
    sampler.Emit(t_, [&](double ts) {
      return std::abs(ts - t_) <= 1e-12 * std::max(1.0, t_) ? Eigen::VectorXd(z_) : solver_.Interpolate(ts);
    });
    if (flag != CV_ROOT_RETURN) return a;
    // Held: the contact force's root releases. Open: a gap's root, or a
    // maximum of x_c in the contact band (a graze, or held).
    const std::vector<int> info = solver_.RootInfo();
    for (int j = 0; j < k_; ++j) {
      if (info[2 * j] != 0 || (!IsHeld(j) && info[2 * j + 1] != 0 && Position(j) >= Gap(j) - xtol_[j])) {
        a.event = Advance::Event::kWitness;
        a.contact = j;
        return a;
      }
    }
    return a;
  }

  // contact.h's logic with CVODE's resolution: x_c is known to ~xtol, so a
  // crossing slower than sqrt(2 |a_c| xtol) cannot be told from a graze, and a
  // rebound lower than xtol would never move the root function away from zero
  // after the restart.
  // While others are held: contact j's acceleration along the held motion.
  ContactKinematics Contact(int j) const {
    const double ac = held_.empty() ? Acceleration(j) : HeldAcceleration(j);
    return {Velocity(j), ac,
            {std::max(vtol_floor_[j], std::sqrt(2.0 * std::abs(ac) * xtol_[j])), xtol_[j], zeno_flight_}};
  }
  ContactKinematics Resting(int j) const { return Contact(j); }
  Eigen::VectorXd Physical() const { return z_; }
  // Newton's law at j, and at every other contact in its band and not moving
  // away at that instant (struck at once: contact.h's law).
  const std::vector<int>& Impact(int j, double e) {
    set_.assign(1, j);
    struck_.assign(1, j);
    for (int k = 0; k < k_; ++k) {
      if (k != j && Position(k) >= Gap(k) - xtol_[k] && Velocity(k) >= -vtol_floor_[k]) set_.push_back(k);
    }
    if (set_.size() == 1) {
      cm_.ApplyImpact(j, e, z_.tail(n_));
    } else if (!cm_.ApplyImpacts(set_, z_.tail(n_), false, &struck_)) {
      throw SolverError("the LCP of the contacts struck at once at t = " + std::to_string(t_) + " has no solution");
    }
    if (struck_.empty()) struck_.assign(1, j);  // round-off left no impulse: the contact found is the event
    if (project_ && std::abs(cm_.EnergyOf(z_.head(n_), z_.tail(n_)) - e0_) > band_) ProjectOnEnergy(cm_, e0_, z_);
    return struck_;
  }
  // Hold j: alone (plastic: n_j . v -> 0), or with the contacts already held
  // (the impulses that bring all their normal velocities to 0: contact.h
  // HoldVelocity).
  void Hold(int j) {
    if (held_.empty()) {
      const nsmodal::Contact& c = cm_.contact(j);
      if (c.form == nsmodal::Contact::Form::kDof) z_[n_ + c.dof] = 0.0;  // plastic: the held contact has no velocity
      cm_.ApplyImpact(j, 0.0, z_.tail(n_));
      held_ = {j};
      return;
    }
    held_.push_back(j);
    std::sort(held_.begin(), held_.end());
    if (!cm_.HoldVelocity(held_, z_.tail(n_))) {
      throw SolverError("the contacts held at once at t = " + std::to_string(t_) + " have dependent normals");
    }
  }
  void Release(int j) { held_.erase(std::remove(held_.begin(), held_.end(), j), held_.end()); }
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
  double Position(int j) const { return cm_.contact(j).Along(z_.head(n_)); }
  double Velocity(int j) const { return cm_.NormalVelocity(j, z_.tail(n_)); }
  double Gap(int j) const { return cm_.contact(j).gap; }
  double Acceleration(int j) const { return cm_.FreeContactAcceleration(j, t_, z_.head(n_), z_.tail(n_)); }
  bool IsHeld(int j) const { return std::find(held_.begin(), held_.end(), j) != held_.end(); }
  // n_j . x'' with the held contacts' forces (the RHS's constrained acceleration).
  double HeldAcceleration(int j) const {
    UserData ud;
    ud.cm = &cm_;
    ud.SetHeld(held_);
    Eigen::VectorXd a = cm_.FreeAcceleration(t_, z_.head(n_), z_.tail(n_));
    ud.Project(a);
    return cm_.contact(j).Along(a);
  }

  const ContactModel& cm_;
  const int n_, k_;
  const double t_end_, zeno_flight_, e0_;
  const bool project_;
  const double band_;  // the energy error below which no projection is made
  std::vector<double> xtol_, vtol_floor_;
  Cvode solver_;
  Eigen::Map<Eigen::VectorXd> z_;
  std::vector<int> held_;  // the held contacts, ascending
  std::vector<int> set_, struck_;  // at an impact: the contacts in their bands, those given an impulse
  double t_ = 0.0, crossing_ = 0.0;
  long base_steps_ = 0;
};

template NSMODAL_RUN_INTEGRATOR(CvodeStepper);

}  // namespace nsmodal::internal
