// Codimension-two curves (curve.h, issue 26): a special point followed in two
// parameters, checked against a closed form, against the special points of
// one-parameter continuations, and against the curves of another kind.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>

#include "forced_fixtures.h"
#include "nsmodal/curve.h"
#include "nsmodal/error.h"
#include "nsmodal/family_parameter.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/scene.h"
#include "nsmodal/response.h"

namespace nsmodal {
namespace {

using testing::ForcedScene;

// m x'' + c x' + k x = a cos(w t) against a wall at x = d: m = k = 1,
// damping ratio zeta.
Model OneDof(double zeta, double d) {
  Model m = MakeChain({1.0}, {1.0}, 0, d, 0.8);
  m.damping = Eigen::MatrixXd::Constant(1, 1, 2.0 * zeta);
  m.forcing.amplitude = Eigen::VectorXd::Constant(1, 0.3);
  m.forcing.frequency = 0.8;
  return m;
}

std::vector<const CurvePoint*> Rows(const CurveSet& s, const std::string& kind) {
  std::vector<const CurvePoint*> out;
  for (const CurvePoint& p : s.rows) {
    if (p.kind == kind) out.push_back(&p);
  }
  return out;
}

TEST(Curve, TheLinearGrazingCurveOfAnImpactOscillatorIsItsClosedForm) {
  // The non-impacting response touches the wall where its amplitude
  // a / sqrt((1 - w^2)^2 + (2 zeta w)^2) equals d.
  const double zeta = 0.05, d = 0.7;
  const Model m = OneDof(zeta, d);
  const CurveOptions o = MakeCurveRequest(m, "frequency", "0.5:1.5", "amplitude", "0.01:2", "grazing", 0, 1);
  const CurveSet s = FollowCurves(m, o);
  ASSERT_EQ(s.curves, 1);
  const std::vector<const CurvePoint*> rows = Rows(s, "grazing");
  ASSERT_GT(rows.size(), 100u);
  double w_min = 1e300, w_max = 0.0;
  for (const CurvePoint* p : rows) {
    const double w = p->first;
    const double a = d * std::hypot(1.0 - w * w, 2.0 * zeta * w);
    // (1e-11 a: the condition holds to 1e-12 d, and |X| is proportional to a.)
    EXPECT_NEAR(p->second, a, 1e-11 * a) << "w = " << w;
    w_min = std::min(w_min, w);
    w_max = std::max(w_max, w);
  }
  // One curve across the whole window, ended on its edges.
  EXPECT_DOUBLE_EQ(w_min, 0.5);
  EXPECT_DOUBLE_EQ(w_max, 1.5);
}

TEST(Curve, TheFoldCurvePassesThroughTheFoldsOfTheFrequencyResponses) {
  const Model m = ForcedScene();
  const CurveOptions o = MakeCurveRequest(m, "frequency", "0.3:1.2", "amplitude", "0.05:1", "fold", 1, 1);
  const CurveSet s = FollowCurves(m, o);
  ASSERT_GE(s.curves, 2);
  int compared = 0;
  for (const double a : {0.2, 0.4, 0.6}) {
    ResponseOptions r;
    r.impacts = 1;
    r.grid = {0.3, 1.2, 0.003};
    r.fixed = a;
    Model at = m;
    at.forcing.amplitude *= a / 0.3;
    const ResponseCurve curve = ComputeResponse(at, r);
    for (const SpecialPoint& f : curve.points) {
      if (f.kind != SpecialKind::kFold) continue;
      // The curve's row nearest to the fold, then its point at amplitude a.
      const CurvePoint* near = nullptr;
      for (const CurvePoint* p : Rows(s, "fold")) {
        if (!near || std::hypot(p->first - f.parameter, p->second - a) <
                         std::hypot(near->first - f.parameter, near->second - a)) {
          near = p;
        }
      }
      ASSERT_NE(near, nullptr);
      ASSERT_LT(std::hypot(near->first - f.parameter, near->second - a), 0.01) << "no fold curve near w = " << f.parameter;
      const std::optional<CurvePoint> on = CurvePointAt(m, o, *near, a);
      ASSERT_TRUE(on.has_value());
      // (1e-8: response locates its folds to ~1e-12 in w by Brent on the
      // tangent; the curve's det dH/du holds to 1e-9, and a fold's w is
      // quadratic in the distance along the branch.)
      EXPECT_NEAR(on->first, f.parameter, 1e-8) << "a = " << a;
      ++compared;
    }
  }
  EXPECT_GE(compared, 3);
}

TEST(Curve, AFoldCurveAndAPeriodDoublingCurveMeetWhereEachSaysTheyDo) {
  const Model m = ForcedScene();
  const CurveSet folds =
      FollowCurves(m, MakeCurveRequest(m, "frequency", "0.45:0.6", "amplitude", "0.05:0.4", "fold", 1, 1));
  const CurveSet doublings =
      FollowCurves(m, MakeCurveRequest(m, "frequency", "0.45:0.6", "amplitude", "0.05:0.4", "period-doubling", 1, 1));
  const std::vector<const CurvePoint*> a = Rows(folds, "period-doubling"), b = Rows(doublings, "fold");
  ASSERT_GE(a.size(), 1u);
  ASSERT_EQ(a.size(), b.size());
  // Each meeting seen from either curve is one seen from the other.
  for (const auto& [from, to] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
    for (const CurvePoint* p : *from) {
      double best = 1e300;
      for (const CurvePoint* q : *to) best = std::min(best, std::hypot(p->first - q->first, p->second - q->second));
      // (1e-8: two independent locations, each Brent's ~1e-12 along a chord
      // of the other curve's test function, both test functions held to 1e-9.)
      EXPECT_LT(best, 1e-8) << "w = " << p->first << ", a = " << p->second;
    }
  }
}

TEST(Curve, ACurveThatReachesTheEndOfTheModelsDomainEndsOnIt) {
  // e = 1 ends the range and the model (e > 1 is no model): the fold curves
  // of a damped response end there, solved on it, not lost before it.
  const Model m = ForcedScene();
  const CurveSet s =
      FollowCurves(m, MakeCurveRequest(m, "restitution", "0.6:1", "frequency", "0.3:1.2", "fold", 1, 1));
  ASSERT_GE(s.curves, 1);
  int at_one = 0;
  for (const std::string& end : s.ends) EXPECT_EQ(end.find("lost"), std::string::npos) << end;
  for (const CurvePoint* p : Rows(s, "fold")) at_one += p->first == 1.0;
  EXPECT_GE(at_one, s.curves);
}

TEST(Curve, EveryPointHoldsItsDefiningCondition) {
  const Model m = ForcedScene();
  const CurveSet s =
      FollowCurves(m, MakeCurveRequest(m, "frequency", "0.45:0.8", "amplitude", "0.05:1", "grazing", 1, 1));
  ASSERT_GE(s.curves, 1);
  for (const CurvePoint* p : Rows(s, "grazing")) {
    ASSERT_TRUE(p->condition.has_value());
    // (1e-12 of the gap: the corrector's tolerance.)
    EXPECT_LE(std::abs(*p->condition), 1e-12);
    EXPECT_LE(p->orbit.residual, 1e-12);
  }
}

TEST(Curve, BadRequestsNameTheirField) {
  const Model m = ForcedScene();
  auto field = [&](const std::string& p, const std::string& r, const std::string& q, const std::string& qr,
                   const std::string& follow, int impacts) {
    try {
      MakeCurveRequest(m, p, r, q, qr, follow, impacts, 1);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(field("frequency", "0.3:1", "amplitude", "0.1:1", "cusp", 1), "follow");
  EXPECT_EQ(field("frequency", "0.3:1", "stiffness", "0.1:1", "fold", 1), "second");
  EXPECT_EQ(field("frequency", "0.3:1", "frequency", "0.1:1", "fold", 1), "second");
  EXPECT_EQ(field("frequency", "0.3:1", "amplitude", "1:0.1", "fold", 1), "second_range");
  EXPECT_EQ(field("frequency", "0.3:1", "restitution", "0.5:1.5", "fold", 1), "second_range");
  EXPECT_EQ(field("frequency", "0.3:1", "gap", "-1:1", "fold", 1), "second_range");
  EXPECT_EQ(field("frequency", "0.3:1", "amplitude", "0:1", "fold", 1), "second_range");
  EXPECT_EQ(field("frequency", "0:1", "amplitude", "0.1:1", "fold", 1), "range");
  EXPECT_EQ(field("masses[1]", "0.5:1", "amplitude", "0.1:1", "fold", 1), "parameter");  // (no keys to rebuild from)
  EXPECT_EQ(field("frequency", "0.3:1", "amplitude", "0.1:1", "fold", 0), "follow");
}

// The paper's chain as a scene (its keys: a spring or mass can be followed).
Model Paper(double gap = 1.0, double k2 = 2.0) {
  std::ostringstream scene;
  scene << std::setprecision(17) << "[system]\nmasses = [1.0, 1.0]\nsprings = [0.85, " << k2 << "]\ngap = " << gap
        << "\nrestitution = 1.0\n";
  return ParseScene(scene.str()).model;
}

TEST(FreeFamily, ItsTransitionsAtTheScenesStiffnessAreTodays) {
  const Model m = Paper();
  const PeriodGrid periods{2.0, 30.0, 0.01};
  const FamilyContinuation f = FollowFamily(m, ParseModelParameter(m, "springs[2]"), {2.0, 2.5, 0.25}, periods);
  const AnalysisBasis b(m);
  const std::vector<Transition> today = SweepTransitions(b, ComputeSweep(b, periods, 1));
  std::vector<const FamilyRow*> at_2;
  int bridges = 0;
  for (const FamilyRow& r : f.rows) {
    if (r.parameter == 2.0 && r.kind != "bridge") at_2.push_back(&r);
    bridges += r.parameter == 2.0 && r.kind == "bridge";
  }
  // The paper's bridge (T_G = 27.26, Figs. 13-15) among them.
  EXPECT_GE(bridges, 1);
  ASSERT_EQ(at_2.size(), today.size());
  ASSERT_GT(today.size(), 10u);
  for (std::size_t k = 0; k < today.size(); ++k) {
    // (The same model rebuilt from the same keys, the same computation: equal.)
    EXPECT_EQ(at_2[k]->period, today[k].period);
    EXPECT_EQ(at_2[k]->kind, ToString(today[k].kind));
  }
  // At k2 = 2.5 the modal transitions are k T_i of the stiffer chain's
  // linear periods, and a track holds one point per value.
  EXPECT_EQ(f.rows.back().parameter, 2.5);
  const Model stiffer = Paper(1.0, 2.5);
  const Eigen::VectorXd periods_25 = MakeModalBasis(stiffer).Periods();
  int modal = 0;
  std::map<std::pair<int, double>, int> per_track;
  for (const FamilyRow& r : f.rows) {
    ++per_track[{r.track, r.parameter}];
    if (r.parameter != 2.5 || r.kind != "modal") continue;
    double best = 1e300;
    for (int i = 0; i < periods_25.size(); ++i) {
      best = std::min(best, std::abs(r.period / periods_25[i] - std::round(r.period / periods_25[i])));
    }
    // (1e-12: ModalPeriods gives k T_i exactly, T_i to round-off.)
    EXPECT_LT(best, 1e-12) << "T = " << r.period;
    ++modal;
  }
  EXPECT_GE(modal, 2);
  for (const auto& [key, n] : per_track) EXPECT_EQ(n, 1) << "track " << key.first << " at k2 = " << key.second;
}

TEST(FreeFamily, TheGapScalesTheEnergyBySquaresAndMovesNoPeriod) {
  const Model m = Paper();
  const PeriodGrid periods{2.0, 20.0, 0.01};
  const FamilyContinuation f = FollowFamily(m, ParseModelParameter(m, "gap"), {1.0, 3.0, 1.0}, periods);
  EXPECT_TRUE(f.scaled);
  // Against the family computed at gap 3 directly (not rescaled).
  const AnalysisBasis b3(Paper(3.0));
  const std::vector<Transition> direct = SweepTransitions(b3, ComputeSweep(b3, periods, 1));
  std::vector<const FamilyRow*> at_3;
  for (const FamilyRow& r : f.rows) {
    if (r.parameter == 3.0 && r.kind != "bridge") at_3.push_back(&r);
  }
  ASSERT_EQ(at_3.size(), direct.size());
  for (std::size_t k = 0; k < direct.size(); ++k) {
    // (1e-13 relative: the roots of the same functions refined to ~1e-15,
    // the energies' quadratic forms in x scaled by d: round-off only.)
    EXPECT_NEAR(at_3[k]->period, direct[k].period, 1e-13 * direct[k].period);
    if (std::isfinite(direct[k].energy)) {
      EXPECT_NEAR(at_3[k]->energy, direct[k].energy, 1e-13 * direct[k].energy);
    }
  }
}

TEST(FreeFamily, ParametersThatDoNotChangeItAreRefused) {
  const Model m = Paper();
  for (const char* name : {"restitution"}) {
    try {
      FollowFamily(m, ParseModelParameter(m, name), {0.5, 1.0, 0.1}, {2.0, 10.0, 0.1});
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "parameter");
    }
  }
  try {
    FollowFamily(m, ParseModelParameter(m, "masses[1]"), {-1.0, 1.0, 0.5}, {2.0, 10.0, 0.1});
    ADD_FAILURE() << "a negative mass accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "range");  // (PeriodGrid: from > 0)
  }
}

}  // namespace
}  // namespace nsmodal
