#pragma once
// The paper's pipeline as values, with no I/O: a grid of periods, a sweep of
// the 1- or 2-ipp orbits over it with their stability, and the atlas of a
// system (both sweeps, the transitions of the 1-ipp family, the bridges and the
// period doublings, paper sections 2-4) computed by one call. The CLI, the
// Python module, the benchmarks and the tests all reach the pipeline here.
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nsmodal/bridge.h"
#include "nsmodal/field_names.h"
#include "nsmodal/modal_basis.h"
#include "nsmodal/orbit.h"
#include "nsmodal/stability.h"
#include "nsmodal/transitions.h"
#include "nsmodal/truncation.h"
#include "nsmodal/two_impact.h"
#include "nsmodal/work.h"

namespace nsmodal {

// Periods from, from + step, ... up to `to` (inclusive to 1e-9 step).
struct PeriodGrid {
  double from = 0.0, to = 0.0, step = 0.0;

  // At most this many periods: a grid is held in memory with its orbits
  // (about 1 kB a period for the 2-ipp sweep of a 2-dof system).
  static constexpr long kMaxPeriods = 1000000;

  // from > 0, to >= from, step > 0, all finite, at most kMaxPeriods values;
  // throws InputError naming `field`.
  void Validate(const std::string& field = "period") const;
  long Count() const;  // number of values
  std::vector<double> Values() const;
  // "FROM:TO:STEP", checked by Validate; throws InputError naming `field`.
  static PeriodGrid Parse(const std::string& text, const std::string& field = "--period");
};

// "0.3" or "0.1,0.2,0.4": values where a grid FROM:TO:STEP could stand (the
// fixed parameter of `response`), every one positive and finite; throws
// InputError naming `field`.
std::vector<double> ParseValues(const std::string& text, const std::string& field);

// The work limit of the analysis (work.h CheckSweepWork) for the sweeps of
// `impacts` (1 and/or 2) over the grid, after the range of its periods
// (AnalysisBasis::CheckPeriod): throws InputError naming `field`.
// Every sweep below checks it before it starts.
void CheckSweepWork(const AnalysisBasis& b, const PeriodGrid& grid, const std::vector<int>& impacts,
                    const std::string& field = "period", bool transitions = false);

// Which orbits of a sweep get their Floquet multipliers (stability.h).
enum class StabilityPolicy {
  kNone,        // none
  kPotential,   // every potential orbit (NC1 + NC2)
  kAdmissible,  // admissible orbits only
};

// One orbit with, as the policy asked, its stability (none where it is not
// defined: an orbit with a grazing impact, stability.h).
struct OrbitRecord {
  Orbit orbit;
  std::optional<Stability> stability;
  bool stable() const { return stability && stability->stable; }
};

struct SweepOptions {
  StabilityPolicy stability = StabilityPolicy::kPotential;
  // Every multiplier, or (all_multipliers = false) the verdict, the largest
  // modulus and the multipliers off the unit circle (stability.h).
  StabilityOptions stability_options;
  TwoImpactOptions two_impact;  // root scan of the 2-ipp sweep
  // The impact sequence (issue 24): the contact of each impact, 0-based, as
  // many entries as impacts (1 or 2); empty: every impact on contact 1.
  std::vector<int> sequence;
  int threads = 0;              // worker threads (0: all cores)
  std::function<void(long done, long count)> progress;
};

// The orbits of one family over a grid: at[i] holds the orbits of period
// periods[i]: the one 1-ipp orbit (potential or not), or every potential
// 2-ipp orbit (one per root t2).
struct Sweep {
  int impacts = 1;
  std::vector<double> periods;
  std::vector<std::vector<OrbitRecord>> at;

