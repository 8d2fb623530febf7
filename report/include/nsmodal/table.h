#pragma once
// Tables declared once. A table's columns are a list of {name, kind, cell};
// the CSV header, the CSV rows and the Python module's column arrays are all
// produced from that one list, so a column cannot be named in one place and
// filled in another.
//
// CSV conventions: numbers with 17 significant digits, booleans 1/0, a
// missing value (a quantity that does not exist for that row: t2 of a 1-ipp
// orbit, the multipliers of an orbit that is not potential) is an empty field,
// text is quoted when it holds a comma, a quote or a line break (RFC 4180).
#include <functional>
#include <ostream>
#include <string>
#include <variant>
#include <vector>

namespace nsmodal::report {

enum class ColumnKind { kReal, kInteger, kBool, kText };

// std::monostate: missing.
using Cell = std::variant<std::monostate, double, long, bool, std::string>;

template <class Row>
struct Column {
  std::string name;
  ColumnKind kind = ColumnKind::kReal;
  std::function<Cell(const Row&)> cell;
};

template <class Row>
using Columns = std::vector<Column<Row>>;

void WriteCell(std::ostream& os, const Cell& cell);

template <class Row>
void WriteCsvHeader(std::ostream& os, const Columns<Row>& columns) {
  for (std::size_t k = 0; k < columns.size(); ++k) os << (k ? "," : "") << columns[k].name;
  os << "\n";
}

template <class Row>
void WriteCsvRow(std::ostream& os, const Columns<Row>& columns, const Row& row) {
  for (std::size_t k = 0; k < columns.size(); ++k) {
    if (k) os << ",";
    WriteCell(os, columns[k].cell(row));
  }
  os << "\n";
}

template <class Row>
void WriteCsv(std::ostream& os, const Columns<Row>& columns, const std::vector<Row>& rows) {
  WriteCsvHeader(os, columns);
  for (const Row& r : rows) WriteCsvRow(os, columns, r);
}

}  // namespace nsmodal::report
