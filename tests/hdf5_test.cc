// HDF5 tables (hdf5.h, issue 25): the HDF5 file of a table holds what its CSV
// holds, value by value, read back through HDF5's C API (and through h5py);
// a failed or abandoned write leaves no result.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cmath>
#include <complex>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "nsmodal/hdf5.h"
#include "nsmodal/output.h"
#include "nsmodal/table.h"
#include "nsmodal/tables.h"

namespace nsmodal {
namespace {

namespace fs = std::filesystem;
using report::Cell;
using report::ColumnKind;
using report::Columns;

// --- Scratch directories and files ------------------------------------------------

fs::path Scratch() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path p = fs::temp_directory_path() /
                     ("nsmodal-hdf5-test-" + std::to_string(::getpid()) + "-" + info->name());
  fs::remove_all(p);
  return p;
}

std::vector<std::string> Listing(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string ReadText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

int OpenDescriptors() {
  int n = 0;
  for ([[maybe_unused]] const fs::directory_entry& e : fs::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

// FailWritesAfter disarmed at scope exit, whatever happens.
struct BudgetGuard {
  ~BudgetGuard() { report::FailWritesAfter(-1); }
};

// --- CSV (RFC 4180) --------------------------------------------------------------

std::vector<std::vector<std::string>> ParseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record;
  std::string field;
  bool quoted = false, in_record = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    in_record = true;
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      record.push_back(std::move(field));
      field.clear();
    } else if (c == '\n') {
      record.push_back(std::move(field));
      field.clear();
      records.push_back(std::move(record));
      record.clear();
      in_record = false;
    } else {
      field += c;
    }
  }
  if (in_record) {
    record.push_back(std::move(field));
    records.push_back(std::move(record));
  }
  return records;
}

// --- HDF5 reading (C API) ----------------------------------------------------------

struct H5Id {
  hid_t id;
  herr_t (*close)(hid_t);
  ~H5Id() {
    if (id >= 0) close(id);
  }
};

std::vector<std::string> ReadStrings(hid_t obj, hid_t space, bool attribute) {
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<char*> raw(static_cast<std::size_t>(n), nullptr);
  H5Id type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, H5T_VARIABLE);
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  const herr_t status = attribute ? H5Aread(obj, type.id, raw.data())
                                  : H5Dread(obj, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data());
  EXPECT_GE(status, 0);
  std::vector<std::string> out;
  for (char* s : raw) out.emplace_back(s != nullptr ? s : "");
  if (n > 0) {
#if H5_VERSION_GE(1, 12, 0)
    H5Treclaim(type.id, space, H5P_DEFAULT, raw.data());
#else
    H5Dvlen_reclaim(type.id, space, H5P_DEFAULT, raw.data());
#endif
  }
  return out;
}

std::vector<std::string> StringAttribute(hid_t file, const char* name) {
  H5Id attr{H5Aopen(file, name, H5P_DEFAULT), H5Aclose};
  EXPECT_GE(attr.id, 0) << name;
  if (attr.id < 0) return {};
  H5Id space{H5Aget_space(attr.id), H5Sclose};
  return ReadStrings(attr.id, space.id, true);
}