  long Count() const;       // orbits
  long Admissible() const;  // admissible orbits
};

// impacts: 1 or 2 (throws InputError naming "impacts" otherwise).
Sweep ComputeSweep(const AnalysisBasis& b, const PeriodGrid& grid, int impacts, const SweepOptions& options = {});

// The same sweep streamed: sink(period, orbits of that period) is called in
// period order from the calling thread, with at most kStreamBlock periods in
// memory at a time, so memory does not grow with the grid (the CLI writes
// orbits.csv this way).
inline constexpr long kStreamBlock = 256;
void StreamSweep(const AnalysisBasis& b, const PeriodGrid& grid, int impacts, const SweepOptions& options,
                 const std::function<void(double period, std::vector<OrbitRecord>& orbits)>& sink);

// The orbits of a sweep on a model's first modes (truncation.h: the basis
// of t.model) in the full model's dofs: each z0 mapped back by to_physical
// (the stability stays the truncated model's).
void ToPhysical(const ModalTruncation& t, std::vector<OrbitRecord>& orbits);

// The orbits of one period, with the policy's stability. Throws InputError
// naming `field` for a period outside the range the basis honours or beyond
// the work limit (CheckSweepWork).
std::vector<OrbitRecord> OrbitsAt(const AnalysisBasis& b, double period, int impacts,
                                  const SweepOptions& options = {}, const std::string& field = "period");

// A sequence "1,2" as the contacts' 0-based indices, checked against the
// basis's contacts: 1 to max_entries entries (the free orbits: 1 or 2), each
// a contact's number; throws InputError naming `field` and the value otherwise.
std::vector<int> ParseSequence(const std::string& text, int contacts, const std::string& field, int max_entries = 2);

// `impacts` against the number m of impacts of the sequence `text`: an
// InputError naming `field` unless they agree, or `one_defers` and impacts is
// 1 (a default left as it is defers to the sequence).
void CheckImpactsAgree(int impacts, int m, const std::string& text, const std::string& field, bool one_defers);

// A face's impacts and sequence (CLI --impacts/--sequence, Python's
// impacts=/sequence=): the sequence if given (impacts then 1, its default, or
// its length), else `impacts` (1 or 2) on contact 1. Returns the impacts and
// the 0-based sequence; throws InputError naming names("impacts") or
// names("sequence").
std::pair<int, std::vector<int>> ImpactSequence(int impacts, const std::optional<std::string>& sequence, int contacts,
                                                const FieldNames& names);

// The potential orbits of the grid with each number of impacts in `impacts`
// (1 and/or 2), period by period and in that order: what `validate` checks.
std::vector<Orbit> PotentialOrbits(const AnalysisBasis& b, const PeriodGrid& grid, const std::vector<int>& impacts,
                                   const SweepOptions& options = {});

// The transitions of the admissible 1-ipp zones seen on a 1-ipp sweep and
// the stability changes inside them (OneImpactTransitionsAndCrossings).
std::vector<Transition> SweepTransitions(const AnalysisBasis& b, const Sweep& one);

// The same for a sweep streamed (StreamSweep, the CLI's orbits): each
// period's 1-ipp admissibility gathered as it comes, nothing else held.
struct ZoneScan {
  std::vector<double> periods;
  std::vector<bool> admissible;
  int contact = 0;  // the family's contact (its orbits' sequence)
  void Add(double period, const std::vector<OrbitRecord>& one_impact_orbits);
  std::vector<Transition> Transitions(const AnalysisBasis& b) const;
};

struct AtlasOptions {
  SweepOptions sweep{.stability = StabilityPolicy::kAdmissible, .stability_options = {}, .two_impact = {}, .sequence = {}, .threads = 0, .progress = {}};
};

struct Atlas {
  PeriodGrid grid;
  Sweep one, two;                       // 1- and 2-ipp orbits over the grid
  std::vector<Transition> transitions;  // of the 1-ipp family
  // Bridges at the grazing transitions, then at the period doublings T* of
  // the 1-ipp family with 2 T* in the grid (those whose bridge is already a
  // grazing one, the paper's case T* = T_G / 2, are not repeated).
  std::vector<Bridge> bridges;
  std::vector<double> doublings;  // every T* found in [from, to / 2]
  // What was looked for and not found, or found twice, one line each.
  std::vector<std::string> notes;
};

// Sweeps (1 and 2 impacts, one pass over the grid), transitions, bridges.
Atlas ComputeAtlas(const AnalysisBasis& b, const PeriodGrid& grid, const AtlasOptions& options = {});

}  // namespace nsmodal
