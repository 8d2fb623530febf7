#include "nsmodal/atlas.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "nsmodal/check.h"
#include "nsmodal/error.h"
#include "nsmodal/input_checks.h"
#include "nsmodal/one_impact.h"
#include "nsmodal/parallel.h"

namespace nsmodal {
namespace {

// The whole text as one finite number, else nullopt.
std::optional<double> NumberOf(const std::string& s) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

double ParseNumber(const std::string& s, const std::string& field, const std::string& whole) {
  const std::optional<double> v = NumberOf(s);
  if (!v) throw InputError(field, "expects FROM:TO:STEP with numbers, got '" + whole + "'");
  return *v;
}

void CheckImpacts(int impacts, const std::string& field = "impacts") {
  if (impacts != 1 && impacts != 2) {
    throw InputError(field, "sweeps compute 1 or 2 impacts per period, got " + std::to_string(impacts));
  }
}

bool WantsStability(StabilityPolicy policy, const Orbit& o) {
  switch (policy) {
    case StabilityPolicy::kNone:
      return false;
    case StabilityPolicy::kPotential:
      return o.potential;
    case StabilityPolicy::kAdmissible:
      return o.admissible;
  }
  return false;
}

}  // namespace

void PeriodGrid::Validate(const std::string& field) const {
  if (!std::isfinite(from) || !std::isfinite(to) || !std::isfinite(step)) {
    throw InputError(field, "FROM, TO and STEP must be finite, got " + FormatValue(from) + ":" + FormatValue(to) +
                                ":" + FormatValue(step));
  }
  if (!(from > 0.0)) throw InputError(field, "FROM must be positive, got " + FormatValue(from));
  if (!(to >= from)) {
    throw InputError(field, "TO must be >= FROM, got " + FormatValue(from) + ":" + FormatValue(to));
  }
  if (!(step > 0.0)) throw InputError(field, "STEP must be positive, got " + FormatValue(step));
  if ((to - from) / step >= static_cast<double>(kMaxPeriods)) {
    throw InputError(field, "asks for " + FormatValue(std::floor((to - from) / step) + 1) + " periods; at most " +
                                std::to_string(kMaxPeriods) + " in one grid");
  }
}

long PeriodGrid::Count() const { return std::lround(std::floor((to - from) / step + 1e-9)) + 1; }

std::vector<double> PeriodGrid::Values() const {
  std::vector<double> out;
  const long cells = Count() - 1;
  out.reserve(static_cast<std::size_t>(cells + 1));
  for (long j = 0; j <= cells; ++j) out.push_back(from + j * step);
  return out;
}

PeriodGrid PeriodGrid::Parse(const std::string& text, const std::string& field) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  for (std::string p; std::getline(ss, p, ':');) parts.push_back(p);
  if (parts.size() != 3) throw InputError(field, "expects FROM:TO:STEP, got '" + text + "'");
  PeriodGrid g{ParseNumber(parts[0], field, text), ParseNumber(parts[1], field, text),
               ParseNumber(parts[2], field, text)};
  g.Validate(field);
  return g;
}

std::vector<double> ParseValues(const std::string& text, const std::string& field) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const std::optional<double> v = NumberOf(item);
    if (!v || !(*v > 0.0)) {
      throw InputError(field, "must be a positive number, a list of them (a,b,c) or a grid FROM:TO:STEP, got '" +
                                  text + "'");
    }
    out.push_back(*v);
  }
  if (out.empty()) throw InputError(field, "is empty");
  return out;
}

long Sweep::Count() const {
  long n = 0;
  for (const auto& list : at) n += static_cast<long>(list.size());
  return n;
}

long Sweep::Admissible() const {
  long n = 0;
  for (const auto& list : at) {
    for (const OrbitRecord& r : list) n += r.orbit.admissible;
  }
  return n;
}

void CheckSweepWork(const AnalysisBasis& b, const PeriodGrid& grid, const std::vector<int>& impacts,
                    const std::string& field, bool transitions) {
  b.CheckPeriod(grid.from, field);  // the range first: the estimate holds within it
  b.CheckPeriod(grid.to, field);
  CheckSweepWork(b, grid.from, grid.step, grid.Count(), impacts, field, transitions);
}

void ToPhysical(const ModalTruncation& t, std::vector<OrbitRecord>& orbits) {
  for (OrbitRecord& r : orbits) r.orbit.z0 = t.PhysicalState(r.orbit.z0);
}

