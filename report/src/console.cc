#include "nsmodal/console.h"

#include <ios>

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

void PrintExplore(std::ostream& out, const ExploreReport& r, std::size_t periods) {
  out << "m = " << r.impacts << ": " << r.samples << " grid samples over " << periods << " periods\n";
  out << "dim ker A_m " << (r.impacts % 2 ? "at grid samples" : "at roots found") << ":";
  for (auto [k, v] : r.kernel_dimension_histogram) out << "  " << k << " -> " << v;
  out << "\npotential orbits (cyclic shifts merged): " << r.Count("repeated-lower-m") << " repeat a lower-m orbit, "
      << r.Count("grazing-contact") << " have a grazing contact, " << r.Count("new") << " new ("
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

}  // namespace nsmodal::report
