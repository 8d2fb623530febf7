#include "nsmodal/response.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <utility>

#include "nsmodal/check.h"
#include "nsmodal/error.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/two_impact.h"
#include "nsmodal/roots.h"
#include "nsmodal/stop.h"
#include "tracer.h"

namespace nsmodal {

std::string ToString(SpecialKind kind) {
  switch (kind) {
    case SpecialKind::kFold: return "fold";
    case SpecialKind::kPeriodDoubling: return "period-doubling";
    case SpecialKind::kGrazing: return "grazing";
    case SpecialKind::kZeroVelocity: return "zero-velocity";
    case SpecialKind::kPeak: return "peak";
    case SpecialKind::kTorus: return "torus";
  }
  return "?";
}

std::string ResponseOptions::ParameterName() const {
  switch (parameter) {
    case ResponseParameter::kFrequency: return "w";
    case ResponseParameter::kAmplitude: return "a";
    case ResponseParameter::kModel: break;
  }
  NSMODAL_CHECK(model_parameter.has_value());
  return model_parameter->name;
}

void ResponseOptions::Validate(const FieldNames& names) const {
  const bool frequency = parameter == ResponseParameter::kFrequency;
  if (parameter == ResponseParameter::kModel) {
    // The grid may start at 0 (a damping ratio, a restitution): the model's
    // own checks say which values are valid (ComputeResponse checks both ends).
    if (!model_parameter) throw InputError(names("parameter"), "is missing: the model parameter to follow");
    CheckParameterRange(grid, names("range"));
  } else {
    grid.Validate(names(frequency ? "frequency" : "amplitude"));
  }
  if (impacts < 0 || impacts > kMaxResponseImpacts) {
    throw InputError(names("impacts"), "must be between 0 (the linear response) and " +
                                           std::to_string(kMaxResponseImpacts) + ", got " + std::to_string(impacts));
  }
  if (periods < 1 || periods > kMaxResponsePeriods || (impacts == 0 && periods != 1)) {
    throw InputError(names("periods"), impacts == 0 ? "must be 1 for the linear response (m = 0), got " +
                                                          std::to_string(periods)
                                                    : "must be between 1 and " + std::to_string(kMaxResponsePeriods) +
                                                          ", got " + std::to_string(periods));
  }
  if (parameter != ResponseParameter::kModel && (!(fixed > 0.0) || !std::isfinite(fixed))) {
    throw InputError(names(frequency ? "amplitude" : "frequency"), "must be positive and finite, got " + FormatValue(fixed));
  }
  if (max_steps < 1 || max_branches < 1) throw InputError(names("max_steps"), "bounds must be positive");
  if (!sequence.empty() && static_cast<int>(sequence.size()) != impacts) {
    throw InputError(names("sequence"), "lists " + std::to_string(sequence.size()) + " impacts, but impacts is " +
                                            std::to_string(impacts));
  }
}

namespace {

using detail::ComplexPairs;
using detail::PeriodDoublingTest;
using detail::SegmentLocator;
using detail::TorusTest;
using detail::Tracer;
using detail::Vec;

// The parameter a response is followed in: the model, frequency, amplitude
// and response problem at each of its values.
class ResponseAxis {
 public:
  ResponseAxis(const Model& model, const ResponseOptions& opt) : model_(model), opt_(opt) {}
  // The model at lambda (kModel: null where the value leaves the valid
  // model, the continuation's domain; else the model itself).
  std::optional<Model> ModelAt(double lambda) const {
    if (opt_.parameter != ResponseParameter::kModel) return model_;
    try {
      return WithParameter(model_, *opt_.model_parameter, lambda);
    } catch (const InputError&) {
      return std::nullopt;
    }
  }
  // Frequency and amplitude at lambda, of the model at lambda.
  double Frequency(const Model& m, double lambda) const {
    switch (opt_.parameter) {
      case ResponseParameter::kFrequency: return lambda;
      case ResponseParameter::kAmplitude: return opt_.fixed;
      case ResponseParameter::kModel: break;
    }
    return m.forcing.frequency;
  }
  double Amplitude(const Model& m, double lambda) const {
    switch (opt_.parameter) {
      case ResponseParameter::kFrequency: return opt_.fixed;
      case ResponseParameter::kAmplitude: return lambda;
      case ResponseParameter::kModel: break;
    }
    return m.ForceAmplitude().cwiseAbs().maxCoeff();
  }
  // The problem at lambda; null outside the continuation's domain (a w or a
  // <= 0; a model parameter's value that leaves the valid model).
  // For a model parameter, a value where the problem cannot be posed (an
  // undamped model at e = 1, a period beyond ForcedProblem's bound) or has
  // another number of unknowns (a spring at 0: a rigid-body mode) is outside
  // the domain too.
  std::unique_ptr<ForcedProblem> Problem(double lambda, int unknowns) const {
    if (opt_.parameter != ResponseParameter::kModel && !(lambda > 0.0)) return nullptr;
    const std::optional<Model> m = ModelAt(lambda);
    if (!m) return nullptr;
    const double w = Frequency(*m, lambda), a = Amplitude(*m, lambda);
    if (opt_.parameter != ResponseParameter::kModel) {
      return detail::MakeForcedProblem(*m, opt_.impacts, opt_.sequence, opt_.periods, w, a);
    }
    return detail::PosedProblem(*m, opt_.impacts, opt_.sequence, opt_.periods, w, a, unknowns);
  }
  // The linear response (m = 0) at lambda; nullopt outside the domain.
  std::optional<ForcedOrbit> Linear(double lambda) const {
    const std::optional<Model> m = ModelAt(lambda);
    if (!m) return std::nullopt;
    return LinearResponse(*m, Frequency(*m, lambda), Amplitude(*m, lambda));
  }
  // The continuation of the (m, n) family in xi = (phi / 2 pi, tau_i / P0,
  // c / d, lambda / L): P0 the response period at the range's middle, d the
  // least gap struck, L the range's width.
  detail::TracerSetup Setup() const {
    detail::TracerSetup s;
    s.impacts = opt_.impacts;
    s.unknowns = opt_.impacts == 0 ? 0 : opt_.impacts + RigidBodyModes(model_.stiffness);
    s.problem = [this, k = s.unknowns](const Vec& l) { return Problem(l[0], k); };
    s.linear = [this](const Vec& l) { return Linear(l[0]); };
    const double mid = 0.5 * (opt_.grid.from + opt_.grid.to);
    const double w_mid = opt_.parameter == ResponseParameter::kFrequency ? mid
                         : opt_.parameter == ResponseParameter::kAmplitude ? opt_.fixed
                                                                          : ModelAt(mid)->forcing.frequency;
    s.period_scale = opt_.periods * 2.0 * M_PI / w_mid;
    s.lambda_scale = Vec::Constant(1, std::max(opt_.grid.to - opt_.grid.from, opt_.grid.step));
    s.gap_scale = LeastGapStruck(model_, opt_.sequence);
    s.one_sided = opt_.parameter == ResponseParameter::kModel;
    return s;
  }

