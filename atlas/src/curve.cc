#include "nsmodal/curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <utility>

#include "nsmodal/check.h"
#include "nsmodal/error.h"
#include "nsmodal/response.h"
#include "nsmodal/stop.h"
#include "tracer.h"

namespace nsmodal {

std::string ToString(CurveKind kind) {
  switch (kind) {
    case CurveKind::kFold: return "fold";
    case CurveKind::kPeriodDoubling: return "period-doubling";
    case CurveKind::kGrazing: return "grazing";
  }
  return "?";
}

namespace {

using detail::Condition;
using detail::SegmentLocator;
using detail::Tracer;
using detail::Vec;

Condition ConditionOf(CurveKind k) {
  switch (k) {
    case CurveKind::kFold: return Condition::kFold;
    case CurveKind::kPeriodDoubling: return Condition::kPeriodDoubling;
    case CurveKind::kGrazing: return Condition::kGrazing;
  }
  return Condition::kNone;
}

SpecialKind SpecialOf(CurveKind k) {
  switch (k) {
    case CurveKind::kFold: return SpecialKind::kFold;
    case CurveKind::kPeriodDoubling: return SpecialKind::kPeriodDoubling;
    case CurveKind::kGrazing: return SpecialKind::kGrazing;
  }
  return SpecialKind::kFold;
}

// The model at (lambda_1, lambda_2); nullopt where it leaves the valid model.
std::optional<Model> ModelAt(const Model& model, const CurveOptions& o, const Vec& l) {
  try {
    return WithParameter(WithParameter(model, o.first, l[0]), o.second, l[1]);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

detail::TracerSetup Setup(const Model& model, const CurveOptions& o) {
  detail::TracerSetup s;
  s.impacts = o.impacts;
  s.unknowns = o.impacts == 0 ? 0 : o.impacts + RigidBodyModes(model.stiffness);
  s.problem = [&model, &o, k = s.unknowns](const Vec& l) -> std::unique_ptr<ForcedProblem> {
    const std::optional<Model> m = ModelAt(model, o, l);
    if (!m) return nullptr;
    return detail::PosedProblem(*m, o.impacts, o.sequence, o.periods, m->forcing.frequency,
                                m->ForceAmplitude().cwiseAbs().maxCoeff(), k);
  };
  s.linear = [&model, &o](const Vec& l) -> std::optional<ForcedOrbit> {
    const std::optional<Model> m = ModelAt(model, o, l);
    if (!m) return std::nullopt;
    return LinearResponse(*m, m->forcing.frequency, m->ForceAmplitude().cwiseAbs().maxCoeff());
  };
  Vec mid(2), width(2);
  mid << 0.5 * (o.first_range.from + o.first_range.to), 0.5 * (o.second_range.from + o.second_range.to);
  width << o.first_range.to - o.first_range.from, o.second_range.to - o.second_range.from;
  const std::optional<Model> centre = ModelAt(model, o, mid);
  s.period_scale = o.periods * 2.0 * M_PI / (centre ? centre->forcing.frequency : model.forcing.frequency);
  s.lambda_scale = width;
  s.gap_scale = LeastGapStruck(model, o.sequence);
  s.one_sided = true;
  s.condition = ConditionOf(o.follow);
  if (o.follow == CurveKind::kFold) {
    // det dH/du carries the round-off of its differences (~1e-11): Newton
    // stops there.
    s.step_tol = 1e-10;
    s.condition_tol = 1e-9;
  }
  return s;
}

struct CurveNode {
  Vec xi, tangent;
  ForcedOrbit orbit;
};

class CurveFollower {
 public:
  CurveFollower(const Model& model, const CurveOptions& opt) : model_(model), opt_(opt), tr_(Setup(model, opt)) {
    h_max_ = std::min(opt.first_range.step / tr_.LambdaScale(0), opt.second_range.step / tr_.LambdaScale(1));
  }

  CurveSet Run() {
    // The seed lines: the first parameter's continuation at `seeds` values
    // of the second, then the second's at `seeds` values of the first.
    const int seeds = opt_.seeds, lines = 2 * seeds;
    for (int line = 0; line < lines; ++line) {
      ThrowIfStopRequested();
      if (opt_.progress) opt_.progress(line, lines);
      const int held = line < seeds ? 1 : 0;  // the parameter held on the line
      const PeriodGrid& r = held == 1 ? opt_.second_range : opt_.first_range;
      const int s = line % seeds;
      const double v = seeds == 1 ? 0.5 * (r.from + r.to)
                       : s == seeds - 1 ? r.to
                                        : r.from + (r.to - r.from) * s / (seeds - 1);
      for (const Vec& start : Starts(held, v)) {
        if (Covered(start)) continue;
        if (set_.curves >= opt_.max_curves) {
          set_.notes.push_back("curve limit (" + std::to_string(opt_.max_curves) + ") reached; further starts not "
                               "followed");
          return set_;
        }
        Trace(start);
      }
    }
    if (opt_.progress) opt_.progress(lines, lines);
    return set_;
  }

 private:
  std::string Where(const Vec& xi) const {
    return opt_.first.name + " = " + FormatValue(tr_.Lambda(xi, 0)) + ", " + opt_.second.name + " = " +
           FormatValue(tr_.Lambda(xi, 1));
  }

  // The special points of the followed kind on the response followed in one
  // parameter with the other (`held`: 0 the first, 1 the second) at v,
  // corrected onto the extended system (v held).
  std::vector<Vec> Starts(int held, double v) {
    std::vector<Vec> out;
    const ModelParameter& fixed = held == 1 ? opt_.second : opt_.first;
    const ModelParameter& followed = held == 1 ? opt_.first : opt_.second;
    Model at;
    try {
      at = WithParameter(model_, fixed, v);
    } catch (const InputError& e) {
      set_.notes.push_back("no model at " + fixed.name + " = " + FormatValue(v) + ": " + e.what());
      return out;
    }
    ResponseCurve curve;
    try {
      const std::optional<std::string> seq =
          opt_.sequence.empty() ? std::nullopt : std::optional<std::string>(SequenceText());
      const ResponseRequest r =
          MakeContinuationRequest(at, followed, held == 1 ? opt_.first_range : opt_.second_range, opt_.impacts,
                                  opt_.periods, FieldNames(), seq);
      ResponseOptions ro = r.options;
      ro.fixed = r.levels.front();
      curve = ComputeResponse(at, ro);
    } catch (const InputError& e) {
      set_.notes.push_back("no response at " + fixed.name + " = " + FormatValue(v) + ": " + e.what());
      return out;
    }
    for (const SpecialPoint& p : curve.points) {
      if (p.kind != SpecialOf(opt_.follow)) continue;
      Vec l(2);
      l[held] = v;
      l[1 - held] = p.parameter;
      const Vec guess = tr_.Xi(opt_.impacts > 0 ? p.orbit.u : Vec(0), l);
      const Vec normal = Vec::Unit(tr_.dim(), tr_.dim() - 2 + held);
      if (const std::optional<Vec> xi = tr_.Correct(guess, guess, normal)) {
        out.push_back(*xi);
      } else {
        set_.notes.push_back(ToString(opt_.follow) + " at " + Where(guess) + " (a start) could not be solved on the "
                             "extended system");
      }
    }
    return out;
  }

  std::string SequenceText() const {
    std::string t;
    for (std::size_t i = 0; i < opt_.sequence.size(); ++i) t += (i ? "," : "") + std::to_string(opt_.sequence[i] + 1);
    return t;
  }

  // A start on a curve already traced: within a step of one of its points
  // (the phase modulo a forcing cycle).
  bool Covered(const Vec& xi) const {
    for (const Vec& other : traced_) {
      if (Distance(xi, other) <= h_max_) return true;
    }
    return false;
  }

  CurveNode MakeNode(const Vec& xi, const Vec& along) const {
    CurveNode n;
    n.xi = xi;
    Eigen::MatrixXd j;
    if (tr_.Jacobian(xi, j)) n.tangent = Tracer::Tangent(j, along);
    n.orbit = tr_.Orbit(xi);
    return n;
  }

  void Trace(const Vec& xi0) {
    const int index = set_.curves++;
    Vec along = Vec::Zero(tr_.dim());
    along[tr_.dim() - 2] = 1.0;  // (either way: the first parameter's increase)
    std::string end_fwd, end_back;
    std::vector<CurveNode> forward = Follow(xi0, along, &end_fwd, index);
    std::vector<CurveNode> backward;
    if (end_fwd != kClosed && forward.front().tangent.size() > 0) {
      backward = Follow(xi0, -forward.front().tangent, &end_back, index);
    } else {
      backward = {forward.front()};
    }
    std::vector<CurveNode> nodes(backward.rbegin(), backward.rend() - 1);
    for (CurveNode& n : nodes) n.tangent = -n.tangent;  // (along the nodes' order)
    nodes.insert(nodes.end(), forward.begin(), forward.end());
    set_.ends.push_back(end_fwd == kClosed ? end_fwd : "one way: " + end_back + "; the other: " + end_fwd);
    for (const CurveNode& n : nodes) {
      traced_.push_back(n.xi);
      traced_curve_.push_back(index);
    }
    Emit(nodes, index);
  }

  static constexpr const char* kClosed = "closed on itself";

  std::vector<CurveNode> Follow(const Vec& xi0, const Vec& dir, std::string* end, int index) {
    const double h_min = 1e-6 * h_max_;
    Vec lo(2), hi(2);
    lo << opt_.first_range.from / tr_.LambdaScale(0), opt_.second_range.from / tr_.LambdaScale(1);
    hi << opt_.first_range.to / tr_.LambdaScale(0), opt_.second_range.to / tr_.LambdaScale(1);
    const int p0 = tr_.dim() - 2;  // the first parameter's coordinate
    std::vector<CurveNode> nodes{MakeNode(xi0, dir)};
    if (nodes[0].tangent.size() == 0) {
      *end = "no tangent at the start (" + Where(xi0) + ")";
      return nodes;
    }
    double h = h_max_;
    int stalled = 0;      // consecutive steps below 1e-3 h_max
    bool away = false;    // the curve has gone 2 h_max from its start (a closure may be tested)
    // The edge of the window a step leaves by: the curve's point on it, and
    // the end (false: no point on the edge near the step).
    auto on_edge = [&](const CurveNode& cur, const Vec& to) {
      for (int i = 0; i < 2; ++i) {
        const double l1 = to[p0 + i], l0 = cur.xi[p0 + i];
        if ((l1 >= lo[i] - 1e-12 && l1 <= hi[i] + 1e-12) || l1 == l0) continue;
        const double edge = l1 > hi[i] ? hi[i] : lo[i];
        const Vec guess = cur.xi + (edge - l0) / (l1 - l0) * (to - cur.xi);
        const Vec cur_t = cur.tangent;
        std::optional<Vec> at = tr_.Correct(guess, guess, Vec::Unit(tr_.dim(), p0 + i));
        if (!at || (*at - guess).norm() > 0.5 * (to - cur.xi).norm()) return false;
        (*at)[p0 + i] = edge;
        // (A start on the edge is its own edge point: not repeated.)
        if (std::abs(cur.xi[p0 + i] - edge) > 1e-12) nodes.push_back(MakeNode(*at, cur_t));
        *end = "left the window at " + Where(nodes.back().xi);
        return true;
      }
      return false;
    };
    for (long step = 0;; ++step) {
      ThrowIfStopRequested();
      // A curve that only creeps on (its condition not smooth there: two
      // interior maxima exchanging, a maximum reaching an impact) ends.
      if (stalled > 40) {
        *end = "stalled at " + Where(nodes.back().xi) + " (the defining condition is not smooth there)";
        return nodes;
      }
      if (step >= opt_.max_steps) {
        *end = "step limit (" + std::to_string(opt_.max_steps) + ") reached";
        set_.notes.push_back("curve " + std::to_string(index + 1) + ": " + *end);
        return nodes;
      }
      const CurveNode& cur = nodes.back();
      const Vec pred = cur.xi + h * cur.tangent;
      const std::optional<Vec> next = tr_.Correct(pred, pred, cur.tangent);
      if (!Tracer::Accepted(cur.xi, cur.tangent, pred, next, h)) {
        // A predictor past the window where the corrector fails (the model
        // ends there too: e = 1, a damping ratio at 0): the edge's point.
        if (!next && on_edge(cur, pred)) return nodes;
        h *= 0.5;
        if (h < h_min) {
          *end = "lost at " + Where(cur.xi) + " (corrector failed: the point's condition degenerates, or a "
                 "parameter leaves the model)";
          return nodes;
        }
        continue;
      }
      if (on_edge(cur, *next)) return nodes;
      const Vec cur_t = cur.tangent;
      CurveNode node = MakeNode(*next, cur_t);
      if (node.tangent.size() == 0) {
        *end = "no tangent at " + Where(*next);
        return nodes;
      }
      nodes.push_back(std::move(node));
      stalled = h < 1e-3 * h_max_ ? stalled + 1 : 0;
      const Vec& here = nodes.back().xi;
      away = away || Distance(here, xi0) > 2.0 * h_max_;
      if (away && Distance(here, xi0) < 0.5 * h_max_) {
        *end = kClosed;
        return nodes;
      }
      // A curve traced already (lost before, met again from another start).
      for (std::size_t k = 0; k < traced_.size(); ++k) {
        if (Distance(here, traced_[k]) <= 0.5 * h_max_) {
          *end = "joined curve " + std::to_string(traced_curve_[k] + 1) + " at " + Where(here);
          return nodes;
        }
      }
      if (step > 0 && h < h_max_) h = std::min(h_max_, 1.5 * h);
    }
  }

  // The distance of two points (the phase modulo a forcing cycle).
  double Distance(const Vec& a, const Vec& b) const {
    Vec d = a - b;
    if (tr_.unknowns() > 0) d[0] = std::remainder(d[0], 1.0);
    return d.norm();
  }

  // The rows of a curve: its points, and between two of them the points
  // where it meets another special point's curve.
  void Emit(const std::vector<CurveNode>& nodes, int index) {
    const std::string followed = ToString(opt_.follow);
    const int p0 = tr_.dim() - 2;
    // (A value on the window's edge written as the range's end, not its
    // scaled copy an ulp off.)
    auto snap = [](double v, const PeriodGrid& r) {
      const double ulps = 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(r.from), std::abs(r.to));
      return std::abs(v - r.from) <= ulps ? r.from : std::abs(v - r.to) <= ulps ? r.to : v;
    };
    auto row = [&](const std::string& kind, const Vec& xi, const ForcedOrbit& orbit) {
      set_.rows.push_back({index, kind, snap(tr_.Lambda(xi, 0), opt_.first_range),
                           snap(tr_.Lambda(xi, 1), opt_.second_range), orbit,
                           tr_.ConditionAt(tr_.condition(), xi, orbit)});
    };
    auto det = [&](const Vec& xi) {
      return tr_.ConditionAt(Condition::kFold, xi).value_or(std::numeric_limits<double>::quiet_NaN());
    };
    auto gap = [](const ForcedOrbit& o) { return o.max_interior_gap; };
    std::vector<double> dets;
    if (opt_.follow != CurveKind::kFold && opt_.impacts > 0) {
      for (const CurveNode& n : nodes) dets.push_back(det(n.xi));
    }
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      row(followed, nodes[k].xi, nodes[k].orbit);
      if (k + 1 == nodes.size()) break;
      const CurveNode &a = nodes[k], &b = nodes[k + 1];
      const SegmentLocator seg(tr_, a.xi, b.xi);
      std::vector<std::pair<double, std::pair<std::string, Vec>>> met;  // (position along the chord, point)
      auto locate = [&](const std::string& kind, const std::function<double(const Vec&, const Vec&)>& test) {
        if (const std::optional<Vec> xi = seg.Root(test)) {
          const Vec chord = b.xi - a.xi;
          met.push_back({(*xi - a.xi).dot(chord) / chord.squaredNorm(), {kind, *xi}});
        } else {
          set_.notes.push_back(kind + " between " + Where(a.xi) + " and " + Where(b.xi) + " on curve " +
                               std::to_string(index + 1) + " could not be located");
        }
      };
      if (opt_.follow == CurveKind::kFold && a.tangent.size() > 0 && b.tangent.size() > 0) {
        const Vec pa = a.tangent.segment(p0, 2), pb = b.tangent.segment(p0, 2);
        if (pa.dot(pb) < 0.0) {
          locate("cusp", [&](const Vec&, const Vec& t) { return t.segment(p0, 2).dot(pa); });
        }
      }
      if (!dets.empty() && std::isfinite(dets[k]) && std::isfinite(dets[k + 1]) && (dets[k] < 0.0) != (dets[k + 1] < 0.0)) {
        locate("fold", [&](const Vec& xi, const Vec&) { return det(xi); });
      }
      if (opt_.follow != CurveKind::kPeriodDoubling && opt_.impacts > 0 &&
          (detail::PeriodDoublingTest(a.orbit) < 0.0) != (detail::PeriodDoublingTest(b.orbit) < 0.0)) {
        // (Through -1, not through a pole.)
        if (const std::optional<Vec> xi = seg.PeriodDoubling()) {
          const Vec chord = b.xi - a.xi;
          met.push_back({(*xi - a.xi).dot(chord) / chord.squaredNorm(), {"period-doubling", *xi}});
        }
      }
      if (opt_.follow != CurveKind::kGrazing && std::isfinite(gap(a.orbit)) && std::isfinite(gap(b.orbit)) &&
          (gap(a.orbit) < 0.0) != (gap(b.orbit) < 0.0)) {
        locate("grazing", [&](const Vec& xi, const Vec&) { return gap(tr_.Orbit(xi)); });
      }
      if (opt_.impacts > 0 && (a.orbit.min_impact_velocity < 0.0) != (b.orbit.min_impact_velocity < 0.0)) {
        locate("zero-velocity", [&](const Vec& xi, const Vec&) { return tr_.Orbit(xi).min_impact_velocity; });
      }
      std::sort(met.begin(), met.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      for (const auto& m : met) row(m.second.first, m.second.second, tr_.Orbit(m.second.second));
    }
  }

  const Model& model_;
  const CurveOptions& opt_;
  Tracer tr_;
  double h_max_ = 1.0;
  CurveSet set_;
  std::vector<Vec> traced_;       // every traced curve's points
  std::vector<int> traced_curve_; // and the curve of each
};

}  // namespace

CurveSet FollowCurves(const Model& model, const CurveOptions& options) {
  Validate(model);
  NSMODAL_CHECK(options.seeds >= 1 && options.max_steps >= 1 && options.max_curves >= 1);
  return CurveFollower(model, options).Run();
}

std::optional<CurvePoint> CurvePointAt(const Model& model, const CurveOptions& options, const CurvePoint& near,
                                       double second) {
  const Tracer tr(Setup(model, options));
  Vec l(2);
  l << near.first, second;
  const Vec guess = tr.Xi(options.impacts > 0 ? near.orbit.u : Vec(0), l);
  const std::optional<Vec> xi = tr.Correct(guess, guess, Vec::Unit(tr.dim(), tr.dim() - 1));
  if (!xi) return std::nullopt;
  const ForcedOrbit o = tr.Orbit(*xi);
  return CurvePoint{near.curve, ToString(options.follow), tr.Lambda(*xi, 0), tr.Lambda(*xi, 1), o,
                    tr.ConditionAt(tr.condition(), *xi, o)};
}

CurveOptions MakeCurveRequest(const Model& model, const std::string& parameter, const std::string& range,
                              const std::string& second, const std::string& second_range, const std::string& follow,
                              int impacts, int periods, const FieldNames& names,
                              const std::optional<std::string>& sequence) {
  CurveOptions o;
  if (follow == "fold") {
    o.follow = CurveKind::kFold;
  } else if (follow == "period-doubling") {
    o.follow = CurveKind::kPeriodDoubling;
  } else if (follow == "grazing") {
    o.follow = CurveKind::kGrazing;
  } else {
    throw InputError(names("follow"), "must be fold, period-doubling or grazing, got '" + follow + "'");
  }
  o.first = ParseModelParameter(model, parameter, names("parameter"));
  o.second = ParseModelParameter(model, second, names("second"));
  if (o.first.kind == o.second.kind && o.first.index == o.second.index) {
    throw InputError(names("second"), "must differ from the first parameter, got '" + second + "' beside '" +
                                          parameter + "'");
  }
  o.first_range = ParseParameterRange(range, names("range"));
  o.second_range = ParseParameterRange(second_range, names("second_range"));
  CheckParameterRange(o.first_range, names("range"));
  CheckParameterRange(o.second_range, names("second_range"));
  // Each range checked at both ends of the other (the window's corners: a
  // valid model on which the response can be posed), as `continue` checks
  // one range.
  FieldNames as_second = names;
  as_second.Set("range", names("second_range")).Set("parameter", names("second"));
  // A corner that leaves the valid model names the range and the value.
  auto at = [&](const ModelParameter& p, double v, const std::string& field) {
    Model m;
    try {
      m = WithParameter(model, p, v);
    } catch (const InputError& e) {
      throw InputError(field, "at " + p.name + " = " + FormatValue(v) + ": " + e.what());
    }
    if (!m.forcing.HasHarmonic()) {
      throw InputError(field, "at " + p.name + " = " + FormatValue(v) + ": the model has no harmonic force left");
    }
    return m;
  };
  ResponseRequest first_request;
  for (const double v : {o.second_range.from, o.second_range.to}) {
    first_request = MakeContinuationRequest(at(o.second, v, names("second_range")), o.first, o.first_range, impacts,
                                            periods, names, sequence);
  }
  for (const double v : {o.first_range.from, o.first_range.to}) {
    MakeContinuationRequest(at(o.first, v, names("range")), o.second, o.second_range, impacts, periods, as_second,
                            sequence);
  }
  o.impacts = first_request.options.impacts;
  o.sequence = first_request.options.sequence;
  o.periods = periods;
  if (o.impacts == 0 && o.follow != CurveKind::kGrazing) {
    throw InputError(names("follow"), "the linear response (impacts 0) has no " + ToString(o.follow) +
                                          ": follow grazing, or give impacts >= 1");
  }
  return o;
}

}  // namespace nsmodal