bool Exists(hid_t file, const std::string& path) {
  std::string prefix;
  std::stringstream ss(path);
  std::string part;
  while (std::getline(ss, part, '/')) {
    prefix += (prefix.empty() ? "" : "/") + part;
    if (H5Lexists(file, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return true;
}

// One column of the file, whatever its type.
struct H5Column {
  H5T_class_t type_class = H5T_NO_CLASS;
  std::vector<double> reals;
  std::vector<std::int64_t> integers;
  std::vector<std::int8_t> bools;
  std::vector<std::string> texts;
  std::size_t size = 0;
};

H5Column ReadColumn(hid_t file, const std::string& name) {
  H5Column c;
  H5Id ds{H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose};
  EXPECT_GE(ds.id, 0) << name;
  if (ds.id < 0) return c;
  H5Id space{H5Dget_space(ds.id), H5Sclose};
  c.size = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space.id));
  H5Id type{H5Dget_type(ds.id), H5Tclose};
  c.type_class = H5Tget_class(type.id);
  switch (c.type_class) {
    case H5T_FLOAT:
      c.reals.resize(c.size);
      EXPECT_GE(H5Dread(ds.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.reals.data()), 0);
      break;
    case H5T_INTEGER:
      c.integers.resize(c.size);
      EXPECT_GE(H5Dread(ds.id, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.integers.data()), 0);
      break;
    case H5T_ENUM: {
      c.bools.resize(c.size);
      H5Id native{H5Tget_native_type(type.id, H5T_DIR_ASCEND), H5Tclose};
      EXPECT_EQ(H5Tget_size(native.id), 1u) << name;
      EXPECT_GE(H5Dread(ds.id, native.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.bools.data()), 0);
      break;
    }
    case H5T_STRING: c.texts = ReadStrings(ds.id, space.id, false); break;
    default: ADD_FAILURE() << name << ": unexpected type class " << c.type_class;
  }
  return c;
}

// H5Literate's callback: the names of a group's links, in the order asked for.
template <class LinkInfo>
herr_t CollectLink(hid_t, const char* name, const LinkInfo*, void* data) {
  static_cast<std::vector<std::string>*>(data)->push_back(name);
  return 0;
}

bool SameDouble(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The file `h5` holds what the CSV text `csv` holds: the same columns in the
// same order (attribute "columns"), the same rows, each value the same
// (reals to the bit, 17 significant digits being exact; empty fields missing).
void ExpectHoldsTheCsv(const fs::path& h5, const std::string& csv, const std::string& table) {
  const std::vector<std::vector<std::string>> records = ParseCsv(csv);
  ASSERT_FALSE(records.empty());
  const std::vector<std::string>& header = records.front();
  const std::size_t rows = records.size() - 1;
  H5Id file{H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  ASSERT_GE(file.id, 0) << h5;
  EXPECT_EQ(StringAttribute(file.id, "columns"), header);
  EXPECT_EQ(StringAttribute(file.id, "table"), std::vector<std::string>{table});
  for (std::size_t k = 0; k < header.size(); ++k) {
    const std::string& name = header[k];
    SCOPED_TRACE("column " + name);
    const H5Column c = ReadColumn(file.id, name);
    ASSERT_EQ(c.size, rows);
    std::vector<std::int8_t> missing(rows, 0);
    const bool has_mask = Exists(file.id, "missing/" + name);
    if (has_mask) {
      EXPECT_EQ(c.type_class, H5T_ENUM) << "a mask beside a column that is not boolean";
      const H5Column m = ReadColumn(file.id, "missing/" + name);
      ASSERT_EQ(m.size, rows);
      missing = m.bools;
    }
    for (std::size_t i = 0; i < rows; ++i) {
      ASSERT_EQ(records[i + 1].size(), header.size()) << "CSV row " << i;
      const std::string& field = records[i + 1][k];
      SCOPED_TRACE("row " + std::to_string(i) + ", CSV field '" + field + "'");
      switch (c.type_class) {
        case H5T_FLOAT:
          if (field.empty()) {
            EXPECT_TRUE(std::isnan(c.reals[i]));
          } else {
            EXPECT_TRUE(SameDouble(c.reals[i], std::strtod(field.c_str(), nullptr))) << c.reals[i];
          }
          break;
        case H5T_INTEGER: EXPECT_EQ(std::to_string(c.integers[i]), field); break;
        case H5T_ENUM:
          if (field.empty()) {
            EXPECT_EQ(missing[i], 1);
            EXPECT_EQ(c.bools[i], 0) << "FALSE where missing";
          } else {
            EXPECT_EQ(missing[i], 0);
            EXPECT_EQ(std::to_string(c.bools[i]), field);
          }
          break;
        case H5T_STRING: EXPECT_EQ(c.texts[i], field); break;
        default: FAIL();
      }
    }
  }
}

// --- Tables -----------------------------------------------------------------------

// Every kind of column, and every way of being missing.
struct Mixed {
  double x = 0.0;
  std::optional<double> y;
  long n = 0;
  bool flag = false;
  std::optional<bool> maybe;
  std::string text;
  std::optional<std::string> note;
};

Columns<Mixed> MixedColumns() {
  return {{"x", ColumnKind::kReal, [](const Mixed& r) -> Cell { return r.x; }},
          {"y", ColumnKind::kReal, [](const Mixed& r) { return report::Real(r.y); }},
          {"n", ColumnKind::kInteger, [](const Mixed& r) -> Cell { return r.n; }},
          {"flag", ColumnKind::kBool, [](const Mixed& r) -> Cell { return r.flag; }},
          {"maybe", ColumnKind::kBool, [](const Mixed& r) { return r.maybe ? Cell(*r.maybe) : Cell(); }},
          {"text", ColumnKind::kText, [](const Mixed& r) -> Cell { return r.text; }},
          {"note", ColumnKind::kText, [](const Mixed& r) { return r.note ? Cell(*r.note) : Cell(); }}};
}

std::vector<Mixed> MixedRows() {
  const double big = std::numeric_limits<double>::max();
  const std::vector<std::string> texts{"plain", "a,b", "say \"hi\"", "line\nbreak", "crlf\r\nend",
                                       "ünïcödé ∑ 🎵", "", " spaced ", "\"", ",", "日本語,\"x\""};
  std::vector<Mixed> rows;
  for (int i = 0; i < 11; ++i) {
    Mixed r;
    const double values[] = {0.1, -0.0, 4.9e-324, big, -1e300, M_PI, 1.0 / 3.0, 0.0, 1e-17, 123456789.125, -2.5};
    r.x = values[i];
    if (i % 3 != 1) r.y = std::exp(0.37 * i) - 2.0;
    const long ints[] = {0, -1, 1, LONG_MAX, LONG_MIN, 42, -42, 7, 1000000007, 3, -3};
    r.n = ints[i];
    r.flag = i % 2 == 0;
    // Missing only from the second block of 4 on: missing/maybe made then.
    if (i < 5 || i == 9) r.maybe = i % 3 == 0;
    r.text = texts[i];
    if (i % 4 != 2) r.note = "note " + std::to_string(i);
    rows.push_back(r);
  }
  return rows;
}

// `rows` written as NAME.csv (ResultFile, as the commands write it) and as
// NAME.h5, appended in groups of `group` (as a sweep hands its blocks over);
// returns the CSV's text.
template <class Row>
std::string WriteBoth(const report::OutputDir& dir, const std::string& name, const Columns<Row>& columns,
                      const std::vector<Row>& rows, std::size_t block_rows, std::size_t group) {
  report::ResultFile csv(dir, name + ".csv");
  report::WriteCsvHeader(csv.stream(), columns);
  report::Hdf5Table<Row> h5(dir, name, columns, block_rows);
  for (std::size_t i = 0; i < rows.size(); i += group) {
    const std::vector<Row> part(rows.begin() + i, rows.begin() + std::min(rows.size(), i + group));
    for (const Row& r : part) report::WriteCsvRow(csv.stream(), columns, r);
    h5.Append(part);
  }
  EXPECT_EQ(h5.rows(), rows.size());
  csv.Commit();
  h5.Commit();
  EXPECT_EQ(h5.path(), dir.path() / (name + ".h5"));
  return ReadText(dir.path() / (name + ".csv"));
}

TEST(Hdf5Table, HoldsWhatTheCsvHolds) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"mixed.csv", "mixed.h5"});
  // 11 rows in blocks of 4 (two full chunks and a partial one), handed over 3 at a time.
  const std::string csv = WriteBoth(dir, "mixed", MixedColumns(), MixedRows(), 4, 3);
  EXPECT_EQ(Listing(d), (std::vector<std::string>{"mixed.csv", "mixed.h5"}));
  ExpectHoldsTheCsv(d / "mixed.h5", csv, "mixed");

  // The missing masks: only for the boolean column that has a missing cell,
  // FALSE in the rows written before it was made.
  H5Id file{H5Fopen((d / "mixed.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  EXPECT_TRUE(Exists(file.id, "missing/maybe"));
  EXPECT_FALSE(Exists(file.id, "missing/flag"));
  const H5Column mask = ReadColumn(file.id, "missing/maybe");
  EXPECT_EQ(mask.bools, (std::vector<std::int8_t>{0, 0, 0, 0, 0, 1, 1, 1, 1, 0, 1}));
  fs::remove_all(d);
}

TEST(Hdf5Table, LayoutForReaders) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"mixed.h5"});
  {
    report::Hdf5Table<Mixed> t(dir, "mixed", MixedColumns(), 4);
    t.Append(MixedRows());
    t.Commit();
  }
  H5Id file{H5Fopen((d / "mixed.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  ASSERT_GE(file.id, 0);
  const std::vector<std::string> names{"x", "y", "n", "flag", "maybe", "text", "note"};
  EXPECT_EQ(StringAttribute(file.id, "columns"), names);
  EXPECT_EQ(StringAttribute(file.id, "table"), std::vector<std::string>{"mixed"});
  const std::vector<std::string> conventions = StringAttribute(file.id, "conventions");
  ASSERT_EQ(conventions.size(), 1u);
  EXPECT_NE(conventions[0].find("NaN where missing"), std::string::npos);

  // Datasets listed in creation order: the CSV's, then the group of masks.
  std::vector<std::string> listed;
#if H5_VERSION_GE(1, 12, 0)
  H5Literate2(file.id, H5_INDEX_CRT_ORDER, H5_ITER_INC, nullptr, CollectLink<H5L_info2_t>, &listed);
#else
  H5Literate(file.id, H5_INDEX_CRT_ORDER, H5_ITER_INC, nullptr, CollectLink<H5L_info_t>, &listed);
#endif
  std::vector<std::string> expected = names;
  expected.push_back("missing");
  EXPECT_EQ(listed, expected);

  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    H5Id ds{H5Dopen2(file.id, name.c_str(), H5P_DEFAULT), H5Dclose};
    H5Id type{H5Dget_type(ds.id), H5Tclose};
    H5Id space{H5Dget_space(ds.id), H5Sclose};
    hsize_t dims = 0, max_dims = 0, chunk = 0;
    ASSERT_EQ(H5Sget_simple_extent_ndims(space.id), 1);
    H5Sget_simple_extent_dims(space.id, &dims, &max_dims);
    EXPECT_EQ(dims, 11u);
    EXPECT_EQ(max_dims, H5S_UNLIMITED);
    H5Id dcpl{H5Dget_create_plist(ds.id), H5Pclose};
    EXPECT_EQ(H5Pget_layout(dcpl.id), H5D_CHUNKED);
    EXPECT_EQ(H5Pget_chunk(dcpl.id, 1, &chunk), 1);
    EXPECT_EQ(chunk, 4u);
    EXPECT_EQ(H5Pget_nfilters(dcpl.id), 0);
    if (name == "x" || name == "y") {
      EXPECT_GT(H5Tequal(type.id, H5T_IEEE_F64LE), 0);
    } else if (name == "n") {
      EXPECT_GT(H5Tequal(type.id, H5T_STD_I64LE), 0);
    } else if (name == "flag" || name == "maybe") {
      // h5py's bool: an enum over int8 of exactly FALSE = 0, TRUE = 1.
      ASSERT_EQ(H5Tget_class(type.id), H5T_ENUM);
      H5Id base{H5Tget_super(type.id), H5Tclose};
      EXPECT_GT(H5Tequal(base.id, H5T_NATIVE_INT8), 0);
      ASSERT_EQ(H5Tget_nmembers(type.id), 2);
      for (int m = 0; m < 2; ++m) {
        char* member = H5Tget_member_name(type.id, static_cast<unsigned>(m));
        std::int8_t value = -1;
        H5Tget_member_value(type.id, static_cast<unsigned>(m), &value);
        EXPECT_STREQ(member, value == 0 ? "FALSE" : "TRUE");
        EXPECT_TRUE(value == 0 || value == 1);
        H5free_memory(member);
      }
    } else {
      ASSERT_EQ(H5Tget_class(type.id), H5T_STRING);
      EXPECT_GT(H5Tis_variable_str(type.id), 0);
      EXPECT_EQ(H5Tget_cset(type.id), H5T_CSET_UTF8);
    }
  }
  fs::remove_all(d);
}

hsize_t ChunkRows(const fs::path& h5, const std::string& column) {
  H5Id file{H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  H5Id ds{H5Dopen2(file.id, column.c_str(), H5P_DEFAULT), H5Dclose};
  H5Id dcpl{H5Dget_create_plist(ds.id), H5Pclose};
  hsize_t chunk = 0;
  EXPECT_EQ(H5Pget_chunk(dcpl.id, 1, &chunk), 1);
  return chunk;
}

// Blocks are whole chunks of at most 1,024 rows: a small table of few
// columns (a block of 65,536 rows) takes a chunk per column on disk, not a
// block; a block of 3,000 rows is 3 chunks of 1,000.
TEST(Hdf5Table, BlocksAreWholeChunks) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"*.csv", "*.h5"});
  const std::vector<Transition> small{{4.834, TransitionKind::kSingular, std::numeric_limits<double>::infinity()},
                                      {9.127, TransitionKind::kGrazing, 0.61}};
  EXPECT_EQ(report::Hdf5Writer::DefaultBlockRows(3), 65536u);
  ExpectHoldsTheCsv(d / "transitions.h5", WriteBoth(dir, "transitions", report::TransitionColumns(), small, 0, 2),
                    "transitions");
  EXPECT_EQ(ChunkRows(d / "transitions.h5", "T"), 1024u);
  EXPECT_LT(fs::file_size(d / "transitions.h5"), 64u * 1024u);

  EXPECT_EQ(report::Hdf5Writer(dir, "blocks", {{"x", ColumnKind::kReal}}, 3000).block_rows(), 3000u);
  EXPECT_EQ(report::Hdf5Writer(dir, "blocks", {{"x", ColumnKind::kReal}}, 1025).block_rows(), 1026u);
  std::vector<Mixed> rows;
  for (int k = 0; k < 320; ++k) {
    for (Mixed r : MixedRows()) {
      r.x += k;
      rows.push_back(r);
    }
  }
  ExpectHoldsTheCsv(d / "mixed.h5", WriteBoth(dir, "mixed", MixedColumns(), rows, 3000, 700), "mixed");
  EXPECT_EQ(ChunkRows(d / "mixed.h5", "x"), 1000u);
  fs::remove_all(d);
}