 private:
  const Model& model_;
  const ResponseOptions& opt_;
};

// A point of a branch with its test functions.
struct Node {
  Vec xi, tangent;
  ForcedOrbit orbit;
  bool grid = false;  // solved at a grid value
};

constexpr const char* kClosed = "closed on itself";

class Responder {
 public:
  Responder(const Model& model, const ResponseOptions& opt) : opt_(opt), axis_(model, opt), tr_(axis_.Setup()) {
    curve_.options = opt;
  }

  ResponseCurve Run() {
    std::vector<double> grid = opt_.grid.Values();
    // (A model parameter's last value no further than TO: from + k step may
    // pass it by an ulp, out of the valid range when TO is its end, e = 1.)
    if (opt_.parameter == ResponseParameter::kModel) {
      for (double& g : grid) g = std::min(g, opt_.grid.to);
    }
    if (opt_.impacts == 0) {
      Linear(grid);
      return curve_;
    }
    for (std::size_t g = 0; g < grid.size(); ++g) {
      ThrowIfStopRequested();
      if (opt_.progress) opt_.progress(static_cast<long>(g), static_cast<long>(grid.size()));
      const std::unique_ptr<ForcedProblem> p = tr_.Problem(grid[g]);
      if (!p) {
        curve_.notes.push_back("no model at " + Name() + " = " + FormatValue(grid[g]) + ": skipped");
        continue;
      }
      for (const Vec& u : p->FindAll()) {
        const Vec xi = tr_.Xi(u, grid[g]);
        if (Covered(*p, xi, grid[g])) continue;
        if (static_cast<int>(curve_.branches.size()) >= opt_.max_branches) {
          curve_.notes.push_back("branch limit (" + std::to_string(opt_.max_branches) + ") reached at " +
                                 Name() + " = " + FormatValue(grid[g]) + "; further branches not followed");
          return curve_;
        }
        Trace(xi);
      }
    }
    if (opt_.progress) opt_.progress(static_cast<long>(grid.size()), static_cast<long>(grid.size()));
    return curve_;
  }

 private:
  std::string Name() const { return opt_.ParameterName(); }

  // A start is covered when a branch has a grid node at the same value with
  // the same orbit.
  bool Covered(const ForcedProblem& p, const Vec& xi, double lambda) const {
    const Vec c = p.Canonical(tr_.U(xi));
    for (const auto& nodes : grid_nodes_) {
      for (const Vec& other : nodes) {
        if (std::abs(tr_.Lambda(other) - lambda) > 1e-12 * std::max(tr_.LambdaScale(), std::abs(lambda))) continue;
        Vec d = p.Canonical(tr_.U(other)) - c;
        d[0] = std::remainder(d[0], 2.0 * M_PI);
        if (d.cwiseAbs().maxCoeff() <= 1e-6 * std::max(1.0, p.period())) return true;
      }
    }
    return false;
  }

