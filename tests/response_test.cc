// Frequency- and amplitude-response curves (response.h): continuation
// through folds, special points checked against independent properties.
#include <gtest/gtest.h>

#include <cmath>

#include "forced_fixtures.h"
#include "nsmodal/error.h"
#include "nsmodal/parameter.h"
#include "nsmodal/response.h"
#include "nsmodal/scene.h"
#include "nsmodal/two_impact.h"

namespace nsmodal {
namespace {

Model Forced() { return testing::ForcedScene(); }

ResponseCurve Curve(int impacts, double from, double to, double step, double amplitude = 0.3) {
  ResponseOptions o;
  o.impacts = impacts;
  o.grid = {from, to, step};
  o.fixed = amplitude;
  return ComputeResponse(Forced(), o);
}

// The distance in w from w to the nearest of the points.
double Nearest(const std::vector<const SpecialPoint*>& points, double w) {
  double best = 1e300;
  for (const SpecialPoint* p : points) best = std::min(best, std::abs(p->orbit.frequency - w));
  return best;
}

std::vector<const SpecialPoint*> Of(const ResponseCurve& c, SpecialKind kind) {
  std::vector<const SpecialPoint*> out;
  for (const SpecialPoint& p : c.points) {
    if (p.kind == kind) out.push_back(&p);
  }
  return out;
}

// The impacting family is born where the linear response grazes the wall:
// the (1,1) orbit's zero-velocity impact and the linear response's grazing
// are the same point, found by two independent computations (continuation
// and Brent on the closed-form max x_c(w) = d).
TEST(Response, TheImpactingFamilyIsBornAtTheLinearGrazing) {
  const ResponseCurve linear = Curve(0, 0.4, 1.0, 0.01);
  const ResponseCurve impacting = Curve(1, 0.4, 1.0, 0.01);
  const auto grazings = Of(linear, SpecialKind::kGrazing);
  const auto zero = Of(impacting, SpecialKind::kZeroVelocity);
  ASSERT_EQ(grazings.size(), 2u);
  ASSERT_EQ(zero.size(), 2u);
  for (const SpecialPoint* g : grazings) {
    // Both located by Brent to ~1e-15 relative; the zero-velocity test
    // function's conditioning at the branch end costs a few digits: 1e-9.
    EXPECT_LT(Nearest(zero, g->orbit.frequency), 1e-9) << "grazing at w = " << g->orbit.frequency;
    EXPECT_NEAR(g->orbit.max_xc, 1.0, 1e-12);
  }
}

// Families with different numbers of impacts meet at grazing orbits (the
// forced counterpart of the paper's bridge, section 4): where a (1,1) orbit
// grazes the wall inside its flight, a (2,1) orbit has a zero-velocity
// impact. Located on two different families by two continuations.
TEST(Response, TheTwoImpactFamilyStartsWhereTheOneImpactFamilyGrazes) {
  const ResponseCurve one = Curve(1, 0.5, 0.75, 0.01);
  const ResponseCurve two = Curve(2, 0.5, 0.75, 0.01);
  const auto grazings = Of(one, SpecialKind::kGrazing);
  const auto zero = Of(two, SpecialKind::kZeroVelocity);
  ASSERT_GE(grazings.size(), 2u);
  for (const SpecialPoint* g : grazings) {
    // Both test functions cross zero transversally; Brent to ~1e-15: 1e-9.
    EXPECT_LT(Nearest(zero, g->orbit.frequency), 1e-9) << "grazing of the (1,1) family at w = " << g->orbit.frequency;
  }
}

TEST(Response, ContinuationPassesFoldsAndLocatesThem) {
  const ResponseCurve c = Curve(1, 0.4, 1.0, 0.01);
  const auto folds = Of(c, SpecialKind::kFold);
  ASSERT_GE(folds.size(), 1u);
  for (const SpecialPoint* f : folds) {
    // A fold of a forced periodic orbit has a Floquet multiplier +1: a
    // property the tangent-based location does not use. 1e-6: the FD
    // Jacobian of the tangent puts the fold to ~1e-9 in the branch's
    // arclength, where the multiplier moves at O(1).
    double closest = 1e300;
    for (int i = 0; i < f->orbit.multipliers.size(); ++i) {
      closest = std::min(closest, std::abs(f->orbit.multipliers[i] - 1.0));
    }
    EXPECT_LT(closest, 1e-6) << "fold at w = " << f->orbit.frequency;
  }
  // The branch turns there: w rises (or falls) to the fold and the
  // continuation goes on past it, with points on both sides.
  const ResponseBranch& b = c.branches[static_cast<std::size_t>(folds[0]->branch)];
  const double wf = folds[0]->orbit.frequency;
  std::size_t turn = 0;
  for (std::size_t k = 1; k + 1 < b.points.size(); ++k) {
    const double dw0 = b.points[k].frequency - b.points[k - 1].frequency;
    const double dw1 = b.points[k + 1].frequency - b.points[k].frequency;
    if ((dw0 > 0.0) != (dw1 > 0.0) && std::abs(b.points[k].frequency - wf) < 0.01) turn = k;
  }
  EXPECT_GT(turn, 10u) << "no turning point near the fold at w = " << wf;
  EXPECT_GT(b.points.size() - turn, 10u);
}

TEST(Response, SpecialPointsHaveTheirDefiningProperty) {
  const ResponseCurve c = Curve(1, 0.4, 1.0, 0.01);
  for (const SpecialPoint* p : Of(c, SpecialKind::kPeriodDoubling)) {
    double closest = 1e300;
    for (int i = 0; i < p->orbit.multipliers.size(); ++i) {
      closest = std::min(closest, std::abs(p->orbit.multipliers[i] + 1.0));
    }
    EXPECT_LT(closest, 1e-6) << "period doubling at w = " << p->orbit.frequency;
  }
  for (const SpecialPoint* p : Of(c, SpecialKind::kGrazing)) {
    // Brent on the interior maximum of x_c - d: zero to its round-off.
    EXPECT_LT(std::abs(p->orbit.max_interior_gap), 1e-9) << "grazing at w = " << p->orbit.frequency;
  }
  for (const SpecialPoint* p : Of(c, SpecialKind::kZeroVelocity)) {
    EXPECT_LT(std::abs(p->orbit.min_impact_velocity), 1e-9) << "zero velocity at w = " << p->orbit.frequency;
  }
  // Every point of every branch satisfies the energy balance (1e-9 of the
  // work: quadrature and solution at round-off) and meets the wall.
  for (const ResponseBranch& b : c.branches) {
    for (const ForcedOrbit& o : b.points) {
      EXPECT_NEAR(o.work, o.dissipated + o.impact_loss, 1e-9 * std::abs(o.work)) << o.frequency;
      EXPECT_LT(o.residual, 1e-12);
    }
  }
}

TEST(Response, AmplitudeContinuationMeetsTheClosedFormGrazingLevel) {
  // At fixed w the linear response scales with a: it grazes at
  // a_g = d / |X_c| per unit force (no preload).
  const Model m = Forced();
  const double w = 0.6;
  ResponseOptions o;
  o.impacts = 1;
  o.parameter = ResponseParameter::kAmplitude;
  o.grid = {0.05, 0.5, 0.005};
  o.fixed = w;
  const ResponseCurve c = ComputeResponse(m, o);
  const ForcedOrbit unit = LinearResponse(m, w, 1.0);
  const double a_g = 1.0 / unit.max_xc;
  const auto zero = Of(c, SpecialKind::kZeroVelocity);
  ASSERT_FALSE(zero.empty());
  double best = 1.0;
  for (const SpecialPoint* z : zero) best = std::min(best, std::abs(z->orbit.amplitude - a_g));
  EXPECT_LT(best, 1e-9 * a_g);
}

// Each branch is traced once. The range's last value is a grid value with
// orbits of its own; before they were recorded, a start found there was
// traced again as a new branch: at w = 0.5 the one (1,1) branch came out three
// times (30 points each, the same fold and zero-velocity points three times).
// The test fails without the edge's nodes (checked): 3 branches.
TEST(Response, AnAmplitudeContinuationTracesEachBranchOnce) {
  ResponseOptions o;
  o.impacts = 1;
  o.parameter = ResponseParameter::kAmplitude;
  o.grid = {0.1, 0.5, 0.05};
  o.fixed = 0.5;
  const ResponseCurve c = ComputeResponse(Forced(), o);
  ASSERT_EQ(c.branches.size(), 1u);
  // And no special point twice: same kind, same amplitude to 1e-9 (the
  // duplicates agreed to ~1e-10, their own corrector tolerance).
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    for (std::size_t j = i + 1; j < c.points.size(); ++j) {
      EXPECT_FALSE(c.points[i].kind == c.points[j].kind &&
                   std::abs(c.points[i].orbit.amplitude - c.points[j].orbit.amplitude) < 1e-9)
          << "special points " << i << " and " << j << " are the same";
    }
  }
}

// Several levels of the fixed parameter merged (response.h, both faces):
// each level's curve as alone, its branches numbered on from the last
// level's; the peaks matched to the backbone, and only the peaks.
TEST(Response, LevelsAreMergedAndPeaksMatchedToTheBackbone) {
  ResponseOptions o;
  o.grid = {0.4, 1.0, 0.05};
  const ResponseLevels r = ComputeResponseLevels(Forced(), o, {0.1, 0.3});
  const ResponseCurve low = Curve(1, 0.4, 1.0, 0.05, 0.1), high = Curve(1, 0.4, 1.0, 0.05, 0.3);
  const int n_low = static_cast<int>(low.branches.size());
  ASSERT_EQ(r.branches, n_low + static_cast<int>(high.branches.size()));
  ASSERT_EQ(r.ends.size(), static_cast<std::size_t>(r.branches));
  ASSERT_EQ(r.points.size(), low.points.size() + high.points.size());
  std::size_t rows = 0;
  for (const ResponseCurve* c : {&low, &high}) {
    for (const ResponseBranch& b : c->branches) rows += b.points.size();
  }
  ASSERT_EQ(r.rows.size(), rows);
  EXPECT_EQ(r.rows.front().branch, 1);
  EXPECT_EQ(r.rows.back().branch, r.branches);
  EXPECT_EQ(r.points.back().branch, high.points.back().branch + n_low);
  EXPECT_EQ(r.rows.back().orbit.energy, high.branches.back().points.back().energy);
  const BackboneMatch match = MatchBackbone(Forced(), o, r.points);
  ASSERT_EQ(match.mode_frequency.size(), r.points.size());
  int matched = 0;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    if (r.points[i].kind != SpecialKind::kPeak) {
      EXPECT_FALSE(match.mode_frequency[i]);
    }
    if (match.mode_frequency[i]) {
      ++matched;
      EXPECT_EQ(match.mode_frequency[i], BackboneFrequency(Forced(), match.backbone, r.points[i].orbit.energy,
                                                           r.points[i].orbit.frequency));
    }
  }
  EXPECT_GT(matched, 0);
}