TEST(Hdf5Table, EmptyTableKeepsItsColumns) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"empty.csv", "empty.h5"});
  const std::string csv = WriteBoth(dir, "empty", MixedColumns(), std::vector<Mixed>{}, 0, 1);
  EXPECT_EQ(csv, "x,y,n,flag,maybe,text,note\n");
  ExpectHoldsTheCsv(d / "empty.h5", csv, "empty");
  fs::remove_all(d);
}

TEST(Hdf5Table, NotCommittedLeavesNothing) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"mixed.h5"});
  const int descriptors = OpenDescriptors();
  {
    report::Hdf5Table<Mixed> t(dir, "mixed", MixedColumns(), 4);
    t.Append(MixedRows());  // two blocks written, three rows buffered
    EXPECT_EQ(Listing(d), std::vector<std::string>{".mixed.h5.partial"});
  }
  EXPECT_TRUE(Listing(d).empty());
  EXPECT_EQ(OpenDescriptors(), descriptors);
  fs::remove_all(d);
}

// A run unwound by an exception after the table was committed: its
// OutputDir removes the table (all or nothing, output.h).
TEST(Hdf5Table, UnwoundRunRemovesItsTable) {
  const fs::path d = Scratch();
  try {
    const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"mixed.h5"});
    report::Hdf5Table<Mixed> t(dir, "mixed", MixedColumns());
    t.Append(MixedRows());
    t.Commit();
    EXPECT_TRUE(fs::is_regular_file(d / "mixed.h5"));
    throw std::runtime_error("a later failure of the run");
  } catch (const std::runtime_error&) {
  }
  EXPECT_TRUE(Listing(d).empty());
  fs::remove_all(d);
}