  Node MakeNode(const Vec& xi, const Vec& along, bool grid) const {
    Node n;
    n.xi = xi;
    Eigen::MatrixXd j;
    if (tr_.Jacobian(xi, j)) n.tangent = Tracer::Tangent(j, along);
    n.orbit = tr_.Orbit(xi);
    n.grid = grid;
    return n;
  }

  // Follows the branch through xi0 both ways; stores it as one branch.
  void Trace(const Vec& xi0) {
    const int index = static_cast<int>(curve_.branches.size());
    Vec up = Vec::Zero(tr_.dim());
    up[tr_.dim() - 1] = 1.0;
    std::string end_up, end_down;
    grid_nodes_.emplace_back();
    std::vector<Node> forward = Follow(xi0, up, &end_up);
    // A closed branch is whole after one way round.
    std::vector<Node> backward =
        end_up == kClosed ? std::vector<Node>{forward.front()} : Follow(xi0, -up, &end_down);
    std::vector<Node> nodes(backward.rbegin(), backward.rend() - 1);  // drop the shared start
    // The backward nodes' tangents point down the branch: turned to point
    // along the nodes' order, as the forward ones do (else the start, where
    // the two meet, looked like a fold to Special: a tangent's lambda
    // changing sign, and a fold "not located" there).
    for (Node& n : nodes) n.tangent = -n.tangent;
    nodes.insert(nodes.end(), forward.begin(), forward.end());
    ResponseBranch branch;
    branch.end = end_up == kClosed ? end_up : "down: " + end_down + "; up: " + end_up;
    for (const Node& n : nodes) {
      branch.points.push_back(n.orbit);
      branch.parameter.push_back(tr_.Lambda(n.xi));
    }
    curve_.branches.push_back(std::move(branch));
    Special(nodes, index);
  }

  // Pseudo-arclength from xi0 in the direction of `dir`, until the range is
  // left, the branch closes, the corrector fails or the step bound is hit.
  std::vector<Node> Follow(const Vec& xi0, const Vec& dir, std::string* end) {
    const double lo = opt_.grid.from / tr_.LambdaScale(), hi = opt_.grid.to / tr_.LambdaScale();
    const double h_max = opt_.grid.step / tr_.LambdaScale();
    const double h_min = 1e-9 * h_max;
    std::vector<Node> nodes{MakeNode(xi0, dir, true)};
    grid_nodes_.back().push_back(xi0);
    if (nodes[0].tangent.size() == 0) {
      *end = "no tangent at the start";
      return nodes;
    }
    double h = h_max;
    for (long step = 0;; ++step) {
      ThrowIfStopRequested();
      if (step >= opt_.max_steps) {
        *end = "step limit (" + std::to_string(opt_.max_steps) + ") reached";
        curve_.notes.push_back("branch " + std::to_string(curve_.branches.size() + 1) + ": " + *end);
        return nodes;
      }
      const Node& cur = nodes.back();
      const Vec pred = cur.xi + h * cur.tangent;
      const std::optional<Vec> next = tr_.Correct(pred, pred, cur.tangent);
      // A step past the range into values where the model is not valid (a
      // restitution past 1): the branch ends on the range's edge, solved there.
      if (!next && EndOnEdge(cur, pred, nodes, end)) return nodes;
      // A step must move forward along the branch and not jump to another.
      if (!Tracer::Accepted(cur.xi, cur.tangent, pred, next, h)) {
        h *= 0.5;
        if (h < h_min) {
          *end = "lost at " + Name() + " = " + FormatValue(tr_.Lambda(cur.xi)) + " (corrector failed; e.g. two "
                 "impacts merging or a non-smooth point)";
          return nodes;
        }
        continue;
      }
      // Grid values crossed on the way get nodes of their own.
      const double l0 = cur.xi[tr_.dim() - 1], l1 = (*next)[tr_.dim() - 1];
      const Vec cur_xi = cur.xi, cur_t = cur.tangent;
      for (double g : GridBetween(l0, l1)) {
        const double a = (g - l0) / (l1 - l0);
        if (const std::optional<Vec> at = tr_.SolveAt(g * tr_.LambdaScale(), cur_xi + a * (*next - cur_xi))) {
          nodes.push_back(MakeNode(*at, cur_t, true));
          grid_nodes_.back().push_back(*at);
        }
      }
      Node node = MakeNode(*next, cur_t, false);
      if (node.tangent.size() == 0) {
        *end = "no tangent at " + Name() + " = " + FormatValue(tr_.Lambda(*next));
        return nodes;
      }
      const bool out = l1 < lo - 1e-12 || l1 > hi + 1e-12;
      if (out) {
        // End exactly on the range's boundary.
        const double edge = l1 > hi ? hi : lo;
        const double a = (edge - l0) / (l1 - l0);
        if (const std::optional<Vec> at =
                tr_.SolveAt(edge * tr_.LambdaScale(), cur_xi + a * (*next - cur_xi))) {
          if (std::abs(nodes.back().xi[tr_.dim() - 1] - edge) > 1e-12) nodes.push_back(MakeNode(*at, cur_t, true));
          // The edge is a grid value too (the range's first or last): its
          // orbit recorded, so that a start found there is covered, not
          // traced as a new branch (GridBetween leaves the edges out).
          grid_nodes_.back().push_back(*at);
        }
        *end = "left the range at " + Name() + " = " + FormatValue(edge * tr_.LambdaScale());
        return nodes;
      }
      nodes.push_back(std::move(node));
      // A closed branch (an isola, or a loop) comes back to its start.
      if (step > 4 && (nodes.back().xi - xi0).norm() < 0.5 * h_max) {
        *end = kClosed;
        return nodes;
      }
      if (step > 0 && h < h_max) h = std::min(h_max, 1.5 * h);
    }
  }

