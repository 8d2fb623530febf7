#include "nsmodal/table.h"

#include <cmath>
#include <stdexcept>

namespace nsmodal::report {

Cell CheckedCell(Cell cell, const std::string& column) {
  if (const double* v = std::get_if<double>(&cell); v != nullptr && !std::isfinite(*v)) {
    throw std::logic_error("internal error: column " + column + " holds " + (std::isnan(*v) ? "nan" : "inf") +
                           " as a value (a missing quantity must be empty); please report it");
  }
  return cell;
}

void WriteCell(std::ostream& os, const Cell& cell) {
  struct Visitor {
    std::ostream& os;
    void operator()(std::monostate) const {}
    void operator()(double v) const { os << v; }
    void operator()(long v) const { os << v; }
    void operator()(bool v) const { os << (v ? 1 : 0); }
    void operator()(const std::string& s) const {
      if (s.find_first_of(",\"\n\r") == std::string::npos) {
        os << s;
        return;
      }
      os << '"';
      for (char ch : s) os << (ch == '"' ? "\"\"" : std::string(1, ch));
      os << '"';
    }
  };
  std::visit(Visitor{os}, cell);
}

}  // namespace nsmodal::report