// The bytes an HDF5 table of `rows` writes (the write budget's count).
long BytesWritten(const report::OutputDir& dir, const std::vector<Mixed>& rows) {
  const BudgetGuard guard;
  const long huge = LONG_MAX / 4;
  report::FailWritesAfter(huge);
  report::Hdf5Table<Mixed> t(dir, "mixed", MixedColumns(), 4);
  t.Append(rows);
  t.Commit();
  return huge - report::WriteBudgetLeft();
}

// A full disk (output.h's write budget: every write past it fails with
// ENOSPC), wherever it strikes: at the creation, in a block, at the close.
TEST(Hdf5Table, FullDiskLeavesNoFile) {
  const fs::path d = Scratch();
  std::vector<Mixed> rows;
  for (int k = 0; k < 20; ++k) {
    for (const Mixed& r : MixedRows()) rows.push_back(r);
  }
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"mixed.h5"});
  const long total = BytesWritten(dir, rows);
  ASSERT_GT(total, 1000);
  fs::remove(d / "mixed.h5");
  const int descriptors = OpenDescriptors();
  const std::string expected = "'" + (d / "mixed.h5").string() + "' failed: " + std::strerror(ENOSPC);
  std::vector<long> budgets{0, 1, 96, 800, total - 200, total - 1};
  for (long k = 1; k < 40; ++k) budgets.push_back(total * k / 40);
  for (const long budget : budgets) {
    SCOPED_TRACE("budget " + std::to_string(budget) + " of " + std::to_string(total));
    const BudgetGuard guard;
    report::FailWritesAfter(budget);
    try {
      report::Hdf5Table<Mixed> t(dir, "mixed", MixedColumns(), 4);
      t.Append(rows);
      t.Commit();
      ADD_FAILURE() << "no failure";
    } catch (const report::OutputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    EXPECT_TRUE(Listing(d).empty());
    EXPECT_EQ(OpenDescriptors(), descriptors);
  }
  // Exactly enough: written.
  {
    const BudgetGuard guard;
    report::FailWritesAfter(total);
    report::Hdf5Table<Mixed> t(dir, "mixed", MixedColumns(), 4);
    t.Append(rows);
    t.Commit();
    EXPECT_EQ(report::WriteBudgetLeft(), 0);
  }
  EXPECT_EQ(Listing(d), std::vector<std::string>{"mixed.h5"});
  fs::remove_all(d);
}

