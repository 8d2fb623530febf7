// The exact event-driven integrator: closed-form flight, impacts found by
// conservative advancement (first_rise.h), the sticking phase in closed form
// (contact.h), Zeno sequences summed. One stepper (event_loop.h) over two
// flights:
//   ConservativeFlight  the paper's model: scaled modal state, rotations;
//   ForcedFlight        damping and forces: physical state, forced_flow.h.
#include <algorithm>
#include <cmath>
#include <optional>

#include "event_loop.h"
#include "integrators.h"
#include "nsmodal/first_rise.h"

namespace nsmodal::internal {

struct ConservativeFlight {
  using State = Eigen::VectorXd;  // scaled modal y
  using Held = Eigen::VectorXd;   // StickingFlow's reduced modal state
  const ContactModel& cm;
  const ModalBasis& b;
  // Built at the first sticking phase: it refuses a rigid-body mode the held
  // contact does not stop, which only matters if the mass is ever held.
  std::optional<StickingFlow> stick;
  ContactSignal gap;
  SinusoidSum release;
  // The flights' impact search sweeps (first_rise.h) from this many modes
  // on: measured, a run with it against one without, 0.55 times as fast for
  // N = 2 (the grid's scalar work outweighs its saving on 2 sinusoids),
  // 1.2 times for N = 10, 2 times for N = 100.
  static constexpr int kSweepFromModes = 8;
  std::optional<SinusoidSweep> sweep;

  explicit ConservativeFlight(const ContactModel& c)
      : cm(c), b(c.basis), gap(c.basis, Eigen::VectorXd::Zero(2 * c.basis.n)) {
    gap.offset = -c.model.gap;
    if (b.n >= kSweepFromModes) sweep.emplace(b.omega);
  }
  FirstRiseResult Search(const ContactSignal& g, double horizon, double tol) {
    return sweep ? FirstRise(g, horizon, tol, *sweep) : FirstRise(g, horizon, tol);
  }
  double FastestRate() const { return b.omega.maxCoeff(); }
  State FromPhysical(const Eigen::VectorXd& z) const { return ToModal(b, z.head(b.n), z.tail(b.n)); }
  Eigen::VectorXd Physical(const State& y) const { return PhysicalOf(b, y); }
  const ContactSignal& Gap(double, const State& y) {
    gap.Reset(b, y);
    return gap;
  }
  void Fly(double, double s, State& y) const { Flow(b, s, y); }
  // x_c'' at the end of a flight, from the state there: -sum r_i w_i u_i
  // (no sin or cos; a rigid-body mode has w_i = 0).
  double Acceleration(const ContactSignal&, double, const State& y) const {
    return -(b.r.array() * b.omega.array() * y.head(b.n).array()).sum();
  }
  void Impact(double e, State& y) const { nsmodal::Impact(b, e, y); }
  double ContactVelocity(const State& y) const { return nsmodal::ContactVelocity(b, y); }
  Held Hold(double, const State& y) {
    const Eigen::VectorXd z = PhysicalOf(b, y);
    if (!stick) stick.emplace(cm);
    return stick->Enter(z.head(b.n), z.tail(b.n));
  }
  const SinusoidSum& Release(double, const Held& yr) {
    const SinusoidSum ac = stick->ContactAcceleration(yr);
    release = SinusoidSum(-ac.offset, -ac.a, -ac.b, ac.omega);  // release when -a_c rises to 0
    return release;
  }
  void FlyHeld(double, double s, Held& yr) const { stick->Advance(s, yr); }
  Eigen::VectorXd PhysicalHeld(const Held& yr) const { return stick->Physical(yr); }
};

struct ForcedFlight {
  using State = Eigen::VectorXd;  // physical (x, v)
  using Held = Eigen::VectorXd;   // (xi, xi') of the dofs other than c
  const ContactModel& cm;
  ForcedFlow flow;
  // Built at the first sticking phase: a held system resonating with the
  // forcing (undamped) only matters if the mass is ever held.
  std::optional<ForcedStickingFlow> stick;
  Eigen::RowVectorXd gap_row;
  DampedSignal gap, release;