std::vector<OrbitRecord> OrbitsAt(const AnalysisBasis& b, double period, int impacts, const SweepOptions& options,
                                  const std::string& field) {
  CheckImpacts(impacts);
  b.CheckPeriod(period, field);
  CheckSweepWork(b, period, 0.0, 1, {impacts}, field);
  NSMODAL_CHECK(options.sequence.empty() || static_cast<int>(options.sequence.size()) == impacts);
  const int first = options.sequence.empty() ? 0 : options.sequence[0];
  std::vector<Orbit> orbits;
  if (impacts == 1) {
    orbits.push_back(OneImpactOrbit(b, period, {}, first));
  } else {
    orbits = TwoImpactOrbits(b, period, options.two_impact, first, options.sequence.empty() ? 0 : options.sequence[1]);
  }
  std::vector<OrbitRecord> records;
  records.reserve(orbits.size());
  for (Orbit& o : orbits) {
    OrbitRecord r{std::move(o), std::nullopt};
    if (WantsStability(options.stability, r.orbit)) {
      Stability st = OrbitStability(b, r.orbit, options.stability_options);
      if (st.defined) r.stability = std::move(st);  // a grazing impact: no verdict (stability.h)
    }
    records.push_back(std::move(r));
  }
  return records;
}

std::vector<int> ParseSequence(const std::string& text, int contacts, const std::string& field, int max_entries) {
  const std::vector<double> values = ParseValues(text, field);
  if (values.empty() || static_cast<int>(values.size()) > max_entries) {
    throw InputError(field, "must list the contact of each impact (1 to " + std::to_string(max_entries) +
                                " entries, e.g. 1,2), got '" + text + "'");
  }
  std::vector<int> out;
  for (double v : values) {
    if (!(v >= 1 && v <= contacts) || v != std::floor(v)) {
      throw InputError(field, "names contact " + FormatValue(v) + ", but the model has " + std::to_string(contacts) +
                                  (contacts == 1 ? " contact" : " contacts") + " (numbered from 1)");
    }
    out.push_back(static_cast<int>(v) - 1);
  }
  return out;
}

void CheckImpactsAgree(int impacts, int m, const std::string& text, const std::string& field, bool one_defers) {
  if (impacts == m || (one_defers && impacts == 1)) return;
  throw InputError(field, std::to_string(impacts) + " disagrees with the sequence " + text + " (" + std::to_string(m) +
                              " impacts): give one of them");
}

std::pair<int, std::vector<int>> ImpactSequence(int impacts, const std::optional<std::string>& sequence, int contacts,
                                                const FieldNames& names) {
  if (!sequence) {
    CheckImpacts(impacts, names("impacts"));
    return {impacts, std::vector<int>(impacts, 0)};
  }
  std::vector<int> s = ParseSequence(*sequence, contacts, names("sequence"));
  CheckImpactsAgree(impacts, static_cast<int>(s.size()), *sequence, names("impacts"), true);
  return {static_cast<int>(s.size()), std::move(s)};
}

void StreamSweep(const AnalysisBasis& b, const PeriodGrid& grid, int impacts, const SweepOptions& options,
                 const std::function<void(double period, std::vector<OrbitRecord>& orbits)>& sink) {
  CheckImpacts(impacts);
  CheckThreads(options.threads, "threads");
  grid.Validate();
  b.CheckPeriod(grid.from);
  b.CheckPeriod(grid.to);
  CheckSweepWork(b, grid, {impacts});
  const std::vector<double> periods = grid.Values();
  const long count = static_cast<long>(periods.size());
  std::vector<std::vector<OrbitRecord>> block;
  for (long first = 0; first < count; first += kStreamBlock) {
    const long size = std::min(kStreamBlock, count - first);
    block.assign(static_cast<std::size_t>(size), {});
    std::function<void(long, long)> progress;
    if (options.progress) progress = [&](long done, long) { options.progress(first + done, count); };
    ParallelFor(
        size, options.threads, [&](long i) { block[i] = OrbitsAt(b, periods[first + i], impacts, options); },
        progress);
    for (long i = 0; i < size; ++i) sink(periods[first + i], block[i]);
  }
}

Sweep ComputeSweep(const AnalysisBasis& b, const PeriodGrid& grid, int impacts, const SweepOptions& options) {
  Sweep s;
  s.impacts = impacts;
  StreamSweep(b, grid, impacts, options, [&s](double period, std::vector<OrbitRecord>& orbits) {
    s.periods.push_back(period);
    s.at.push_back(std::move(orbits));
  });
  return s;
}

