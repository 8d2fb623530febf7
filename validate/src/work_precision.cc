#include "nsmodal/work_precision.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <set>

#include "nsmodal/admissibility.h"
#include "nsmodal/error.h"
#include "nsmodal/flow.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/parallel.h"
#include "nsmodal/simulate.h"
#include "nsmodal/transitions.h"

namespace nsmodal {
namespace {

double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

struct Case {
  std::string name;
  Model model;
  Eigen::VectorXd x0, v0;
  double t_end;
  bool long_horizon = false;
};

// The grazing transition of the paper's 1-ipp family near 9.127, and which
// side of it (+1 or -1 in T) is admissible, for both the near-grazing case
// and the grazing sweep.
struct Grazing {
  double period;
  int admissible_side;
};

Grazing GrazingTransition(const AnalysisBasis& b) {
  const double tg = OneImpactTransitions(b, 9.0, 9.3, 0.01).front().period;
  return {tg, OneImpactOrbit(b, tg + 1e-6).admissible ? 1 : -1};
}

// A 1-ipp orbit's start and a horizon ending mid-flight (no impact at t_end).
Case OrbitCase(const AnalysisBasis& b, const std::string& name, double period, int periods, bool long_horizon = false) {
  const Orbit o = OneImpactOrbit(b, period);
  return {name, PaperModel(), o.z0.head(2), o.z0.tail(2), periods * period + 0.5 * period, long_horizon};
}

std::vector<Case> Cases(bool quick) {
  const AnalysisBasis b(PaperModel());
  const Grazing g = GrazingTransition(b);
  const double ts = SingularPeriods(b, 4.8, 4.9).front();
  std::vector<Case> cases{OrbitCase(b, "smooth", 7.5, 10),
                          OrbitCase(b, "near-grazing", g.period + g.admissible_side * 1e-3, 3),
                          OrbitCase(b, "high-energy", ts + 0.01, 3),
                          // Named by its length: the quick run's is not the full one's.
                          OrbitCase(b, quick ? "long-100" : "long-10000", 7.5, quick ? 100 : 10000, true)};
  Model zeno = PaperModel();
  zeno.FirstContact().restitution = 0.5;
  Eigen::VectorXd x0(2), v0(2);
  x0 << 1.5, 1.0;
  v0 << 0.0, 0.01;
  cases.push_back({"zeno", zeno, x0, v0, 1.0});
  return cases;
}

struct Setting {
  std::string integrator, label;
  double value;
  std::function<void(SimulateOptions&)> apply;
};

std::vector<Setting> Settings(bool long_horizon, bool quick) {
  std::vector<Setting> out;
  const std::vector<double> root_tols = quick ? std::vector<double>{1e-6, 1e-14} : std::vector<double>{1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14};
  for (double r : root_tols) {
    out.push_back({"exact", "root_tol", r, [r](SimulateOptions& o) {
                     o.integrator = Integrator::kExact;
                     o.root_tol = r;
                   }});
  }
  const std::vector<double> rtols = quick ? std::vector<double>{1e-6, 1e-10} : std::vector<double>{1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-13};
  for (const char* method : {"adams", "bdf"}) {
    for (double r : rtols) {
      out.push_back({std::string("cvode-") + method, "rtol", r, [r, method](SimulateOptions& o) {
                       o.integrator = Integrator::kCvode;
                       o.cvode_method = method;
                       o.rtol = r;
                       o.atol = 1e-2 * r;
                     }});
    }
  }
  // Before/after of the energy projection at impacts (simulate.h): Adams
  // without it ("cvode-plain"), the CVODE of earlier versions.
  for (double r : rtols) {
    out.push_back({"cvode-plain", "rtol", r, [r](SimulateOptions& o) {
                     o.integrator = Integrator::kCvode;
                     o.cvode_method = "adams";
                     o.cvode_energy_projection = false;
                     o.rtol = r;
                     o.atol = 1e-2 * r;
                   }});
  }
  std::vector<double> steps = quick ? std::vector<double>{1e-2, 1e-3} : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5};
  for (double h : steps) {
    if (long_horizon && h < 1e-4) continue;  // 7.5e8 steps at 1e-4 already
    out.push_back({"moreau-jean", "step", h, [h](SimulateOptions& o) {
                     o.integrator = Integrator::kMoreauJean;
                     o.step = h;
                   }});
  }
  return out;
}

std::string Label(const Setting& s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s=%.0e", s.label.c_str(), s.value);
  return buf;
}

}  // namespace

void CheckBenchModel(const Model& model, const std::string& field) {
  const Model paper = PaperModel();
  if (model.mass != paper.mass || model.stiffness != paper.stiffness || model.FirstContact().dof != paper.FirstContact().dof ||
      model.FirstContact().gap != paper.FirstContact().gap) {
    throw InputError(field, "the bench cases (a stable orbit at T = 7.5, the grazing and singular transitions at "
                            "9.127 and 4.834, a Zeno start) are defined on the paper's system; use "
                            "configs/paper.toml");
  }
}