  // The branch's end on the range's edge when `pred` is past it: the grid
  // values before the edge and the edge get nodes. False when pred is inside
  // the range or the edge cannot be solved.
  bool EndOnEdge(const Node& cur_node, const Vec& pred, std::vector<Node>& nodes, std::string* end) {
    const int last = tr_.dim() - 1;
    const double lo = opt_.grid.from / tr_.LambdaScale(), hi = opt_.grid.to / tr_.LambdaScale();
    const double lp = pred[last], l0 = cur_node.xi[last];
    if (!(lp > hi + 1e-12 || lp < lo - 1e-12) || lp == l0) return false;
    if (tr_.Problem(tr_.Lambda(pred))) return false;  // (inside the domain: the corrector's own failure)
    const double edge = lp > hi ? hi : lo;
    const Vec cur_xi = cur_node.xi, cur_t = cur_node.tangent;  // (nodes grows below)
    const Vec guess = cur_xi + (edge - l0) / (lp - l0) * (pred - cur_xi);
    const std::optional<Vec> at = tr_.SolveAt(edge * tr_.LambdaScale(), guess);
    // (Not a jump to another branch: within half the step of the predictor.)
    if (!at || (*at - guess).norm() > 0.5 * (pred - cur_xi).norm()) return false;
    for (double g : GridBetween(l0, edge)) {
      if (const std::optional<Vec> x = tr_.SolveAt(g * tr_.LambdaScale(), cur_xi + (g - l0) / (edge - l0) * (*at - cur_xi))) {
        nodes.push_back(MakeNode(*x, cur_t, true));
        grid_nodes_.back().push_back(*x);
      }
    }
    if (std::abs(nodes.back().xi[last] - edge) > 1e-12) nodes.push_back(MakeNode(*at, cur_t, true));
    grid_nodes_.back().push_back(*at);
    *end = "left the range at " + Name() + " = " + FormatValue(edge * tr_.LambdaScale());
    return true;
  }

  std::vector<double> GridBetween(double l0, double l1) const {
    std::vector<double> out;
    const double from = opt_.grid.from / tr_.LambdaScale(), step = opt_.grid.step / tr_.LambdaScale();
    // Within the grid's range (a value outside has no grid node; clamping
    // also keeps the index conversions below in range).
    const double lo = std::max(std::min(l0, l1), from), hi = std::min(std::max(l0, l1), opt_.grid.to / tr_.LambdaScale());
    if (!(lo <= hi)) return out;
    const long k0 = static_cast<long>(std::ceil((lo - from) / step - 1e-9));
    const long k1 = static_cast<long>(std::floor((hi - from) / step + 1e-9));
    for (long k = std::max(0L, k0); k <= k1 && k < opt_.grid.Count(); ++k) {
      const double g = from + k * step;
      if (g > lo && g < hi) out.push_back(g);
    }
    if (l1 < l0) std::reverse(out.begin(), out.end());
    return out;
  }

  void Record(SpecialKind kind, int branch, const ForcedOrbit& o, double parameter) {
    curve_.points.push_back({kind, branch, o, parameter});
  }
  void Record(SpecialKind kind, int branch, const Vec& xi) { Record(kind, branch, tr_.Orbit(xi), tr_.Lambda(xi)); }

