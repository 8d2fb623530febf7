#pragma once
// A table (table.h) as an HDF5 file: the binary face of large results (sweeps,
// trajectories, studies), read by h5py, MATLAB, Julia and the HDF5 tools.
//
// The file NAME.h5 of a table NAME holds:
// - one 1-D dataset per column, under the column's CSV name, one element per
//   row, in the CSV's row order:
//     real     float64; a missing cell is NaN, the one missing marker of a
//              real column (as in the Python module's columns): no table
//              holds inf or nan as a value (CheckedCell), so a NaN is exactly
//              an empty field of the CSV and nothing else;
//     integer  int64; an integer cell is never missing (a count that may be
//              missing is declared real, as tables.cc does; a missing integer
//              cell throws std::logic_error);
//     bool     the enum {FALSE = 0, TRUE = 1} over int8, which h5py reads as
//              numpy bool (its own encoding of bool), so a column can index
//              rows directly (an int8 0/1 array would index by position);
//              MATLAB and Julia read it as int8 or as the member names.
//              A missing cell is FALSE there, and TRUE in the dataset
//              missing/NAME (the same enum, one element per row), created
//              only for a boolean column that has a missing cell: no
//              missing/NAME, no missing cell;
//     text     variable-length UTF-8 strings; a missing cell is "" (the CSV
//              writes both as an empty field);
//   each extendible (unlimited maximum size), uncompressed, in chunks of at
//   most 1,024 rows (a block of rows is a whole number of chunks; the last
//   chunk, partly filled, takes a whole one on disk);
// - root attributes: "table" (NAME), "columns" (the column names in the CSV's
//   order: the order to rebuild the CSV in; the root group also tracks the
//   datasets' creation order, which h5dump --sort_by=creation_order shows,
//   but h5py 3.7 lists a group's members by name) and "conventions" (the
//   paragraph above, short).
// The file format is HDF5 1.8's (readable by every HDF5 from 1.8 on).
//
// In Python:  f = h5py.File("orbits.h5");
//             df = pandas.DataFrame({c: f[c][()] for c in f.attrs["columns"]})
// (h5py 3 reads a text column as bytes: f[c].asstr()[()] gives str; the
// attributes come back as str.)
//
// A table is written as the CSV is (output.h): created under the hidden
// temporary DIR/.NAME.h5.partial, appended to row by row, buffered a block of
// rows per column and written block by block, published as DIR/NAME.h5 by
// Commit() only when complete (OutputDir::Publish: an OutputDir unwound by an
// exception removes it again); destroyed without Commit() it closes and
// removes its temporary. Memory: one block (8 MiB of cells by default) and
// what HDF5 keeps of the open file, some 20-25 KB a column once rows are
// written (mostly the 1.8 format's chunk indexes in HDF5's metadata cache),
// not growing with the rows. Measured peaks, more than the CSV writer's:
// 22 MB for the 611 columns of the 100-mass orbits table, 157 MB for the
// 6,011 of a 1,000-mass one, 35 MB for a trajectory of 202 columns whether
// of 1 or 3 million rows. Every HDF5 call's status is
// checked; a failure throws OutputError naming DIR/NAME.h5 and the system's
// reason (the errno of the read or write that failed, taken where it failed,
// through the writer's own POSIX file driver), or HDF5's message when the
// failure is not the system's. HDF5's automatic error printing is off while
// the writer works. Writes count against output.h's FailWritesAfter budget, as
// a CSV's do. A table that has failed refuses further rows and its Commit().
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nsmodal/output.h"
#include "nsmodal/table.h"

namespace nsmodal::report {

// The file a table is published as: NAME.h5 (the name for OutputDir::Prepare's
// list of owned results, beside or instead of NAME.csv).
inline std::string Hdf5FileName(const std::string& table) { return table + ".h5"; }

struct Hdf5Column {
  std::string name;
  ColumnKind kind = ColumnKind::kReal;
};

// The untyped writer behind Hdf5Table: cells set column by column into the
// row being built, rows ended one by one.
class Hdf5Writer {
 public:
  // Rows per block when none is given: as many as fit 8 MiB of 8-byte cells,
  // between 256 and 65,536 (1,716 rows for the 611 columns of a 100-mass
  // orbits table; 256 rows, 12 MiB, for the 6,011 of a 1,000-mass one: each
  // block costs HDF5 some 10 us per column).
  static std::size_t DefaultBlockRows(std::size_t columns);

  // Creates DIR/.NAME.h5.partial with a dataset per column. Throws
  // std::logic_error when a column name cannot be a dataset's (empty, "." or
  // holding '/'), is given twice or is "missing" (the group of the boolean
  // columns' missing cells), and OutputError when the file cannot be written.
  Hdf5Writer(const OutputDir& dir, const std::string& table, std::vector<Hdf5Column> columns,
             std::size_t block_rows = 0);
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;
  Hdf5Writer(Hdf5Writer&&) noexcept;
  Hdf5Writer& operator=(Hdf5Writer&&) = delete;
  ~Hdf5Writer();