// A write the system refuses (a file-size limit: EFBIG, as root gets on a
// full file system) names the file and the system's reason.
TEST(Hdf5Table, SystemWriteFailureNamesTheReason) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"mixed.h5"});
  std::vector<Mixed> rows;
  for (int k = 0; k < 50; ++k) {
    for (const Mixed& r : MixedRows()) rows.push_back(r);
  }
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old), 0);
  void (*old_handler)(int) = std::signal(SIGXFSZ, SIG_IGN);
  std::string message;
  {
    rlimit small = old;
    small.rlim_cur = 4096;
    ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
    try {
      report::Hdf5Table<Mixed> t(dir, "mixed", MixedColumns(), 4);
      t.Append(rows);
      t.Commit();
    } catch (const report::OutputError& e) {
      message = e.what();
    }
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, old_handler);
  }
  EXPECT_EQ(message, "writing '" + (d / "mixed.h5").string() + "' failed: " + std::strerror(EFBIG));
  EXPECT_TRUE(Listing(d).empty());
  fs::remove_all(d);
}

// A directory that went away after Prepare: the file cannot be created.
TEST(Hdf5Table, UncreatableFileNamesTheReason) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"mixed.h5"});
  fs::remove_all(d);
  try {
    report::Hdf5Table<Mixed> t(dir, "mixed", MixedColumns());
    FAIL() << "created";
  } catch (const report::OutputError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write '" + (d / "mixed.h5").string() + "': " + std::strerror(ENOENT));
  }
  EXPECT_FALSE(fs::exists(d));
}

