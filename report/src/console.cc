#include "nsmodal/console.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <complex>
#include <iomanip>
#include <ios>
#include <memory>
#include <optional>
#include <string>

#include "nsmodal/figure_subjects.h"

namespace nsmodal::report {
namespace {

// Restores a stream's format (flags, precision, width) when it goes out of scope.
class FormatGuard {
 public:
  explicit FormatGuard(std::ostream& out) : out_(out), saved_(nullptr) { saved_.copyfmt(out); }
  ~FormatGuard() { out_.copyfmt(saved_); }
  FormatGuard(const FormatGuard&) = delete;
  FormatGuard& operator=(const FormatGuard&) = delete;

 private:
  std::ostream& out_;
  std::ios saved_;
};

}  // namespace

std::function<void(long, long)> ProgressBar(const std::string& label) {
  if (!isatty(STDERR_FILENO)) {
    // A log, not a terminal: a plain line every 10 s and at the end, once a
    // run has lasted that long (short runs stay quiet).
    const auto every = std::chrono::seconds(10);
    const auto start = std::chrono::steady_clock::now();
    auto last = std::make_shared<std::chrono::steady_clock::time_point>(start);
    return [label, every, start, last](long done, long count) {
      const auto now = std::chrono::steady_clock::now();
      if (now - *last < every && (done < count || now - start < every)) return;
      *last = now;
      std::fprintf(stderr, "%s: %ld/%ld (%.0f s)\n", label.c_str(), done, count,
                   std::chrono::duration<double>(now - start).count());
      std::fflush(stderr);
    };
  }
  return [label](long done, long count) {
    const int width = 40;
    const int filled = count > 0 ? static_cast<int>(width * done / count) : width;
    std::fprintf(stderr, "\r%s [%s%s] %ld/%ld", label.c_str(), std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done, count);
    if (done == count) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  };
}

void PrintTruncation(std::ostream& out, const ModalTruncation& t) {
  out << "modal truncation: " << t.kept << " of " << t.dofs << " modes kept (up to " << t.highest_kept_frequency
      << " rad/s; " << (t.kept < t.dofs ? "the first neglected " : "none neglected");
  if (t.kept < t.dofs) out << t.lowest_neglected_frequency << " rad/s";
  out << "); residual flexibility " << t.residual_flexibility << " m/N";
}

void PrintSweepTruncation(std::ostream& out, const ModalTruncation& t) {
  PrintTruncation(out, t);
  out << ": the neglected modes carry at most sqrt(2 E f_res) of x_c at energy E (orbits.csv, neglected_xc_bound)\n";
}

void PrintSimulationTruncation(std::ostream& out, const SimulationPlan& plan, const Contact& contact) {
  if (!plan.truncation) return;
  const ModalTruncation& t = *plan.truncation;
  PrintTruncation(out, t);
  out << ": at the initial energy " << plan.initial_energy << " J the neglected modes carry at most "
      << t.ContactBound(plan.initial_energy)
      << " m of x_c in the full model (for as long as the energy does not grow: unforced, e <= 1); "
      << "the run starts from the kept modes' part of the initial state (x_c " << (t.from_physical * plan.x0)[0]
      << " of " << contact.Along(plan.x0) << ")\n";
}

void PrintExplore(std::ostream& out, const ExploreReport& r, long periods) {
  out << "m = " << r.impacts << ": " << r.samples << " grid samples over " << periods << " periods\n";
  out << "dim ker A_m " << (r.impacts % 2 ? "at grid samples" : "at roots found") << ":";
  for (auto [k, v] : r.kernel_dimension_histogram) out << "  " << k << " -> " << v;
  out << "\npotential orbits (cyclic shifts merged): " << r.Count("repeated-lower-m") << " repeat a lower-m orbit, "
      << r.Count("grazing-contact") << " have a grazing contact, ";
  if (r.Count("simultaneous-impacts") > 0) out << r.Count("simultaneous-impacts") << " strike two contacts at once, ";
  out << r.Count("new") << " new ("
      << r.Count("new", true) << " admissible)\n";
  out << "smallest defect away from repeated orbits: " << r.best_phi_new << "\n";
  out << "conjecture (paper 2.3): dim ker = " << (r.impacts % 2 ? 1 : 2)
      << "; potential solutions only as degenerate lower-m orbits\n";
  for (const ExploreFinding& f : r.findings) {
    if (f.kind != "new") continue;
    out << "  new: T = " << f.orbit.period << " times =";
    for (double t : f.orbit.times) out << " " << t;
    out << " energy = " << f.orbit.energy << " min/max |v_c-| = " << f.grazing_ratio
        << (f.orbit.admissible ? " admissible" : " not admissible") << "\n";
  }
}

void PrintFamilies(std::ostream& out, const std::vector<FamilySummary>& families, double step) {
  for (const FamilySummary& f : families) {
    out << "  family of T = " << f.start.period << ": admissible for T in [" << FormatValue(f.from) << ", "
        << FormatValue(f.to) << "]" << (f.lower_end ? " (lower end: " + *f.lower_end + ")" : "")
        << (f.upper_end ? " (upper end: " + *f.upper_end + ")" : "") << "; " << f.points << " points at step "
        << step << ": energy " << f.energy_min << " to " << f.energy_max << ", largest |multiplier| "
        << f.multiplier_min << " to " << f.multiplier_max << (f.multiplier_min > 1.0 ? " (unstable throughout)" : "")
        << "\n";
  }
}

void PrintResponseCurve(std::ostream& out, const ResponseCurve& curve, int first_branch) {
  for (std::size_t b = 0; b < curve.branches.size(); ++b) {
    out << "branch " << first_branch + b + 1 << ": " << curve.branches[b].points.size() << " points; "
        << curve.branches[b].end << "\n";
  }
  for (const std::string& note : curve.notes) out << "note: " << note << "\n";
}

void PrintResponsePeaks(std::ostream& out, const std::vector<SpecialPoint>& points, const BackboneMatch& match,
                        int periods) {
  const double n = periods;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SpecialPoint& p = points[i];
    if (p.kind != SpecialKind::kPeak) continue;
    const double own = p.orbit.frequency / n;  // the response's own frequency 2 pi / P
    out << "peak on branch " << p.branch + 1 << ": w = " << FormatValue(p.orbit.frequency)
        << (n > 1 ? " (w / n = " + FormatValue(own) + ")" : std::string()) << ", energy = "
        << FormatValue(p.orbit.energy);
    if (const std::optional<double>& w = match.mode_frequency[i]) {
      out << "; the nonsmooth mode at that energy: w = " << FormatValue(*w) << " (difference "
          << FormatValue(own - *w) << ")\n";
    } else {
      out << "; no admissible nonsmooth mode at that energy in the range\n";
    }
  }
}

