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
//
// No table holds inf or nan as a value. A quantity that does not exist for a
// row (an infinite energy at a singular transition, the impact-time error of
// a first period that did not have the predicted impacts) is missing, said so
// where the column is declared (Real(std::optional)); a non-finite double
// reaching a writer is a bug in nsmodal, and CheckedCell stops it: it throws
// std::logic_error naming the column, so the run fails (exit 1, its results
// removed, output.h) instead of writing it, and never crashes.
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <variant>
#include <vector>

#include "nsmodal/output.h"

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

// A real cell from a quantity that may not exist.
inline Cell Real(const std::optional<double>& v) { return v ? Cell(*v) : Cell(); }

// The cell of `column` for a row, after the invariant: a double in it is
// finite (throws std::logic_error naming the column otherwise). Every writer (the CSV below,
// the Python module's column arrays) takes its cells from here.
Cell CheckedCell(Cell cell, const std::string& column);

template <class Row>
Cell CellOf(const Column<Row>& column, const Row& row) {
  return CheckedCell(column.cell(row), column.name);
}

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
    WriteCell(os, CellOf(columns[k], row));
  }
  os << "\n";
}

template <class Row>
void WriteCsv(std::ostream& os, const Columns<Row>& columns, const std::vector<Row>& rows) {
  WriteCsvHeader(os, columns);
  for (const Row& r : rows) WriteCsvRow(os, columns, r);
}

// DIR/NAME written whole or not at all (ResultFile): the CSV of `rows`.
template <class Row>
void WriteCsvFile(const OutputDir& dir, const std::string& name, const Columns<Row>& columns,
                  const std::vector<Row>& rows) {
  ResultFile file(dir, name);
  WriteCsv(file.stream(), columns, rows);
  file.Commit();
}

}  // namespace nsmodal::report