// A table declared wrongly is nsmodal's bug: std::logic_error, and no file.
TEST(Hdf5Table, DeclarationBugsAreLogicErrors) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"bad.h5"});
  using W = report::Hdf5Writer;
  using K = ColumnKind;
  for (const std::string& name : {std::string(), std::string("."), std::string("a/b"), std::string("missing")}) {
    EXPECT_THROW(W(dir, "bad", {{"x", K::kReal}, {name, K::kReal}}), std::logic_error) << "'" << name << "'";
  }
  EXPECT_THROW(W(dir, "bad", {{"x", K::kReal}, {"x", K::kInteger}}), std::logic_error);
  EXPECT_TRUE(Listing(d).empty());
  {
    W w(dir, "bad", {{"r", K::kReal}, {"i", K::kInteger}, {"b", K::kBool}, {"s", K::kText}});
    EXPECT_THROW(w.Set(0, Cell(std::numeric_limits<double>::quiet_NaN())), std::logic_error);
    EXPECT_THROW(w.Set(0, Cell(std::numeric_limits<double>::infinity())), std::logic_error);
    EXPECT_THROW(w.Set(0, Cell(1L)), std::logic_error);
    EXPECT_THROW(w.Set(1, Cell()), std::logic_error);  // a count that may be missing is real
    EXPECT_THROW(w.Set(1, Cell(1.0)), std::logic_error);
    EXPECT_THROW(w.Set(2, Cell(1L)), std::logic_error);
    EXPECT_THROW(w.Set(3, Cell(true)), std::logic_error);
    EXPECT_THROW(w.Set(4, Cell(1.0)), std::logic_error);
    // A row left unfinished by the exception is overwritten by the next.
    w.Set(0, Cell(1.5));
    w.Set(1, Cell(2L));
    w.Set(2, Cell());
    w.Set(3, Cell());
    w.EndRow();
    EXPECT_EQ(w.rows(), 1u);
  }
  EXPECT_TRUE(Listing(d).empty());
  fs::remove_all(d);
}