  // Special points on consecutive nodes of a branch.
  void Special(const std::vector<Node>& nodes, int branch) {
    const int last = tr_.dim() - 1;
    for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
      const Node& a = nodes[k];
      const Node& b = nodes[k + 1];
      const SegmentLocator seg(tr_, a.xi, b.xi);
      auto not_located = [&](SpecialKind kind) {
        curve_.notes.push_back(ToString(kind) + " between " + Name() + " = " + FormatValue(tr_.Lambda(a.xi)) +
                               " and " + FormatValue(tr_.Lambda(b.xi)) + " on branch " + std::to_string(branch + 1) +
                               " could not be located");
      };
      auto locate = [&](SpecialKind kind, const std::function<double(const Vec&, const Vec&)>& test) {
        if (const std::optional<Vec> xi = seg.Root(test)) {
          Record(kind, branch, *xi);
        } else {
          not_located(kind);
        }
      };
      if (a.tangent.size() > 0 && b.tangent.size() > 0 && (a.tangent[last] < 0.0) != (b.tangent[last] < 0.0)) {
        locate(SpecialKind::kFold, [&](const Vec&, const Vec& t) { return t[last]; });
      }
      if ((PeriodDoublingTest(a.orbit) < 0.0) != (PeriodDoublingTest(b.orbit) < 0.0)) {
        // (A multiplier through -1, not through a pole.)
        if (const std::optional<Vec> xi = seg.PeriodDoubling()) Record(SpecialKind::kPeriodDoubling, branch, *xi);
      }
      if (std::isfinite(a.orbit.max_interior_gap) && std::isfinite(b.orbit.max_interior_gap) &&
          (a.orbit.max_interior_gap < 0.0) != (b.orbit.max_interior_gap < 0.0)) {
        locate(SpecialKind::kGrazing, [&](const Vec& xi, const Vec&) { return tr_.Orbit(xi).max_interior_gap; });
      }
      const std::optional<double> ta = TorusTest(a.orbit), tb = TorusTest(b.orbit);
      if (ta && tb && (*ta < 0.0) != (*tb < 0.0) && ComplexPairs(a.orbit) == ComplexPairs(b.orbit)) {
        // Recorded only when the point has a complex pair on the unit circle
        // (1e-6: Brent's ~1e-12 in the parameter moves |mu| far less; a pair
        // that left the real axis or a pole inside the segment fails it).
        const std::optional<Vec> xi = seg.Root([&](const Vec& x, const Vec&) {
          return TorusTest(tr_.Orbit(x)).value_or(std::numeric_limits<double>::quiet_NaN());
        });
        const std::optional<ForcedOrbit> o = xi ? std::optional<ForcedOrbit>(tr_.Orbit(*xi)) : std::nullopt;
        bool on_circle = false;
        if (o && o->multipliers.allFinite()) {
          for (int i = 0; i < o->multipliers.size(); ++i) {
            const std::complex<double> mu = o->multipliers[i];
            on_circle = on_circle || (mu.imag() > 1e-6 && std::abs(std::abs(mu) - 1.0) <= 1e-6);
          }
        }
        if (on_circle) {
          Record(SpecialKind::kTorus, branch, *o, tr_.Lambda(*xi));
        } else {
          not_located(SpecialKind::kTorus);
        }
      }
      if ((a.orbit.min_impact_velocity < 0.0) != (b.orbit.min_impact_velocity < 0.0)) {
        locate(SpecialKind::kZeroVelocity,
               [&](const Vec& xi, const Vec&) { return tr_.Orbit(xi).min_impact_velocity; });
      }
    }
    // Peaks: the energy's local maxima on admissible stretches.
    for (std::size_t k = 1; k + 1 < nodes.size(); ++k) {
      const ForcedOrbit &p = nodes[k - 1].orbit, &c = nodes[k].orbit, &q = nodes[k + 1].orbit;
      if (!(p.admissible && c.admissible && q.admissible && c.energy > p.energy && c.energy > q.energy)) continue;
      const SegmentLocator seg(tr_, nodes[k - 1].xi, nodes[k + 1].xi);
      const Vec chord = nodes[k + 1].xi - nodes[k - 1].xi;
      const double mid = (nodes[k].xi - nodes[k - 1].xi).dot(chord) / chord.squaredNorm();
      auto minus_energy = [&](double sigma) {
        const std::optional<Vec> xi = seg.At(sigma);
        return xi ? -tr_.Orbit(*xi).energy : std::numeric_limits<double>::quiet_NaN();
      };
      const double sigma = MinimizeOn(minus_energy, 0.0, mid, 1.0);
      if (const std::optional<Vec> xi = seg.At(sigma)) Record(SpecialKind::kPeak, branch, *xi);
    }
  }

  // m = 0: the closed-form linear response at every grid value, with its
  // grazing points and peaks located in lambda.
  void Linear(const std::vector<double>& grid) {
    ResponseBranch branch;
    auto at = [&](double l) {
      const std::optional<ForcedOrbit> o = axis_.Linear(l);
      NSMODAL_CHECK(o.has_value());  // (the grid's values: the range's ends are checked)
      return *o;
    };
    for (double l : grid) {
      branch.points.push_back(at(l));
      branch.parameter.push_back(l);
    }
    branch.end = "the grid";
    const std::vector<ForcedOrbit>& pts = branch.points;
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      if ((pts[k].max_interior_gap < 0.0) != (pts[k + 1].max_interior_gap < 0.0)) {
        const double l = PolishRoot([&](double x) { return at(x).max_interior_gap; }, grid[k], grid[k + 1]);
        Record(SpecialKind::kGrazing, 0, at(l), l);
      }
    }
    for (std::size_t k = 1; k + 1 < pts.size(); ++k) {
      if (pts[k].admissible && pts[k].energy > pts[k - 1].energy && pts[k].energy > pts[k + 1].energy) {
        const double l = MinimizeOn([&](double x) { return -at(x).energy; }, grid[k - 1], grid[k], grid[k + 1]);
        Record(SpecialKind::kPeak, 0, at(l), l);
      }
    }
    curve_.branches.push_back(std::move(branch));
  }

