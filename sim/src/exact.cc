// The exact event-driven integrator: closed-form flight, impacts found by
// conservative advancement (first_rise.h), the sticking phase in closed form
// (contact.h), Zeno sequences summed. One stepper (event_loop.h) over two
// flights:
//   ConservativeFlight  the paper's model: scaled modal state, rotations;
//   ForcedFlight        damping and forces: physical state, forced_flow.h.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <vector>

#include "event_loop.h"
#include "integrators.h"
#include "nsmodal/first_rise.h"

namespace nsmodal::internal {

struct ConservativeFlight {
  using State = Eigen::VectorXd;  // scaled modal y
  using Held = Eigen::VectorXd;   // StickingFlow's reduced modal state
  using Signal = SinusoidSum;
  const ContactModel& cm;
  const ModalBasis& b;
  // Built at a held set's first sticking phase: it refuses a rigid-body mode
  // the held contacts do not stop, which only matters if they are ever held.
  std::map<std::vector<int>, StickingFlow> stick;
  const StickingFlow* held = nullptr;  // the sticking phase flown
  std::vector<ContactSignal> gaps;  // one per contact
  SinusoidSum release, other;
  // The flights' impact search sweeps (first_rise.h) from this many modes
  // on: measured, a run with it against one without, 0.55 times as fast for
  // N = 2 (the grid's scalar work outweighs its saving on 2 sinusoids),
  // 1.2 times for N = 10, 2 times for N = 100.
  static constexpr int kSweepFromModes = 8;
  std::optional<SinusoidSweep> sweep;

  explicit ConservativeFlight(const ContactModel& c) : cm(c), b(c.basis) {
    for (int j = 0; j < c.NumContacts(); ++j) {
      gaps.emplace_back(c.basis, c.basis.contacts[j], Eigen::VectorXd::Zero(2 * c.basis.n));
      gaps.back().offset = -c.contact(j).gap;
    }
    if (b.n >= kSweepFromModes) sweep.emplace(b.omega);
  }
  FirstRiseResult Search(const SinusoidSum& g, double horizon, double tol) {
    return sweep ? FirstRise(g, horizon, tol, *sweep) : FirstRise(g, horizon, tol);
  }
  State FromPhysical(const Eigen::VectorXd& z) const { return ToModal(b, z.head(b.n), z.tail(b.n)); }
  Eigen::VectorXd Physical(const State& y) const { return PhysicalOf(b, y); }
  // n_j . x - d_j on the flight from y.
  const SinusoidSum& Gap(int j, double, const State& y) {
    gaps[j].Reset(b, b.contacts[j], y);
    return gaps[j];
  }
  void Fly(double, double s, State& y) const { Flow(b, s, y); }
  // The signal's second derivative at the end of a flight, from the state
  // there: -sum r_i w_i u_i (no sin or cos; a rigid-body mode has w_i = 0).
  double Acceleration(int j, const SinusoidSum&, double, const State& y) const {
    return -(b.contacts[j].r.array() * b.omega.array() * y.head(b.n).array()).sum();
  }
  void Impact(int j, double e, State& y) const { nsmodal::Impact(b, b.contacts[j], e, y); }
  double ContactVelocity(int j, const State& y) const { return b.contacts[j].r.dot(y.tail(b.n)); }
  Held Hold(const std::vector<int>& set, double, const State& y) {
    const Eigen::VectorXd z = PhysicalOf(b, y);
    auto it = stick.find(set);
    if (it == stick.end()) it = stick.emplace(set, StickingFlow(cm, set)).first;
    held = &it->second;
    return held->Enter(z.head(b.n), z.tail(b.n));
  }
  // The i-th held contact's release signal: minus its force, rising to 0.
  const SinusoidSum& Release(int i, double, const Held& yr) {
    const SinusoidSum ac = held->ContactAcceleration(i, yr);
    release = SinusoidSum(-ac.offset, -ac.a, -ac.b, ac.omega);
    return release;
  }
  const SinusoidSum& OtherGap(int k, double, const Held& yr) {
    other = held->OtherGap(k, yr);
    return other;
  }
  void FlyHeld(double, double s, Held& yr) const { held->Advance(s, yr); }
  Eigen::VectorXd PhysicalHeld(const Held& yr) const { return held->Physical(yr); }
};

struct ForcedFlight {
  using State = Eigen::VectorXd;  // physical (x, v)
  using Held = Eigen::VectorXd;   // (xi, xi') of the held subspace
  using Signal = DampedSignal;
  const ContactModel& cm;
  ForcedFlow flow;
  // Built at a held set's first sticking phase: a held system resonating
  // with the forcing (undamped) only matters if it is ever held.
  std::map<std::vector<int>, ForcedStickingFlow> stick;
  const ForcedStickingFlow* held = nullptr;
  std::vector<Eigen::RowVectorXd> gap_rows;  // (n_j', 0)
  std::vector<DampedSignal> gaps;
  DampedSignal release, other;

