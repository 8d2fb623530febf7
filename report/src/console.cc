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

}  // namespace nsmodal::report