// --- The project's tables --------------------------------------------------------

OrbitRecord Record(int dofs, int impacts, double period, int stability) {
  OrbitRecord r;
  r.orbit.impacts = impacts;
  r.orbit.period = period;
  if (impacts == 2) r.orbit.times = {0.37 * period};
  r.orbit.z0 = Eigen::VectorXd::LinSpaced(2 * dofs, -1.0, 1.0) * period;
  r.orbit.energy = 0.5 * period * period;
  r.orbit.potential = stability > 0;
  r.orbit.admissible = stability == 1;
  r.orbit.periodicity_residual = 1e-15 * period;
  r.orbit.nc2_residual = 3e-16;
  r.orbit.max_excess = stability == 2 ? -std::numeric_limits<double>::infinity() : -0.01 * period;
  if (stability > 0) {
    Stability s;
    // 1: every multiplier; 2: a verdict-only spectrum (two located).
    const int located = stability == 1 ? 2 * dofs : 2;
    s.multipliers.resize(located);
    for (int k = 0; k < located; ++k) s.multipliers[k] = std::polar(1.0 + 0.01 * k, 0.3 * k);
    s.max_modulus = std::abs(s.multipliers[0]);
    s.stable = stability == 1;
    r.stability = s;
  }
  return r;
}

TEST(Hdf5Table, ProjectTablesHoldWhatTheirCsvHolds) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"*.csv", "*.h5"});
  {
    std::vector<OrbitRecord> rows;
    for (int i = 0; i < 30; ++i) rows.push_back(Record(3, i % 5 == 4 ? 2 : 1, 0.5 + 0.25 * i, i % 3));
    ExpectHoldsTheCsv(d / "orbits.h5", WriteBoth(dir, "orbits", report::OrbitColumns(3), rows, 8, 7), "orbits");
  }
  {
    std::vector<report::Sample> rows;
    for (int i = 0; i < 25; ++i) rows.push_back({0.1 * i, Eigen::VectorXd::Constant(4, std::sin(0.1 * i)), 0.5});
    ExpectHoldsTheCsv(d / "trajectory.h5", WriteBoth(dir, "trajectory", report::TrajectoryColumns(2), rows, 0, 1),
                      "trajectory");
  }
  {
    std::vector<ContactEvent> rows;
    for (int i = 0; i < 9; ++i) {
      rows.push_back({1.0 * i, Eigen::VectorXd::Constant(4, 0.5 * i), Eigen::VectorXd::Constant(4, -0.5 * i)});
    }
    ExpectHoldsTheCsv(d / "impacts.h5", WriteBoth(dir, "impacts", report::ImpactColumns(2), rows, 4, 1), "impacts");
  }
  {
    const std::vector<Transition> rows{{4.834, TransitionKind::kSingular, std::numeric_limits<double>::infinity()},
                                       {9.127, TransitionKind::kGrazing, 0.61}};
    ExpectHoldsTheCsv(d / "transitions.h5", WriteBoth(dir, "transitions", report::TransitionColumns(), rows, 0, 2),
                      "transitions");
  }
  {
    std::vector<OrbitValidation> rows(3);
    rows[0].orbit.period = 7.5;
    rows[0].deviation = {1e-12, 2e-12};
    rows[0].consistent = true;
    rows[1].orbit.period = 4.0;
    rows[1].orbit.times = {1.5};
    rows[1].integrator = Integrator::kCvode;
    rows[1].impact_time_error = 1e-9;
    rows[1].reason = "grew x1e3, over 10 periods: \"unstable\"";
    rows[2].perturbed_periods = 12;
    ExpectHoldsTheCsv(d / "validation.h5", WriteBoth(dir, "validation", report::ValidationColumns(), rows, 2, 2),
                      "validation");
  }
  fs::remove_all(d);
}