  explicit ForcedFlight(const ContactModel& c) : cm(c), flow(c.model) {
    const int n = c.model.dofs();
    gap_row = Eigen::RowVectorXd::Zero(2 * n);
    gap_row[c.model.contact] = 1.0;
  }
  FirstRiseResult Search(const DampedSignal& g, double horizon, double tol) const { return FirstRise(g, horizon, tol); }
  double FastestRate() const { return cm.basis.omega.maxCoeff(); }
  State FromPhysical(const Eigen::VectorXd& z) const { return z; }
  Eigen::VectorXd Physical(const State& z) const { return z; }
  const DampedSignal& Gap(double t, const State& z) {
    flow.Observe(t, z, gap_row, -cm.model.gap, 0.0, gap);
    return gap;
  }
  void Fly(double t, double s, State& z) const { flow.Advance(t, s, z); }
  double Acceleration(const DampedSignal& g, double s, const State&) const { return g.Acceleration(s); }
  void Impact(double e, State& z) const {
    const int n = cm.model.dofs();
    cm.ApplyImpact(e, z.tail(n));
    if (e == 0.0) z[n + cm.model.contact] = 0.0;  // exactly, not to round-off
  }
  double ContactVelocity(const State& z) const { return z[cm.model.dofs() + cm.model.contact]; }
  Held Hold(double, const State& z) {
    if (!stick) stick.emplace(cm);
    return stick->Enter(z);
  }
  const DampedSignal& Release(double t, const Held& zr) {
    stick->Release(t, zr, release);
    return release;
  }
  void FlyHeld(double t, double s, Held& zr) const { stick->Advance(t, s, zr); }
  Eigen::VectorXd PhysicalHeld(const Held& zr) const { return stick->Physical(zr); }
};

// The exact integrator's advance (event_loop.h's Stepper): one flight to the
// first crossing of the gap's witness (the search's band is its resolution,
// witness.h), or one held stretch to the release, in closed form; samples by
// flying the stretch's start state to each sample time.
template <typename Flight>
class ExactStepper {
 public:
  using State = typename Flight::State;
  using Held = typename Flight::Held;

  ExactStepper(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
               const SimulateOptions& opt)
      : f_(cm),
        t_end_(opt.t_end),
        root_tol_(opt.root_tol),
        d_(cm.model.gap),
        zeno_flight_(opt.zeno_flight * 2.0 * M_PI / f_.FastestRate()) {
    Eigen::VectorXd z0(2 * cm.model.dofs());
    z0 << x0, v0;
    y_ = f_.FromPhysical(z0);
  }

  bool Finished() const { return t_ >= t_end_; }
  double Time() const { return t_; }
  long Steps() const { return steps_ + sweep_steps_; }

  // In the contact band, moving in (or at rest and pushed in).
  std::optional<int> InitialContact() {
    const auto& g = Band(f_.Gap(t_, y_));
    const double v = g.Velocity(0.0), a = g.Acceleration(0.0);
    if (g.Position(0.0) >= -tol_ && (v > vtol_ || (std::abs(v) <= vtol_ && a > 0.0))) {
      ac_ = a;
      return 0;
    }
    return std::nullopt;
  }