std::vector<WorkPrecisionRow> RunWorkPrecision(const WorkPrecisionOptions& options) {
  const std::vector<Case> cases = Cases(options.quick);
  // References first (exact at its tightest root tolerance), then every
  // (case, setting) run as one job; CPU time is per thread, so running the
  // jobs side by side does not charge one run for another.
  std::vector<SimulationSummary> refs(cases.size());
  const auto base_options = [&](const Case& c) {
    SimulateOptions o;
    o.t_end = c.t_end;
    o.sample_dt = 0.0;
    o.root_tol = 1e-14;
    return o;
  };
  ParallelFor(static_cast<long>(cases.size()), options.threads, [&](long i) {
    refs[i] = Simulate(cases[i].model, cases[i].x0, cases[i].v0, base_options(cases[i]));
  });
  std::vector<std::pair<size_t, Setting>> jobs;  // in the order of the cases, as the rows
  for (size_t i = 0; i < cases.size(); ++i) {
    for (const Setting& s : Settings(cases[i].long_horizon, options.quick)) jobs.emplace_back(i, s);
  }
  // Run the long horizon first: its runs are the slowest, and the others fill in.
  std::vector<long> order(jobs.size());
  for (size_t j = 0; j < jobs.size(); ++j) order[j] = static_cast<long>(j);
  std::stable_partition(order.begin(), order.end(), [&](long j) { return cases[jobs[j].first].long_horizon; });
  std::vector<WorkPrecisionRow> rows(jobs.size());
  ParallelFor(
      static_cast<long>(jobs.size()), options.threads,
      [&](long k) {
        const long j = order[k];
        const Case& c = cases[jobs[j].first];
        const Setting& s = jobs[j].second;
        const SimulationSummary& ref = refs[jobs[j].first];
        SimulateOptions opt = base_options(c);
        s.apply(opt);
        // Fast runs are repeated (up to 10 times, while under 10 ms) and the
        // least CPU time kept: a cold first run would otherwise dominate.
        SimulationSummary r;
        double cpu = INFINITY;
        for (int rep = 0; rep < 10 && (rep == 0 || cpu < 0.01); ++rep) {
          const double t0 = ThreadCpuSeconds();
          r = Simulate(c.model, c.x0, c.v0, opt);
          cpu = std::min(cpu, ThreadCpuSeconds() - t0);
        }
        const double err = r.status == SimulationStatus::kFinished
                               ? (r.final_state - ref.final_state).norm() / ref.final_state.norm()
                               : INFINITY;
        rows[j] = {c.name, s.integrator, Label(s), s.value, err, cpu, r.impacts, r.steps, ref.impacts,
                   ref.zeno_events > 0};
      },
      options.progress);
  return rows;
}

std::vector<GrazingRow> RunGrazingFailures(const WorkPrecisionOptions& options) {
  std::vector<GrazingRow> rows;
  const Model m = PaperModel();
  const AnalysisBasis b(m);
  const Grazing g = GrazingTransition(b);
  const std::vector<Setting> settings = Settings(false, options.quick);
  const std::vector<double> deltas = options.quick ? std::vector<double>{1e-4, 1e-7} : std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  for (double delta : deltas) {
    for (int sign : {-1, 1}) {
      const Orbit o = OneImpactOrbit(b, g.period + sign * delta);
      SimulateOptions base;
      base.t_end = 0.999 * o.period;  // one period, stopping short of the nominal impact
      base.sample_dt = 0.0;
      std::vector<long> impacts;
      for (const Setting& s : settings) {
        SimulateOptions opt = base;
        s.apply(opt);
        impacts.push_back(Simulate(m, o.z0.head(2), o.z0.tail(2), opt).impacts);
      }
      // The expected count: the exact integrator at its tightest root_tol,
      // one of the settings just run.
      long expected = 0;
      double tightest = INFINITY;
      for (size_t k = 0; k < settings.size(); ++k) {
        if (settings[k].integrator == "exact" && settings[k].value < tightest) {
          tightest = settings[k].value;
          expected = impacts[k];
        }
      }
      const std::string side = sign == g.admissible_side ? "below" : "above";
      for (size_t k = 0; k < settings.size(); ++k) {
        rows.push_back({delta, side, settings[k].integrator, Label(settings[k]), impacts[k], expected, o.max_excess});
      }
    }
  }
  return rows;
}

std::vector<GrazingLimit> SummarizeGrazing(const std::vector<GrazingRow>& rows) {
  std::vector<GrazingLimit> out;
  auto find = [&](const GrazingRow& r) -> GrazingLimit& {
    for (GrazingLimit& l : out) {
      if (l.integrator == r.integrator && l.setting == r.setting) return l;
    }
    out.push_back({r.integrator, r.setting, INFINITY, INFINITY});
    return out.back();
  };
  for (const GrazingRow& r : rows) find(r);  // the settings in their order
  // Walk each side from the largest |clearance| down; the limit is the last
  // one reached before the first failure.
  std::vector<const GrazingRow*> sorted;
  for (const GrazingRow& r : rows) sorted.push_back(&r);
  std::stable_sort(sorted.begin(), sorted.end(), [](const GrazingRow* a, const GrazingRow* b) {
    return std::abs(a->clearance) > std::abs(b->clearance);
  });
  std::set<std::string> failed;  // integrator|setting|side that already failed
  for (const GrazingRow* r : sorted) {
    GrazingLimit& l = find(*r);
    const bool above = r->side == "above";
    const std::string key = r->integrator + "|" + r->setting + "|" + r->side;
    if (failed.count(key) != 0) continue;
    if (r->impacts != r->expected_impacts) {
      failed.insert(key);
      continue;
    }
    (above ? l.shallowest_excursion : l.smallest_clearance) = std::abs(r->clearance);
  }
  return out;
}

}  // namespace nsmodal