// The orbits table of a 1,000-mass sweep: 6,011 columns, their names an
// attribute larger than an object header's 64 KiB.
TEST(Hdf5Table, ThousandMassOrbitsTable) {
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"orbits.csv", "orbits.h5"});
  std::vector<OrbitRecord> rows;
  for (int i = 0; i < 3; ++i) rows.push_back(Record(1000, 1, 3.0 + i, i == 1 ? 2 : 0));
  const std::string csv = WriteBoth(dir, "orbits", report::OrbitColumns(1000), rows, 0, 2);
  ExpectHoldsTheCsv(d / "orbits.h5", csv, "orbits");
  fs::remove_all(d);
}

// h5py (Debian's /usr/bin/python3) reads the file back into the CSV's text,
// byte for byte: the types are the ones h5py maps to float64, int64, bool
// and str, and the attribute "columns" gives the order (h5py 3.7 lists a
// group's members by name, whatever order the group tracks).
// Runs a program with its arguments, no shell between (a path is an
// argument, never a command); its output to /dev/null when `quiet`. Returns
// its exit status, -1 when it could not run.
int RunProgram(const std::vector<std::string>& args, bool quiet = false) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  }
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

TEST(Hdf5Table, H5pyRebuildsTheCsv) {
  if (RunProgram({"/usr/bin/python3", "-c", "import h5py"}, true) != 0) GTEST_SKIP() << "no h5py";
  const fs::path d = Scratch();
  const report::OutputDir dir = report::OutputDir::Prepare(d.string(), {"*.csv", "*.h5", "*.py", "*.out"});
  std::vector<OrbitRecord> orbits;
  for (int i = 0; i < 10; ++i) orbits.push_back(Record(2, 1, 1.0 + i, i % 3));
  WriteBoth(dir, "orbits", report::OrbitColumns(2), orbits, 4, 3);
  WriteBoth(dir, "mixed", MixedColumns(), MixedRows(), 4, 3);
  report::WriteResult(dir, "rebuild.py", R"(import sys, h5py, numpy as np
def field(v):
    if isinstance(v, bytes): v = v.decode("utf-8")
    if isinstance(v, str):
        return '"' + v.replace('"', '""') + '"' if any(c in v for c in ',"\n\r') else v
    if isinstance(v, (bool, np.bool_)): return "1" if v else "0"
    if isinstance(v, (int, np.integer)): return str(int(v))
    return "" if np.isnan(v) else "%.17g" % v
f = h5py.File(sys.argv[1], "r")
cols = [str(c) for c in f.attrs["columns"]]
assert set(f) - {"missing"} == set(cols), list(f)
data = {}
for c in cols:
    a = f[c][()]
    kind = {"f": np.float64, "i": np.int64, "b": np.bool_, "O": object}[a.dtype.kind]
    assert a.dtype == kind or kind is object, (c, a.dtype)
    cells = [field(v) for v in a]
    if "missing" in f and c in f["missing"]:
        assert a.dtype == np.bool_
        cells = ["" if m else x for m, x in zip(f["missing"][c][()], cells)]
    data[c] = cells
n = len(data[cols[0]]) if cols else 0
with open(sys.argv[2], "w", newline="") as out:
    out.write(",".join(cols) + "\n")
    for i in range(n):
        out.write(",".join(data[c][i] for c in cols) + "\n")
)");
  for (const std::string name : {"orbits", "mixed"}) {
    SCOPED_TRACE(name);
    const std::vector<std::string> command{"/usr/bin/python3", (d / "rebuild.py").string(),
                                           (d / (name + ".h5")).string(), (d / (name + ".out")).string()};
    ASSERT_EQ(RunProgram(command), 0) << command[1];
    EXPECT_EQ(ReadText(d / (name + ".out")), ReadText(d / (name + ".csv")));
  }
  fs::remove_all(d);
}

}  // namespace
}  // namespace nsmodal