  Advance Step(Sampler& sampler) {
    const double horizon = t_end_ - t_;
    Advance a;
    if (!held_) {
      const auto& g = Band(f_.Gap(t_, y_));  // x_c - d on this flight
      const FirstRiseResult r = f_.Search(g, horizon, tol_);
      steps_ += r.steps;
      sweep_steps_ += r.sweep_steps;
      EmitAlong(sampler, t_ + r.s, y_, [&](double s, State& y) { f_.Fly(t_, s, y); },
                [&](const State& y) { return f_.Physical(y); });
      f_.Fly(t_, r.s, y_);
      t_ = r.found ? t_ + r.s : (r.s >= horizon ? t_end_ : t_ + r.s);
      if (r.stalled) return Failed("impact search stalled at a degenerate tangency at t = ");
      if (r.found) {
        ac_ = f_.Acceleration(g, r.s, y_);
        a.event = Advance::Event::kWitness;
      }
      return a;
    }
    const auto& g = f_.Release(t_, yr_);  // -a_c: released when it rises to 0
    const double tol = root_tol_ * std::max(std::abs(g.offset), g.bound[0]);
    const FirstRiseResult r = FirstRise(g, horizon, tol);
    steps_ += r.steps;
    EmitAlong(sampler, t_ + r.s, yr_, [&](double s, Held& y) { f_.FlyHeld(t_, s, y); },
              [&](const Held& y) { return f_.PhysicalHeld(y); });
    f_.FlyHeld(t_, r.s, yr_);
    a.held = r.s;
    t_ = r.found ? t_ + r.s : t_end_;
    if (r.stalled) {
      Advance failed = Failed("release search stalled at t = ");
      failed.held = r.s;
      return failed;
    }
    if (r.found) a.event = Advance::Event::kWitness;
    return a;
  }

  // A rebound lower than 2 tol can never arm the next search (it arms below
  // -2 tol, first_rise.h): such a sequence is summed as Zeno, not flown as
  // unarmed micro-flights that each end tol further out (4 tol: margin for
  // the acceleration's change over the rebound).
  ContactKinematics Contact(int) const {
    return {f_.ContactVelocity(y_), ac_, {vtol_, 4.0 * tol_, zeno_flight_}};
  }
  Eigen::VectorXd Physical() const { return held_ ? f_.PhysicalHeld(yr_) : f_.Physical(y_); }
  void Impact(int, double e) { f_.Impact(e, y_); }
  void Hold(int) {
    f_.Impact(0.0, y_);  // v_c -> 0
    yr_ = f_.Hold(t_, y_);
    held_ = true;
  }
  void Release(int) {
    y_ = f_.FromPhysical(f_.PhysicalHeld(yr_));
    held_ = false;
  }
  void Restart() {}
  void Finish(SimulationSummary& sum) const {
    sum.steps = steps_;
    sum.sweep_steps = sweep_steps_;
    sum.final_time = t_;
    sum.final_state = Physical();
  }

 private:
  // The contact band of the flight of g: its half-width tol (relative to the
  // signal's scale) and the speed below which a contact is a graze or a hold.
  template <typename Signal>
  const Signal& Band(const Signal& g) {
    tol_ = root_tol_ * std::max({d_, std::abs(g.offset), g.bound[0]});
    vtol_ = std::sqrt(2.0 * g.bound[2] * tol_);
    return g;
  }
  // The samples of the stretch about to be flown from (t_, start), before it
  // is: each flies the start to its time.
  template <typename S, typename Fly, typename ToPhysical>
  void EmitAlong(Sampler& sampler, double to, const S& start, Fly fly, ToPhysical physical) const {
    sampler.Emit(to, [&](double ts) {
      S y = start;
      fly(ts - t_, y);
      return physical(y);
    });
  }
  Advance Failed(const std::string& what) const {
    Advance a;
    a.event = Advance::Event::kFailed;
    a.message = what + std::to_string(t_);
    return a;
  }

  Flight f_;
  const double t_end_, root_tol_, d_, zeno_flight_;
  State y_;   // free-flight state
  Held yr_;   // sticking state
  bool held_ = false;
  double t_ = 0.0;
  double tol_ = 0.0, vtol_ = 0.0, ac_ = 0.0;  // the band and x_c'' at the contact found
  long steps_ = 0, sweep_steps_ = 0;
};

template NSMODAL_RUN_INTEGRATOR(ExactStepper<ConservativeFlight>);
template NSMODAL_RUN_INTEGRATOR(ExactStepper<ForcedFlight>);

}  // namespace nsmodal::internal