void PrintInconsistent(std::ostream& out, const ResponseValidation& validation) {
  for (const ForcedValidationRow& r : validation.rows) {
    if (r.v.consistent) continue;
    out << "  inconsistent: w = " << FormatValue(r.v.orbit.frequency) << " (" << ToString(r.v.integrator)
        << "): " << r.v.reason << "\n";
  }
}

void PrintResponseValidation(std::ostream& out, const ResponseValidation& validation, std::size_t orbits, int periods,
                             const std::string& path) {
  out << "validated " << orbits << " orbits over " << periods << " periods: " << validation.consistent << "/"
      << validation.rows.size() << " runs consistent; wrote " << path << "\n";
}

void PrintOrbits(std::ostream& out, const std::vector<OrbitRecord>& orbits, int impacts, double period) {
  const FormatGuard guard(out);
  out << std::setprecision(12);
  out << orbits.size() << " potential orbit(s) with " << impacts << " impact(s) per period, T = " << period << "\n";
  for (std::size_t k = 0; k < orbits.size(); ++k) {
    const Orbit& o = orbits[k].orbit;
    const long n = o.z0.size() / 2;
    out << "\n#" << k + 1 << (o.admissible ? "  admissible" : "  NOT admissible")
        << (o.potential ? "" : " (not potential)") << (o.degenerate ? " (degenerate: bridge)" : "") << "\n";
    if (!o.times.empty()) out << "  t2                    " << o.times[0] << "\n";
    out << "  energy                " << o.energy << "\n"
        << "  periodicity residual  " << o.periodicity_residual << "\n"
        << "  NC2 residual          " << o.nc2_residual << "\n"
        << "  NC3 margin (max x_c-d) " << o.max_excess << "\n";
    out << "  x(0) =";
    for (long i = 0; i < n; ++i) out << " " << o.z0[i];
    out << "\n  v(0+) =";
    for (long i = 0; i < n; ++i) out << " " << o.z0[n + i];
    out << "\n";
    if (const std::optional<Stability>& st = orbits[k].stability) {
      out << "  " << (st->stable ? "stable" : "unstable") << ", Floquet multipliers";
      for (const std::complex<double>& mu : st->multipliers) {
        out << " " << mu.real() << (mu.imag() < 0 ? "-" : "+") << std::abs(mu.imag()) << "i";
      }
      out << "\n";
    }
    if (!o.reason.empty()) out << "  " << o.reason << "\n";
  }
}

