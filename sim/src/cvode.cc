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

#include "integrators.h"
#include "nsmodal/roots.h"
#include "nsmodal/stop.h"

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
  if (flag < 0) throw std::runtime_error(std::string(call) + " failed with flag " + std::to_string(flag));
}

// Owns the CVODE memory block and its vectors, matrix and linear solver.
class Cvode {
 public:
  Cvode(const ContactModel& cm, const Eigen::VectorXd& z0, const SimulateOptions& opt) : n_(cm.model.dofs()) {
    ud_.cm = &cm;
    Check(SUNContext_Create(nullptr, &ctx_), "SUNContext_Create");
    y_ = N_VNew_Serial(2 * n_, ctx_);
    if (y_ == nullptr) throw std::runtime_error("N_VNew_Serial failed");
    State() = z0;
    mem_ = CVodeCreate(opt.cvode_method == "adams" ? CV_ADAMS : CV_BDF, ctx_);
    if (mem_ == nullptr) throw std::runtime_error("CVodeCreate failed");
    Check(CVodeInit(mem_, Rhs, 0.0, y_), "CVodeInit");
    Check(CVodeSStolerances(mem_, opt.rtol, opt.atol), "CVodeSStolerances");
    Check(CVodeSetUserData(mem_, &ud_), "CVodeSetUserData");
    a_ = SUNDenseMatrix(2 * n_, 2 * n_, ctx_);
    ls_ = SUNLinSol_Dense(y_, a_, ctx_);
    if (a_ == nullptr || ls_ == nullptr) throw std::runtime_error("dense linear solver allocation failed");
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

SimulationSummary SimulateCvode(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
                                const SimulateOptions& opt, const SimulationObserver& observer) {
  const Model& m = cm.model;
  const int n = m.dofs(), c = m.contact;
  const double e = m.restitution, d = m.gap;
  const double zeno_flight = opt.zeno_flight * 2.0 * M_PI / cm.basis.omega.maxCoeff();
  Eigen::VectorXd z0(2 * n);
  z0 << x0, v0;
  Cvode solver(cm, z0, opt);
  SimulationSummary sum;
  Sampler sampler(opt, observer);
  sampler.Emit(0.0, [&](double) { return z0; });
  // The contact band: CVODE's error control keeps x_c within ~atol + rtol d of
  // its true value, so contact decisions use that scale.
  const double xtol = 10.0 * (opt.atol + opt.rtol * d);
  const double vscale = std::sqrt(cm.EnergyScale(x0, v0) * 2.0 * cm.w_cc) + 1e-300;
  const double vtol_floor = 10.0 * (opt.atol + opt.rtol * vscale);
  bool sticking = false;
  // e = 1 without damping or forcing: the energy of the start is an invariant; each restart is put back
  // on it (simulate.h, cvode_energy_projection).
  const double e0 = cm.EnergyOf(x0, v0);
  const bool project = opt.cvode_energy_projection && e == 1.0 && m.Conservative();
  double t = 0.0, stick_start = 0.0;
  long base_steps = 0, next_progress = 0;
  auto z = solver.State();
  auto restart = [&] {
    base_steps += solver.Steps();  // CVodeReInit resets the counters
    solver.Restart(t, sticking);
  };

  auto enter_sticking = [&] {
    z[n + c] = 0.0;  // plastic: the held contact has no velocity
    cm.ApplyImpact(0.0, z.tail(n));
    sticking = true;
    stick_start = t;
    ++sum.sticking_phases;
  };
  // contact.h's logic with CVODE's resolution: x_c is known to ~xtol, so a
  // crossing slower than sqrt(2 |a_c| xtol) cannot be told from a graze, and a
  // rebound lower than xtol would never move the root function away from zero
  // after the restart.
  auto handle_contact = [&] {
    const double ac = cm.FreeContactAcceleration(t, z.head(n), z.tail(n));
    const double vtol = std::max(vtol_floor, std::sqrt(2.0 * std::abs(ac) * xtol));
    const ContactDecision dec = DecideContact(z[n + c], ac, e, {vtol, xtol, zeno_flight});
    if (dec.outcome == ContactOutcome::kGraze) {
      ++sum.grazes;
    } else if (dec.outcome != ContactOutcome::kHold) {
      ContactEvent ev{t, z, {}};
      cm.ApplyImpact(e, z.tail(n));
      if (project && std::abs(cm.EnergyOf(z.head(n), z.tail(n)) - e0) > kProjectionBand * opt.rtol * e0) {
        ProjectOnEnergy(cm, e0, z);
      }
      ev.after = z;
      ++sum.impacts;
      if (observer.on_impact) observer.on_impact(ev);
    }
    if (dec.outcome != ContactOutcome::kGraze && dec.outcome != ContactOutcome::kImpact) enter_sticking();
    if (dec.outcome == ContactOutcome::kImpactZeno) {
      ++sum.zeno_events;
      if (sum.first_zeno_time < 0.0) sum.first_zeno_time = t + dec.accumulation;
      stick_start = t + dec.accumulation;  // held from the accumulation time on
    }
    restart();
  };

  try {
    if (z[c] >= d - xtol && (z[n + c] > vtol_floor || (std::abs(z[n + c]) <= vtol_floor &&
                                                       cm.FreeContactAcceleration(t, z.head(n), z.tail(n)) > 0.0))) {
      handle_contact();
    }
    while (t < opt.t_end) {
      ThrowIfStopRequested();  // a signal (stop.h): the run unwinds
      if (observer.stop_requested && observer.stop_requested()) {
        sum.status = SimulationStatus::kStopped;
        break;
      }
      if (base_steps + solver.Steps() >= opt.max_steps) {
        sum.status = SimulationStatus::kStepLimit;
        sum.message = "step limit reached at t = " + std::to_string(t);
        break;
      }
      if (observer.on_progress && sum.impacts >= next_progress) {
        observer.on_progress(t);
        next_progress = sum.impacts + 10000;
      }
      // Samples within round-off of t take the current state; then return at
      // the next sample time (CVODE interpolates there) or at a root.
      sampler.Emit(t + 1e-12 * std::max(1.0, t), [&](double) { return Eigen::VectorXd(z); });
      double tout = opt.t_end;
      if (sampler.active()) tout = std::min(opt.t_end, sampler.NextTime());
      const int flag = solver.Step(tout, &t);
      if (!sticking && z[c] > d + xtol) {
        // Beyond the obstacle with no root reported (two crossings in one
        // step): locate the rising crossing on the dense output of the step.
        // A step that starts at or beyond the wall is a restart there: after
        // an impact, which CVODE's root location leaves up to
        // (|t| + |h|) 100 uround |v_c| beyond d (1e-11 at t = 4e4, above the
        // band at rtol 1e-13), the mass moves away; after an impact with
        // e = 0 where nothing pushed yet (g0 = 0, inactive by CVODE's rule)
        // it is pushed in later. It penetrates only if x_c rises a band above
        // where the step started, and the contact is half a band above that.
        const double lo = solver.LastStepStart();
        const double start = solver.Interpolate(lo)[c] - d;
        if (start < 0.0 || z[c] - d > start + xtol) {
          const double level = start < 0.0 ? 0.0 : start + 0.5 * xtol;
          auto gap = [&](double ts) { return solver.Interpolate(ts)[c] - d - level; };
          t = PolishRoot(gap, lo, t);
          z = solver.Interpolate(t);
          sampler.Emit(t, [&](double ts) { return solver.Interpolate(ts); });
          handle_contact();
          continue;
        }
      }
      sampler.Emit(t, [&](double ts) {
        return std::abs(ts - t) <= 1e-12 * std::max(1.0, t) ? Eigen::VectorXd(z) : solver.Interpolate(ts);
      });
      if (flag != CV_ROOT_RETURN) continue;
      if (sticking) {
        sum.sticking_time += t - stick_start;
        sticking = false;
        restart();
        continue;
      }
      if (solver.RootInfo(0) != 0) {
        handle_contact();
      } else if (solver.RootInfo(1) != 0 && z[c] >= d - xtol) {
        handle_contact();  // a maximum of x_c in the contact band: a graze (or held)
      }
    }
  } catch (const Stopped&) {
    throw;  // a signal: not the solver's failure
  } catch (const std::exception& ex) {
    sum.status = SimulationStatus::kSolverError;
    sum.message = ex.what();
  }
  if (sticking) sum.sticking_time += t - stick_start;
  sum.steps = base_steps + solver.Steps();
  sum.final_time = t;
  sum.final_state = z;
  return sum;
}

}  // namespace nsmodal::internal