  const ResponseOptions& opt_;
  ResponseAxis axis_;
  Tracer tr_;
  ResponseCurve curve_;
  std::vector<std::vector<Vec>> grid_nodes_;  // per branch, its nodes at grid values
};

}  // namespace

Model ConservativeTwin(const Model& model) {
  Model twin = model;
  twin.source.reset();  // (edited below: its keys are no longer the model's)
  twin.damping.resize(0, 0);
  twin.forcing = Forcing{};
  for (Contact& c : twin.contacts) c.restitution = AnalysisBasis::kRestitution;
  return twin;
}

namespace {

// A backbone of two different contacts struck once each (else one contact's).
bool TwoContactBackbone(const std::vector<int>& sequence) {
  return sequence.size() == 2 && sequence[0] != sequence[1];
}

// The symmetric member of the (a, b) family at period T: t2 = T / 2.
bool Symmetric(const Orbit& o) { return o.times.size() == 1 && std::abs(o.times[0] - 0.5 * o.period) <= 1e-9 * o.period; }

}  // namespace

Sweep BackboneSweep(const Model& model, double w_from, double w_to, long points, const SweepOptions& options,
                    const std::vector<int>& sequence) {
  if (!(w_from > 0.0) || !(w_to > w_from) || !std::isfinite(w_to) || points < 2) {
    throw InputError("frequency", "the backbone needs 0 < from < to and at least 2 points, got " +
                                      FormatValue(w_from) + " to " + FormatValue(w_to));
  }
  const AnalysisBasis b(ConservativeTwin(model));
  PeriodGrid grid{2.0 * M_PI / w_to, 2.0 * M_PI / w_from, 0.0};
  grid.step = (grid.to - grid.from) / static_cast<double>(points - 1);
  SweepOptions on_contact = options;
  if (!TwoContactBackbone(sequence)) {
    on_contact.sequence = {sequence.empty() ? 0 : sequence.front()};
    return ComputeSweep(b, grid, 1, on_contact);
  }
  on_contact.sequence = sequence;
  Sweep sweep = ComputeSweep(b, grid, 2, on_contact);
  for (std::vector<OrbitRecord>& orbits : sweep.at) {
    orbits.erase(std::remove_if(orbits.begin(), orbits.end(), [](const OrbitRecord& r) { return !Symmetric(r.orbit); }),
                 orbits.end());
  }
  return sweep;
}

std::optional<double> BackboneFrequency(const Model& model, const Sweep& backbone, double energy, double near,
                                        const std::vector<int>& sequence) {
  const AnalysisBasis b(ConservativeTwin(model));
  const bool two = TwoContactBackbone(sequence);
  const int first = sequence.empty() ? 0 : sequence.front();
  auto energy_at = [&](double period) {
    return two ? TwoImpactOrbitAt(b, 0.5 * period, period, {}, sequence[0], sequence[1]).energy
               : OneImpactOrbit(b, period, {}, first).energy;
  };
  std::optional<double> best;
  for (std::size_t k = 0; k + 1 < backbone.periods.size(); ++k) {
    if (backbone.at[k].empty() || backbone.at[k + 1].empty()) continue;
    const Orbit& p = backbone.at[k].front().orbit;
    const Orbit& q = backbone.at[k + 1].front().orbit;
    if (!p.admissible || !q.admissible || (p.energy < energy) == (q.energy < energy)) continue;
    const double t = PolishRoot([&](double period) { return energy_at(period) - energy; }, backbone.periods[k],
                                backbone.periods[k + 1]);
    const double w = 2.0 * M_PI / t;
    if (!best || std::abs(w - near) < std::abs(*best - near)) best = w;
  }
  return best;
}

namespace {

// The model and the response problem at both ends of a model parameter's
// range: an end that leaves the valid model throws WithParameter's error
// (the scene's field and the value: a negative mass, e > 1); one where the
// response cannot be posed (an undamped model at e = 1, a spring at 0 that
// frees a rigid-body mode) throws naming `range`. The model's own checks are
// intervals in each parameter; inside the range, a value where the problem
// cannot be posed ends the branch there (Tracer::Problem).
void CheckRangeEnds(const Model& model, const ResponseOptions& o, const std::string& range) {
  if (!model.forcing.HasHarmonic()) {
    throw InputError("forcing.amplitude", "is needed: a response follows the model's harmonic force");
  }
  const int rigid = RigidBodyModes(model.stiffness);
  for (const double v : {o.grid.from, o.grid.to}) {
    const Model m = WithParameter(model, *o.model_parameter, v);
    const std::string at = "at " + o.model_parameter->name + " = " + FormatValue(v) + ": ";
    if (RigidBodyModes(m.stiffness) != rigid) {
      throw InputError(range, at + "the model has " + std::to_string(RigidBodyModes(m.stiffness)) +
                                  " rigid-body modes, " + std::to_string(rigid) + " at the scene's value: a range "
                                  "on one side of that value");
    }
    if (o.impacts == 0) continue;  // (the linear response: posed wherever the model is valid)
    try {
      detail::MakeForcedProblem(m, o.impacts, o.sequence, o.periods, m.forcing.frequency,
                                m.ForceAmplitude().cwiseAbs().maxCoeff());
    } catch (const InputError& e) {
      throw InputError(range, at + e.what());
    }
  }
}

}  // namespace