void PrintAtlas(std::ostream& out, const Atlas& atlas) {
  for (const std::string& note : atlas.notes) out << note << "\n";
  const std::vector<double>& periods = atlas.one.periods;
  out << periods.size() << " periods from " << periods.front() << " to " << periods.back() << "; "
      << atlas.transitions.size() << " transitions, " << atlas.bridges.size() << " bridges\n";
  for (const Bridge& br : atlas.bridges) {
    out << "  " << (IsGrazing(br) ? "grazing" : "period-doubling") << " bridge at T = " << br.period
        << " (t2 = " << br.t2 << "): E from " << br.energy_min << " to " << br.energy_max << "\n";
  }
}

void PrintBenchTables(std::ostream& out, const std::vector<WorkPrecisionRow>& rows,
                      const std::vector<GrazingRow>& grazing) {
  const FormatGuard guard(out);
  out << std::left << std::setw(13) << "case" << std::setw(13) << "integrator" << std::setw(16) << "setting"
      << std::right << std::setw(10) << "error" << std::setw(11) << "cpu_s" << std::setw(9) << "impacts"
      << std::setw(12) << "steps" << "\n";
  for (const WorkPrecisionRow& r : rows) {
    out << std::left << std::setw(13) << r.case_name << std::setw(13) << r.integrator << std::setw(16) << r.setting
        << std::right << std::scientific << std::setprecision(2) << std::setw(10) << r.error << std::setw(11)
        << r.cpu_s << std::defaultfloat << std::setw(9) << r.impacts << std::setw(12) << r.steps << "\n";
  }
  out << "\ngrazing (T_G +- delta, one period): the shallowest excursion past d turned into the right impacts,\n"
         "and the smallest clearance below d without a spurious impact (inf: wrong at the largest tried)\n";
  out << std::left << std::setw(13) << "integrator" << std::setw(16) << "setting" << std::right << std::setw(14)
      << "excursion" << std::setw(14) << "clearance" << "\n";
  for (const GrazingLimit& l : SummarizeGrazing(grazing)) {
    out << std::left << std::setw(13) << l.integrator << std::setw(16) << l.setting << std::right << std::scientific
        << std::setprecision(2) << std::setw(14) << l.shallowest_excursion << std::setw(14) << l.smallest_clearance
        << std::defaultfloat << "\n";
  }
}

}  // namespace nsmodal::report