  explicit ForcedFlight(const ContactModel& c)
      : cm(c), flow(c.model), gaps(c.NumContacts()) {
    const int n = c.model.dofs();
    for (int j = 0; j < c.NumContacts(); ++j) {
      gap_rows.push_back(Eigen::RowVectorXd::Zero(2 * n));
      gap_rows.back().head(n) = c.contact(j).normal.transpose();
    }
  }
  FirstRiseResult Search(const DampedSignal& g, double horizon, double tol) const { return FirstRise(g, horizon, tol); }
  State FromPhysical(const Eigen::VectorXd& z) const { return z; }
  Eigen::VectorXd Physical(const State& z) const { return z; }
  const DampedSignal& Gap(int j, double t, const State& z) {
    flow.Observe(t, z, gap_rows[j], -cm.contact(j).gap, 0.0, gaps[j]);
    return gaps[j];
  }
  void Fly(double t, double s, State& z) const { flow.Advance(t, s, z); }
  double Acceleration(int, const DampedSignal& g, double s, const State&) const { return g.Acceleration(s); }
  void Impact(int j, double e, State& z) const {
    const int n = cm.model.dofs();
    cm.ApplyImpact(j, e, z.tail(n));
    const Contact& c = cm.contact(j);
    if (e == 0.0 && c.form == Contact::Form::kDof) z[n + c.dof] = 0.0;  // exactly, not to round-off
  }
  double ContactVelocity(int j, const State& z) const { return cm.contact(j).Along(z.tail(cm.model.dofs())); }
  Held Hold(const std::vector<int>& set, double, const State& z) {
    auto it = stick.find(set);
    if (it == stick.end()) it = stick.emplace(set, ForcedStickingFlow(cm, set)).first;
    held = &it->second;
    return held->Enter(z);
  }
  const DampedSignal& Release(int i, double t, const Held& zr) {
    held->Release(i, t, zr, release);
    return release;
  }
  const DampedSignal& OtherGap(int k, double t, const Held& zr) {
    held->OtherGap(k, t, zr, other);
    return other;
  }
  void FlyHeld(double t, double s, Held& zr) const { held->Advance(t, s, zr); }
  Eigen::VectorXd PhysicalHeld(const Held& zr) const { return held->Physical(zr); }
};

// The exact integrator's advance (event_loop.h's Stepper): one flight to the
// first crossing of any contact's gap witness (each contact's search bounded
// by the earliest crossing found so far, so K contacts cost at most K
// searches and none is missed: each search is guaranteed on its own signal;
// the search's band is its resolution, witness.h), or one held stretch to
// the release or to another contact's crossing, in closed form; samples by
// flying the stretch's start state to each sample time.
template <typename Flight>
class ExactStepper {
 public:
  using State = typename Flight::State;
  using Held = typename Flight::Held;

  ExactStepper(const ContactModel& cm, const Eigen::VectorXd& x0, const Eigen::VectorXd& v0,
               const SimulateOptions& opt)
      : cm_(cm),
        f_(cm),
        k_(cm.NumContacts()),
        t_end_(opt.t_end),
        root_tol_(opt.root_tol),
        zeno_flight_(ZenoFlightTime(cm, opt)),
        tol_(k_, 0.0),
        vtol_(k_, 0.0) {
    Eigen::VectorXd z0(2 * cm.model.dofs());
    z0 << x0, v0;
    y_ = f_.FromPhysical(z0);
    t_ = opt.t_start;
  }

  bool Finished() const { return t_ >= t_end_; }
  double Time() const { return t_; }
  long Steps() const { return steps_ + sweep_steps_; }

  // In a contact's band, moving in (or at rest and pushed in): the first such.
  std::optional<int> InitialContact() {
    for (int j = 0; j < k_; ++j) {
      const auto& g = Band(j, f_.Gap(j, t_, y_));
      const double v = g.Velocity(0.0), a = g.Acceleration(0.0);
      if (g.Position(0.0) >= -tol_[j] && (v > vtol_[j] || (std::abs(v) <= vtol_[j] && a > 0.0))) {
        ac_ = a;
        return j;
      }
    }
    return std::nullopt;
  }