std::vector<Orbit> PotentialOrbits(const AnalysisBasis& b, const PeriodGrid& grid, const std::vector<int>& impacts,
                                   const SweepOptions& options) {
  grid.Validate();
  for (int m : impacts) CheckImpacts(m);
  CheckSweepWork(b, grid, impacts);  // all the sweeps' work, before the first starts
  std::vector<Sweep> sweeps;
  for (int m : impacts) sweeps.push_back(ComputeSweep(b, grid, m, options));
  std::vector<Orbit> orbits;
  for (std::size_t i = 0; i < static_cast<std::size_t>(grid.Count()); ++i) {
    for (const Sweep& sweep : sweeps) {
      for (const OrbitRecord& r : sweep.at[i]) {
        if (r.orbit.potential) orbits.push_back(r.orbit);
      }
    }
  }
  return orbits;
}

std::vector<Transition> SweepTransitions(const AnalysisBasis& b, const Sweep& one) {
  if (one.impacts != 1) throw InputError("impacts", "transitions are those of the 1-ipp family; got a 2-ipp sweep");
  ZoneScan zones;
  for (std::size_t i = 0; i < one.at.size(); ++i) zones.Add(one.periods[i], one.at[i]);
  return zones.Transitions(b);
}

void ZoneScan::Add(double period, const std::vector<OrbitRecord>& one_impact_orbits) {
  periods.push_back(period);
  const Orbit& o = one_impact_orbits.front().orbit;
  admissible.push_back(o.admissible);
  if (!o.sequence.empty()) contact = o.sequence.front();
}

std::vector<Transition> ZoneScan::Transitions(const AnalysisBasis& b) const {
  return OneImpactTransitionsAndCrossings(b, periods, admissible, contact);
}

Atlas ComputeAtlas(const AnalysisBasis& b, const PeriodGrid& grid, const AtlasOptions& options) {
  CheckThreads(options.sweep.threads, "threads");
  grid.Validate();
  b.CheckPeriod(grid.from);
  b.CheckPeriod(grid.to);
  CheckSweepWork(b, grid, {1, 2}, "period", true);
  Atlas a;
  a.grid = grid;
  a.one.impacts = 1;
  a.two.impacts = 2;
  a.one.periods = a.two.periods = grid.Values();
  const std::size_t count = a.one.periods.size();
  a.one.at.resize(count);
  a.two.at.resize(count);
  // One pass over the grid for both families (one progress report).
  ParallelFor(
      static_cast<long>(count), options.sweep.threads,
      [&](long i) {
        a.one.at[i] = OrbitsAt(b, a.one.periods[i], 1, options.sweep);
        a.two.at[i] = OrbitsAt(b, a.two.periods[i], 2, options.sweep);
      },
      options.sweep.progress);
  a.transitions = SweepTransitions(b, a.one);
  for (const Transition& t : a.transitions) {
    if (t.kind != TransitionKind::kGrazing || t.contact != 0) continue;  // contact 1's own grazings
    BridgeSearch search = FindBridgeAt(b, t.period);
    if (search.found()) {
      a.bridges.push_back(std::move(search.bridge));
    } else {
      a.notes.push_back("no bridge at the grazing transition T = " + FormatValue(t.period) + ": " + search.message);
    }
  }
  // The period doublings are the -1 crossings of the sweep (OneImpactPeriodDoublings
  // on the same grid points), up to T / 2 = grid.to / 2: the 2T-periodic 2-ipp
  // orbit born there must fit the grid too.
  for (const Transition& t : a.transitions) {
    if (t.kind == TransitionKind::kMultiplierMinusOne && t.period <= 0.5 * grid.to) a.doublings.push_back(t.period);
  }
  for (double ts : a.doublings) {
    bool known = false;
    for (const Bridge& br : a.bridges) known = known || std::abs(br.period - 2.0 * ts) <= 1e-9 * br.period;
    if (known) {
      a.notes.push_back("period doubling at T* = " + FormatValue(ts) + ": its bridge is the grazing one at " +
                        FormatValue(2.0 * ts));
      continue;
    }
    BridgeSearch search = FindPeriodDoublingBridge(b, ts);
    if (search.found()) {
      a.bridges.push_back(std::move(search.bridge));
    } else {
      a.notes.push_back("period doubling at T* = " + FormatValue(ts) + ": no bridge (" + search.message + ")");
    }
  }
  return a;
}

}  // namespace nsmodal