ResponseCurve ComputeResponse(const Model& model, const ResponseOptions& options) {
  Validate(model);
  options.Validate();
  if (options.parameter == ResponseParameter::kModel) CheckRangeEnds(model, options, "range");
  // The longest response period of the request within what ForcedProblem
  // honours (1e5 shortest linear periods), checked once here rather than
  // failing midway.
  const double w_min = options.parameter == ResponseParameter::kFrequency ? options.grid.from
                       : options.parameter == ResponseParameter::kAmplitude ? options.fixed
                                                                           : model.forcing.frequency;
  const double shortest = MakeModalBasis(model).Periods().minCoeff();
  if (options.periods * 2.0 * M_PI / w_min > AnalysisBasis::kMaxPeriodRatio * shortest) {
    throw InputError("frequency",
                     "w = " + FormatValue(w_min) + " gives response periods beyond " +
                         FormatValue(AnalysisBasis::kMaxPeriodRatio) + " times the shortest linear period " +
                         FormatValue(shortest));
  }
  return Responder(model, options).Run();
}

namespace {

// The impacts of a request: m, or the sequence's contacts (which set m).
void SetImpacts(const Model& model, int impacts, const std::optional<std::string>& sequence, const FieldNames& names,
                ResponseOptions& o) {
  o.impacts = impacts;
  if (sequence) {
    o.sequence = ParseSequence(*sequence, static_cast<int>(model.contacts.size()), names("sequence"), kMaxResponseImpacts);
    const int m = static_cast<int>(o.sequence.size());
    CheckImpactsAgree(impacts, m, *sequence, names("impacts"), true);
    o.impacts = m;
  }
}

// "FROM:TO" or "FROM:TO:STEP" (numbers; STEP by default (TO - FROM) / 300).
PeriodGrid ParseRange(const std::string& text, const std::string& field) {
  std::vector<double> v;
  std::size_t start = 0;
  while (true) {
    const std::size_t colon = text.find(':', start);
    const std::string part = text.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
    std::size_t used = 0;
    double x = 0.0;
    // Plain decimal numbers only (stod would take " 1" and hex "0x1p-2").
    const bool plain = !part.empty() && part.find_first_not_of("0123456789.eE+-") == std::string::npos;
    try {
      if (plain) x = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (!plain || used != part.size()) {
      throw InputError(field, "must be FROM:TO or FROM:TO:STEP (numbers), got '" + text + "'");
    }
    v.push_back(x);
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  if (v.size() != 2 && v.size() != 3) throw InputError(field, "must be FROM:TO or FROM:TO:STEP, got '" + text + "'");
  return {v[0], v[1], v.size() == 3 ? v[2] : (v[1] - v[0]) / 300.0};
}

}  // namespace

ResponseRequest MakeResponseRequest(const Model& model, ResponseParameter swept, const PeriodGrid& grid,
                                    std::vector<double> levels, int impacts, int periods, const FieldNames& names,
                                    const std::optional<std::string>& sequence) {
  if (levels.empty()) {
    const Eigen::VectorXd& f = model.forcing.amplitude;
    levels.push_back(swept == ResponseParameter::kFrequency ? (f.size() > 0 ? f.cwiseAbs().maxCoeff() : 0.0)
                                                            : model.forcing.frequency);
  }
  ResponseRequest r;
  SetImpacts(model, impacts, sequence, names, r.options);
  r.options.periods = periods;
  r.options.parameter = swept;
  r.options.grid = grid;
  r.options.fixed = levels.front();
  r.levels = std::move(levels);
  r.options.Validate(names);
  return r;
}

ResponseRequest MakeContinuationRequest(const Model& model, const std::string& parameter, const std::string& range,
                                        int impacts, int periods, const FieldNames& names,
                                        const std::optional<std::string>& sequence) {
  return MakeContinuationRequest(model, ParseModelParameter(model, parameter, names("parameter")),
                                 ParseRange(range, names("range")), impacts, periods, names, sequence);
}

PeriodGrid ParseParameterRange(const std::string& text, const std::string& field) { return ParseRange(text, field); }

void CheckParameterRange(const PeriodGrid& grid, const std::string& field) {
  if (!std::isfinite(grid.from) || !std::isfinite(grid.to) || !std::isfinite(grid.step) || !(grid.to > grid.from) ||
      !(grid.step > 0.0)) {
    throw InputError(field, "must be FROM:TO[:STEP] with TO > FROM and STEP > 0, all finite, got " +
                                FormatValue(grid.from) + ":" + FormatValue(grid.to) + ":" + FormatValue(grid.step));
  }
  if ((grid.to - grid.from) / grid.step >= static_cast<double>(PeriodGrid::kMaxPeriods)) {
    throw InputError(field, "asks for " + FormatValue(std::floor((grid.to - grid.from) / grid.step) + 1) +
                                " values; at most " + std::to_string(PeriodGrid::kMaxPeriods));
  }
}

ResponseRequest MakeContinuationRequest(const Model& model, const ModelParameter& p, const PeriodGrid& grid,
                                        int impacts, int periods, const FieldNames& names,
                                        const std::optional<std::string>& sequence) {
  if (!model.forcing.HasHarmonic()) {
    throw InputError("forcing.amplitude", "is needed: a continuation follows a forced response (the scene's "
                                          "[forcing] amplitude and frequency)");
  }
  if (p.kind == ModelParameter::Kind::kFrequency || p.kind == ModelParameter::Kind::kAmplitude) {
    // As `response` follows them, the other held at the model's value.
    FieldNames as_range = names;
    as_range.Set("frequency", names("range")).Set("amplitude", names("range"));
    return MakeResponseRequest(model,
                               p.kind == ModelParameter::Kind::kFrequency ? ResponseParameter::kFrequency
                                                                          : ResponseParameter::kAmplitude,
                               grid, {}, impacts, periods, as_range, sequence);
  }
  ResponseRequest r;
  SetImpacts(model, impacts, sequence, names, r.options);
  r.options.periods = periods;
  r.options.parameter = ResponseParameter::kModel;
  r.options.model_parameter = p;
  r.options.grid = grid;
  r.levels = {0.0};  // (one curve: `fixed` is unused)
  r.options.Validate(names);
  CheckRangeEnds(model, r.options, names("range"));  // (before any work or file)
  return r;
}

ResponseLevels ComputeResponseLevels(const Model& model, const ResponseOptions& options,
                                     const std::vector<double>& levels,
                                     const std::function<std::function<void(long, long)>(double)>& progress,
                                     const std::function<void(const ResponseCurve&, int)>& on_curve) {
  ResponseLevels out;
  for (double level : levels) {
    ResponseOptions opt = options;
    opt.fixed = level;
    if (progress) opt.progress = progress(level);
    const ResponseCurve curve = ComputeResponse(model, opt);
    for (std::size_t b = 0; b < curve.branches.size(); ++b) {
      const ResponseBranch& branch = curve.branches[b];
      for (std::size_t k = 0; k < branch.points.size(); ++k) {
        out.rows.push_back({out.branches + static_cast<int>(b) + 1, branch.points[k], branch.parameter[k]});
      }
      out.ends.push_back(curve.branches[b].end);
    }
    for (SpecialPoint p : curve.points) {
      p.branch += out.branches;
      out.points.push_back(p);
    }
    out.notes.insert(out.notes.end(), curve.notes.begin(), curve.notes.end());
    if (on_curve) on_curve(curve, out.branches);
    out.branches += static_cast<int>(curve.branches.size());
  }
  return out;
}

std::optional<std::string> NoBackbone(const Model& model, const ResponseOptions& options) {
  const std::vector<int>& seq = options.sequence;
  bool one_contact = true;
  for (int c : seq) one_contact = one_contact && c == seq.front();
  if (!one_contact && !TwoContactBackbone(seq)) {
    return "the response's sequence is neither on one contact nor two contacts once each: compare it with that "
           "sequence's free orbits (nsmodal orbits --sequence, 1 or 2 impacts)";
  }
  if (RigidBodyModes(model.stiffness) > 0) {
    if (!TwoContactBackbone(seq)) {
      return "the model has a rigid-body mode: its conservative twin has no one-impact mode to follow (a "
             "backbone needs two contacts struck once each, e.g. --sequence 1,2)";
    }
    try {
      CheckTwoImpactSequence(AnalysisBasis(ConservativeTwin(model)), seq[0], seq[1]);
    } catch (const InputError& e) {
      return std::string("the conservative twin has no orbits of the sequence: ") + e.what();
    }
  }
  return std::nullopt;
}

BackboneMatch MatchBackbone(const Model& model, const ResponseOptions& options, const std::vector<SpecialPoint>& points,
                            const std::function<void(long, long)>& progress) {
  NSMODAL_CHECK(!NoBackbone(model, options));
  SweepOptions sweep;
  sweep.stability = StabilityPolicy::kAdmissible;
  sweep.progress = progress;
  const double n = options.periods;
  BackboneMatch out{BackboneSweep(model, options.grid.from / n, options.grid.to / n, 2000, sweep, options.sequence),
                    {}};
  for (const SpecialPoint& p : points) {
    // The response's own frequency 2 pi / P, P = n 2 pi / w.
    out.mode_frequency.push_back(p.kind == SpecialKind::kPeak ? BackboneFrequency(model, out.backbone, p.orbit.energy,
                                                                                  p.orbit.frequency / n,
                                                                                  options.sequence)
                                                              : std::nullopt);
  }
  return out;
}

}  // namespace nsmodal