  Advance Step(Sampler& sampler) {
    const double horizon = t_end_ - t_;
    Advance a;
    if (held_.empty()) {
      // Each contact's n_j . x - d_j on this flight, searched up to the
      // earliest crossing found so far.
      FirstRiseResult best;
      best.s = horizon;
      int first = -1;
      const typename Flight::Signal* crossed = nullptr;  // the signal of the crossing found
      for (int j = 0; j < k_; ++j) {
        const auto& g = Band(j, f_.Gap(j, t_, y_));
        const FirstRiseResult r = f_.Search(g, best.s, tol_[j]);
        steps_ += r.steps;
        sweep_steps_ += r.sweep_steps;
        if (r.stalled) {
          best = r;
          first = j;
          break;
        }
        if (r.found) {
          best.found = true;
          best.s = r.s;
          first = j;
          crossed = &g;
        }
      }
      EmitAlong(sampler, t_ + best.s, y_, [&](double s, State& y) { f_.Fly(t_, s, y); },
                [&](const State& y) { return f_.Physical(y); });
      f_.Fly(t_, best.s, y_);
      t_ = best.found ? t_ + best.s : (best.s >= horizon ? t_end_ : t_ + best.s);
      if (best.stalled) return Failed("impact search stalled at a degenerate tangency at t = ");
      if (best.found) {
        // The normal acceleration at the crossing (the band is the flight's).
        ac_ = f_.Acceleration(first, *crossed, best.s, y_);
        a.event = Advance::Event::kWitness;
        a.contact = first;
      }
      return a;
    }
    // Held: a release (minus a held contact's force rising to 0) or another
    // contact's crossing, each searched up to the earliest found so far.
    FirstRiseResult best;
    best.s = horizon;
    int first = -1;
    for (int i = 0; i < static_cast<int>(held_.size()) && !best.stalled; ++i) {
      const auto& g = f_.Release(i, t_, yr_);
      const double tol = root_tol_ * std::max(std::abs(g.offset), g.bound[0]);
      const FirstRiseResult r = FirstRise(g, best.s, tol);
      steps_ += r.steps;
      if (r.stalled) best = r;
      if (r.found) {
        best.found = true;
        best.s = r.s;
        first = held_[i];
      }
    }
    for (int k = 0; k < k_ && !best.stalled; ++k) {
      if (std::find(held_.begin(), held_.end(), k) != held_.end()) continue;
      const auto& o = Band(k, f_.OtherGap(k, t_, yr_));
      const FirstRiseResult r = FirstRise(o, best.s, tol_[k]);
      steps_ += r.steps;
      if (r.stalled) best = r;
      if (r.found) {
        best.found = true;
        best.s = r.s;
        first = k;
        held_ac_ = o.Acceleration(r.s);  // n_k . x'' along the held motion
      }
    }
    EmitAlong(sampler, t_ + best.s, yr_, [&](double s, Held& y) { f_.FlyHeld(t_, s, y); },
              [&](const Held& y) { return f_.PhysicalHeld(y); });
    f_.FlyHeld(t_, best.s, yr_);
    a.held = best.s;
    t_ = best.found ? t_ + best.s : (best.s >= horizon ? t_end_ : t_ + best.s);
    if (best.stalled) {
      Advance failed = Failed("release search stalled at t = ");
      failed.held = best.s;
      return failed;
    }
    if (best.found) {
      a.event = Advance::Event::kWitness;
      a.contact = first;
      if (std::find(held_.begin(), held_.end(), first) == held_.end()) pending_ = first;  // struck while held
    }
    return a;
  }