TEST(Response, BadOptionsNameTheField) {
  auto expect = [](ResponseOptions o, const std::string& field) {
    try {
      ComputeResponse(Forced(), o);
      FAIL() << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  ResponseOptions o;
  o.grid = {0.4, 1.0, 0.01};
  o.fixed = 0.3;
  ResponseOptions bad = o;
  bad.impacts = -1;
  expect(bad, "impacts");
  bad = o;
  bad.impacts = 0;
  bad.periods = 2;
  expect(bad, "periods");
  bad = o;
  bad.grid = {1.0, 0.4, 0.01};
  expect(bad, "frequency");
  bad = o;
  bad.fixed = 0.0;
  expect(bad, "amplitude");
  bad = o;
  bad.parameter = ResponseParameter::kAmplitude;
  bad.fixed = -1.0;
  expect(bad, "frequency");
}

}  // namespace
}  // namespace nsmodal

namespace nsmodal {
namespace {

// The forced scene's chain between two stops (x2 <= 0.5, x2 >= -0.5), 2 %
// damping, e = 0.8: responses of the sequence (1, 2).
Model ForcedClearance() {
  Model m = Forced();
  m.contacts = {DofContact(2, 1, true, 0.5, 0.8), DofContact(2, 1, false, 0.5, 0.8)};
  Validate(m);
  return m;
}

// The (1, 2) response's backbone is the conservative twin's symmetric (1, 2)
// orbit (t2 = T/2) at each period; a peak's mode frequency is where that
// family has the peak's energy. Each backbone orbit is TwoImpactOrbitAt's at
// t2 = T/2 (the same closed form: to the last bit), and the energy at a
// matched frequency equals the peak's to Brent's tolerance on T (1e-9 of the
// energy with the slopes here).
TEST(Response, ATwoContactSequenceHasTheSymmetricFamilyAsItsBackbone) {
  const Model m = ForcedClearance();
  ResponseOptions o;
  o.impacts = 2;
  o.sequence = {0, 1};
  o.grid = {0.4, 1.6, 0.02};
  o.fixed = 0.3;
  EXPECT_FALSE(NoBackbone(m, o));
  const ResponseCurve c = ComputeResponse(m, o);
  ASSERT_FALSE(c.branches.empty());
  for (const ResponseBranch& b : c.branches) {
    for (const ForcedOrbit& p : b.points) EXPECT_EQ(p.sequence, (std::vector<int>{0, 1}));
  }
  const BackboneMatch match = MatchBackbone(m, o, c.points);
  const AnalysisBasis twin(ConservativeTwin(m));
  long orbits = 0;
  for (std::size_t k = 0; k < match.backbone.periods.size(); ++k) {
    ASSERT_LE(match.backbone.at[k].size(), 1u);
    for (const OrbitRecord& r : match.backbone.at[k]) {
      ++orbits;
      const double t = match.backbone.periods[k];
      EXPECT_EQ(r.orbit.times.at(0), 0.5 * t);
      EXPECT_EQ(r.orbit.energy, TwoImpactOrbitAt(twin, 0.5 * t, t, {}, 0, 1).energy);
    }
  }
  EXPECT_GT(orbits, 1900);  // the symmetric member exists at (nearly) every period
  int matched = 0;
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    if (!match.mode_frequency[i]) continue;
    ++matched;
    const double t = 2.0 * M_PI / *match.mode_frequency[i];
    EXPECT_NEAR(TwoImpactOrbitAt(twin, 0.5 * t, t, {}, 0, 1).energy, c.points[i].orbit.energy,
                1e-9 * c.points[i].orbit.energy);
  }
  EXPECT_GT(matched, 0);
  // No backbone for other sequences, nor for a model with a free mass.
  o.impacts = 3;
  o.sequence = {0, 1, 1};
  EXPECT_NE(NoBackbone(m, o)->find("neither on one contact nor two contacts"), std::string::npos);
}

// Continuation in a model parameter (issue 26): the gap. x -> s x maps the
// response of (gap d, force a) onto that of (s d, s a) (the flight is linear,
// the impact law and the conditions n . x = d homogeneous), so following the
// gap d at fixed a is following the amplitude a / d at gap 1, the energies
// scaled by d^2: two continuations in two parameters, through different
// code (WithParameter's model at each d; the amplitude's ForcedProblem),
// must place every special point at d* = a / a*.
TEST(Response, AGapContinuationIsTheAmplitudeContinuationRescaled) {
  const Model m = Forced();
  const double w = 0.6, a = 0.3;
  ResponseOptions gap;
  gap.impacts = 1;
  gap.parameter = ResponseParameter::kModel;
  gap.model_parameter = ParseModelParameter(m, "gap");
  gap.grid = {0.6, 6.0, 0.02};
  Model at_w = m;
  at_w.forcing.frequency = w;
  const ResponseCurve by_gap = ComputeResponse(at_w, gap);
  ResponseOptions amp;
  amp.impacts = 1;
  amp.parameter = ResponseParameter::kAmplitude;
  amp.grid = {a / 6.0, a / 0.6, 0.001};
  amp.fixed = w;
  const ResponseCurve by_amplitude = ComputeResponse(m, amp);
  // Over this window: the zero-velocity point where the impacts begin and a
  // Neimark-Sacker point (a complex pair leaving the unit circle).
  ASSERT_EQ(Of(by_gap, SpecialKind::kZeroVelocity).size(), 1u);
  ASSERT_EQ(Of(by_gap, SpecialKind::kTorus).size(), 1u);
  EXPECT_EQ(by_gap.points.size(), by_amplitude.points.size());
  for (const SpecialPoint& p : by_gap.points) {
    // (The impact condition x_2(t_1-) = d holds at the point's gap.)
    const double d_star = p.parameter;
    // (1e-12 d: the corrector's tolerance on the impact condition, in gaps.)
    EXPECT_NEAR(p.orbit.before.front()[1], d_star, 1e-12 * d_star);
    double best = 1e300, energy = 0.0;
    for (const SpecialPoint& q : by_amplitude.points) {
      if (q.kind != p.kind) continue;
      const double rel = std::abs(a / q.orbit.amplitude - d_star) / d_star;
      if (rel < best) {
        best = rel;
        energy = q.orbit.energy * d_star * d_star;
      }
    }
    // 1e-8: both located by Brent to ~1e-12 in their parameter, on orbits
    // solved to 1e-13 of the gap; the comparison passes through a / a*.
    EXPECT_LT(best, 1e-8) << ToString(p.kind) << " at d = " << d_star;
    EXPECT_NEAR(p.orbit.energy, energy, 1e-8 * energy) << ToString(p.kind) << " at d = " << d_star;
  }
  // At the torus point a complex pair is on the unit circle (1e-7: the
  // point's parameter to ~1e-12 moves |mu| by that times d|mu|/dd).
  const SpecialPoint& torus = *Of(by_gap, SpecialKind::kTorus).front();
  double closest = 1e300;
  for (int i = 0; i < torus.orbit.multipliers.size(); ++i) {
    const std::complex<double> mu = torus.orbit.multipliers[i];
    if (std::abs(mu.imag()) > 1e-6) closest = std::min(closest, std::abs(std::abs(mu) - 1.0));
  }
  EXPECT_LT(closest, 1e-7);
}

// A model parameter's range up to the end of its valid values: the
// restitution to 1 (the model damped, so the response is posed there). The
// branch ends on the edge, solved at e = 1 exactly (the last grid value is
// clamped to it, the Jacobian one-sided in e there), and a range past it is
// refused naming the field before any work.
TEST(Response, ARestitutionContinuationEndsOnTheEdgeOfItsRange) {
  const Model m = Forced();
  ResponseOptions o;
  o.impacts = 1;
  o.parameter = ResponseParameter::kModel;
  o.model_parameter = ParseModelParameter(m, "restitution");
  o.grid = {0.2, 1.0, 0.8 / 300};
  const ResponseCurve c = ComputeResponse(m, o);
  ASSERT_FALSE(c.branches.empty());
  double top = 0.0;
  bool ended = false;
  for (const ResponseBranch& b : c.branches) {
    for (const double e : b.parameter) top = std::max(top, e);
    ended = ended || b.end.find("left the range at restitution = 1") != std::string::npos;
  }
  EXPECT_EQ(top, 1.0);
  EXPECT_TRUE(ended) << c.branches.front().end;
  o.grid.to = 1.1;
  try {
    ComputeResponse(m, o);
    ADD_FAILURE() << "a range past e = 1 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("system.restitution"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nsmodal