  // The cell of `column` in the row being built. Throws std::logic_error when
  // the cell is not of the column's kind (or a missing integer, or a
  // non-finite real): a bug in the table's declaration. A row left unfinished
  // by an exception is overwritten by the next.
  void Set(std::size_t column, Cell cell);
  // Ends the row being built (every column set); writes the block when full.
  void EndRow();
  // Writes the last block, closes the file and publishes it as NAME.h5.
  void Commit();

  const std::filesystem::path& path() const;  // DIR/NAME.h5
  std::size_t rows() const;                   // rows ended so far
  // Rows per block: the block_rows asked for (or the default) rounded up to
  // a whole number of chunks of at most 1,024 rows (3,000: 3 x 1,000).
  std::size_t block_rows() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A table's rows as an HDF5 file, columns from the table's declaration (the
// same list the CSV is written from).
template <class Row>
class Hdf5Table {
 public:
  // `name` is the table's name without extension: "orbits" is published as
  // DIR/orbits.h5. block_rows = 0: Hdf5Writer::DefaultBlockRows.
  Hdf5Table(const OutputDir& dir, const std::string& name, Columns<Row> columns, std::size_t block_rows = 0)
      : columns_(std::move(columns)), writer_(dir, name, Describe(columns_), block_rows) {}

  void Append(const Row& row) {
    for (std::size_t k = 0; k < columns_.size(); ++k) writer_.Set(k, CellOf(columns_[k], row));
    writer_.EndRow();
  }
  void Append(const std::vector<Row>& rows) {
    for (const Row& r : rows) Append(r);
  }
  // Writes what is buffered, closes and publishes NAME.h5; throws OutputError
  // on any failure (the temporary is removed then).
  void Commit() { writer_.Commit(); }

  const std::filesystem::path& path() const { return writer_.path(); }
  std::size_t rows() const { return writer_.rows(); }
  const Columns<Row>& columns() const { return columns_; }

 private:
  static std::vector<Hdf5Column> Describe(const Columns<Row>& columns) {
    std::vector<Hdf5Column> out;
    out.reserve(columns.size());
    for (const Column<Row>& c : columns) out.push_back({c.name, c.kind});
    return out;
  }
  Columns<Row> columns_;
  Hdf5Writer writer_;
};

// The format of a command's tables (--format): CSV, the default, or HDF5 for
// large work (one NAME.h5 a table, each column a dataset under its CSV name).
enum class TableFormat { kCsv, kHdf5 };
// "csv" or "hdf5"; throws InputError naming `field` and the text otherwise.
TableFormat ParseTableFormat(const std::string& text, const std::string& field = "--format");
// "orbits" -> "orbits.csv" or "orbits.h5".
std::string TableFileName(const std::string& table, TableFormat format);
// Both formats' names of each table: what OutputDir::Prepare removes (a run
// in one format leaves no older run's file of the other beside its own).
std::vector<std::string> TableFileNames(const std::vector<std::string>& tables);

// One table of a run, streamed row by row in the chosen format, complete or
// absent (ResultFile, Hdf5Table): the CSV and the HDF5 file hold the same
// columns from the one declaration (table.h).
template <class Row>
class TableWriter {
 public:
  TableWriter(const OutputDir& dir, const std::string& table, Columns<Row> columns, TableFormat format)
      : name_(TableFileName(table, format)) {
    if (format == TableFormat::kHdf5) {
      h5_.emplace(dir, table, std::move(columns));
    } else {
      columns_ = std::move(columns);
      csv_.emplace(dir, name_);
      WriteCsvHeader(csv_->stream(), columns_);
    }
  }
  void Append(const Row& row) {
    if (h5_) {
      h5_->Append(row);
    } else {
      WriteCsvRow(csv_->stream(), columns_, row);
    }
  }
  void Commit() {
    if (h5_) {
      h5_->Commit();
    } else {
      csv_->Commit();
    }
  }
  const std::string& file_name() const { return name_; }  // "orbits.csv" / "orbits.h5"

 private:
  std::string name_;
  Columns<Row> columns_;
  std::optional<ResultFile> csv_;
  std::optional<Hdf5Table<Row>> h5_;
};

// A whole table in the chosen format (WriteCsvFile's twin); returns its file name.
template <class Row>
std::string WriteTableFile(const OutputDir& dir, const std::string& table, const Columns<Row>& columns,
                           const std::vector<Row>& rows, TableFormat format) {
  TableWriter<Row> w(dir, table, columns, format);
  for (const Row& r : rows) w.Append(r);
  w.Commit();
  return w.file_name();
}

}  // namespace nsmodal::report