  // A rebound lower than 2 tol can never arm the next search (it arms below
  // -2 tol, first_rise.h): such a sequence is summed as Zeno, not flown as
  // unarmed micro-flights that each end tol further out (4 tol: margin for
  // the acceleration's change over the rebound).
  // While others are held: contact j's velocity and acceleration along the held motion.
  ContactKinematics Contact(int j) const {
    if (!held_.empty()) {
      const Eigen::VectorXd z = f_.PhysicalHeld(yr_);
      const int n = cm_.model.dofs();
      return {cm_.contact(j).Along(z.tail(n)), held_ac_, {vtol_[j], 4.0 * tol_[j], zeno_flight_}};
    }
    return {f_.ContactVelocity(j, y_), ac_, {vtol_[j], 4.0 * tol_[j], zeno_flight_}};
  }
  ContactKinematics Resting(int j) {
    if (held_.empty()) {
      const auto& g = Band(j, f_.Gap(j, t_, y_));
      return {g.Velocity(0.0), g.Acceleration(0.0), {vtol_[j], 4.0 * tol_[j], zeno_flight_}};
    }
    const auto& g = Band(j, f_.OtherGap(j, t_, yr_));
    return {g.Velocity(0.0), g.Acceleration(0.0), {vtol_[j], 4.0 * tol_[j], zeno_flight_}};
  }
  Eigen::VectorXd Physical() const { return !held_.empty() ? f_.PhysicalHeld(yr_) : f_.Physical(y_); }
  // Newton's law at contact j, and at every other contact in its band and
  // not moving away at that instant (struck at once: contact.h's law).
  const std::vector<int>& Impact(int j, double e) {
    set_.assign(1, j);
    for (int k = 0; k < k_; ++k) {
      if (k == j) continue;
      const auto& g = Band(k, f_.Gap(k, t_, y_));
      if (g.Position(0.0) >= -tol_[k] && g.Velocity(0.0) >= -vtol_[k]) set_.push_back(k);
    }
    if (set_.size() == 1) {
      f_.Impact(j, e, y_);
      return set_;
    }
    Eigen::VectorXd z = f_.Physical(y_);
    if (!cm_.ApplyImpacts(set_, z.tail(cm_.model.dofs()), false, &struck_)) {
      throw SolverError("the LCP of the contacts struck at once at t = " + std::to_string(t_) + " has no solution");
    }
    y_ = f_.FromPhysical(z);
    if (struck_.empty()) struck_ = {j};  // round-off left no impulse: the contact found is the event
    return struck_;
  }
  // Hold j: alone (n_j . v -> 0), or with the contacts already held (the
  // impulses that bring all their normal velocities to 0: contact.h
  // HoldVelocity).
  void Hold(int j) {
    if (held_.empty()) {
      f_.Impact(j, 0.0, y_);  // n_j . v -> 0
      held_ = {j};
      yr_ = f_.Hold(held_, t_, y_);
      return;
    }
    Eigen::VectorXd z = f_.PhysicalHeld(yr_);
    held_.push_back(j);
    std::sort(held_.begin(), held_.end());
    if (!cm_.HoldVelocity(held_, z.tail(cm_.model.dofs()))) {
      throw SolverError("the contacts held at once at t = " + std::to_string(t_) + " have dependent normals");
    }
    yr_ = f_.Hold(held_, t_, f_.FromPhysical(z));
  }
  // Release j: free flight, or the others held on from the same state.
  void Release(int j) {
    const Eigen::VectorXd z = f_.PhysicalHeld(yr_);
    held_.erase(std::remove(held_.begin(), held_.end(), j), held_.end());
    if (!held_.empty()) {
      yr_ = f_.Hold(held_, t_, f_.FromPhysical(z));
      return;
    }
    y_ = f_.FromPhysical(z);
    if (pending_ >= 0) {
      const auto& g = Band(pending_, f_.Gap(pending_, t_, y_));
      ac_ = g.Acceleration(0.0);
      pending_ = -1;
    }
  }
  void Restart() { pending_ = -1; }
  void Finish(SimulationSummary& sum) const {
    sum.steps = steps_;
    sum.sweep_steps = sweep_steps_;
    sum.final_time = t_;
    sum.final_state = Physical();
  }

 private:
  // Contact j's band on the flight of g: its half-width tol (relative to the
  // signal's scale) and the speed below which a contact is a graze or a hold.
  template <typename Signal>
  const Signal& Band(int j, const Signal& g) {
    tol_[j] = root_tol_ * std::max({cm_.contact(j).gap, std::abs(g.offset), g.bound[0]});
    vtol_[j] = std::sqrt(2.0 * g.bound[2] * tol_[j]);
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

  const ContactModel& cm_;
  Flight f_;
  const int k_;
  const double t_end_, root_tol_, zeno_flight_;
  State y_;   // free-flight state
  Held yr_;   // sticking state
  std::vector<int> held_;  // the held contacts, ascending (none: free flight)
  int pending_ = -1;       // a contact struck while others were held: its free kinematics after the release
  double held_ac_ = 0.0;   // its n . x'' along the held motion
  double t_ = 0.0;
  std::vector<double> tol_, vtol_;  // each contact's band, from its last signal
  double ac_ = 0.0;                 // the free normal acceleration at the contact found
  std::vector<int> set_, struck_;   // the contacts in their bands at an impact, those given an impulse (storage reused)
  long steps_ = 0, sweep_steps_ = 0;
};

template NSMODAL_RUN_INTEGRATOR(ExactStepper<ConservativeFlight>);
template NSMODAL_RUN_INTEGRATOR(ExactStepper<ForcedFlight>);

}  // namespace nsmodal::internal
