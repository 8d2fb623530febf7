#include "nsmodal/hdf5.h"

#include "nsmodal/error.h"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <unistd.h>

#if H5_VERSION_GE(1, 13, 0)
#include <H5FDdevelop.h>  // H5FD_class_t and H5FD_t moved here in 1.13
#endif

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
#include <new>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace nsmodal::report {
namespace {

// --- The file driver ---------------------------------------------------------
// HDF5's POSIX driver (sec2) reports a failed write as a line of its error
// stack; this one, the same pread/pwrite driver in a few lines, keeps the
// errno where the call failed (as output.h's FileBuffer does) and counts its
// writes against FailWritesAfter's budget, so that an HDF5 table fails on a
// "full disk" exactly where a CSV would.
//
// A failed write (or truncation, or close) is recorded, not reported to
// HDF5: the driver answers success and writes nothing more to that file, and
// the writer checks the record after every HDF5 call, abandons the file and
// removes it. HDF5 1.10 does not survive its own I/O error paths: an H5Fclose
// whose flush failed leaves the file's id half released, and the library
// crashes on it when it closes at exit (or on a second H5Fclose).

// The first system error of the calling thread's current HDF5 operation
// (reset by Quiet below; HDF5 calls its driver on the calling thread).
struct SystemError {
  int error = 0;
  bool at_open = false;
};
thread_local SystemError system_error;

void Record(int error, bool at_open = false) {
  if (system_error.error != 0) return;
  system_error.error = error != 0 ? error : EIO;
  system_error.at_open = at_open;
}

struct PosixFile {
  H5FD_t pub;  // first: HDF5 sees a PosixFile* as its H5FD_t*
  int fd;
  haddr_t eoa;
  haddr_t eof;
  dev_t device;
  ino_t inode;
  bool failed;  // a write failed: nothing more is written
};

// Set while the writer abandons a file: its last writes are not made.
thread_local bool discarding = false;

PosixFile* Of(H5FD_t* f) { return reinterpret_cast<PosixFile*>(f); }
const PosixFile* Of(const H5FD_t* f) { return reinterpret_cast<const PosixFile*>(f); }

constexpr haddr_t kMaxAddress = static_cast<haddr_t>(std::numeric_limits<off_t>::max());
constexpr std::size_t kMaxIo = std::size_t{1} << 30;

bool OutOfRange(haddr_t addr, std::size_t size) {
  return addr == HADDR_UNDEF || addr > kMaxAddress || size > kMaxAddress - addr;
}

H5FD_t* DriverOpen(const char* name, unsigned flags, hid_t, haddr_t maxaddr) {
  if (name == nullptr || *name == '\0' || maxaddr == 0 || maxaddr == HADDR_UNDEF) return nullptr;
  int o = (flags & H5F_ACC_RDWR) ? O_RDWR : O_RDONLY;
  if (flags & H5F_ACC_TRUNC) o |= O_TRUNC;
  if (flags & H5F_ACC_CREAT) o |= O_CREAT;
  if (flags & H5F_ACC_EXCL) o |= O_EXCL;
  const int fd = ::open(name, o | O_CLOEXEC, 0644);
  if (fd < 0) {
    Record(errno, true);
    return nullptr;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    Record(errno, true);
    ::close(fd);
    return nullptr;
  }
  auto* f = new (std::nothrow) PosixFile{};
  if (f == nullptr) {
    Record(ENOMEM, true);
    ::close(fd);
    return nullptr;
  }
  // HDF5 first tries to open a file it creates without creating it (to find
  // it among the files it has open): that attempt's ENOENT is no failure.
  system_error = {};
  f->fd = fd;
  f->failed = false;
  f->eoa = 0;
  f->eof = static_cast<haddr_t>(st.st_size);
  f->device = st.st_dev;
  f->inode = st.st_ino;
  return &f->pub;
}

herr_t DriverClose(H5FD_t* file) {
  PosixFile* f = Of(file);
  if (::close(f->fd) != 0 && !f->failed && !discarding) Record(errno);  // recorded, not reported (above)
  delete f;
  return 0;
}

int DriverCompare(const H5FD_t* a, const H5FD_t* b) {
  const PosixFile* x = Of(a);
  const PosixFile* y = Of(b);
  if (x->device != y->device) return x->device < y->device ? -1 : 1;
  if (x->inode != y->inode) return x->inode < y->inode ? -1 : 1;
  return 0;
}

herr_t DriverQuery(const H5FD_t*, unsigned long* flags) {
  if (flags != nullptr) {
    *flags = H5FD_FEAT_AGGREGATE_METADATA | H5FD_FEAT_ACCUMULATE_METADATA | H5FD_FEAT_DATA_SIEVE |
             H5FD_FEAT_AGGREGATE_SMALLDATA | H5FD_FEAT_POSIX_COMPAT_HANDLE;
  }
  return 0;
}

haddr_t DriverGetEoa(const H5FD_t* file, H5FD_mem_t) { return Of(file)->eoa; }
herr_t DriverSetEoa(H5FD_t* file, H5FD_mem_t, haddr_t addr) {
  if (addr > kMaxAddress) return -1;
  Of(file)->eoa = addr;
  return 0;
}
haddr_t DriverGetEof(const H5FD_t* file, H5FD_mem_t) { return Of(file)->eof; }

herr_t DriverGetHandle(H5FD_t* file, hid_t, void** handle) {
  if (handle == nullptr) return -1;
  *handle = &Of(file)->fd;
  return 0;
}

herr_t DriverRead(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t addr, std::size_t size, void* buffer) {
  if (OutOfRange(addr, size)) return -1;
  auto* p = static_cast<char*>(buffer);
  while (size > 0) {
    const ssize_t n = ::pread(Of(file)->fd, p, std::min(size, kMaxIo), static_cast<off_t>(addr));
    if (n < 0) {
      if (errno == EINTR) continue;
      Record(errno);
      return -1;
    }
    if (n == 0) {  // past the end of the file: zeros, as HDF5 expects
      std::memset(p, 0, size);
      break;
    }
    p += n;
    addr += static_cast<haddr_t>(n);
    size -= static_cast<std::size_t>(n);
  }
  return 0;
}

// Writes all `size` bytes at `addr`; 0 or the errno.
int WriteAt(int fd, const char* p, std::size_t size, haddr_t addr) {
  while (size > 0) {
    std::size_t chunk = std::min(size, kMaxIo);
    const long budget = WriteBudgetLeft();
    if (budget >= 0) {
      if (budget == 0) return ENOSPC;
      chunk = std::min<std::size_t>(chunk, static_cast<std::size_t>(budget));
    }
    const ssize_t n = ::pwrite(fd, p, chunk, static_cast<off_t>(addr));
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno != 0 ? errno : EIO;
    }
    if (budget >= 0) FailWritesAfter(WriteBudgetLeft() - n);
    p += n;
    addr += static_cast<haddr_t>(n);
    size -= static_cast<std::size_t>(n);
  }
  return 0;
}

herr_t DriverWrite(H5FD_t* file, H5FD_mem_t, hid_t, haddr_t addr, std::size_t size, const void* buffer) {
  if (OutOfRange(addr, size)) return -1;
  PosixFile* f = Of(file);
  if (!f->failed && !discarding) {
    if (const int error = WriteAt(f->fd, static_cast<const char*>(buffer), size, addr); error != 0) {
      Record(error);  // recorded, not reported (above)
      f->failed = true;
    }
  }
  f->eof = std::max(f->eof, addr + size);
  return 0;
}

herr_t DriverTruncate(H5FD_t* file, hid_t, hbool_t) {
  PosixFile* f = Of(file);
  if (f->eoa == f->eof) return 0;
  if (!f->failed && !discarding && ::ftruncate(f->fd, static_cast<off_t>(f->eoa)) != 0) {
    Record(errno);  // recorded, not reported (above)
    f->failed = true;
  }
  f->eof = f->eoa;
  return 0;
}

// The driver's id, registered on first use (again if the library was closed).
hid_t Driver() {
  static std::mutex mutex;
  static hid_t id = -1;
  const std::lock_guard<std::mutex> lock(mutex);
  if (id >= 0 && H5Iget_type(id) == H5I_VFL) return id;
  H5FD_class_t c{};
#if H5_VERSION_GE(1, 13, 0)
  c.version = H5FD_CLASS_VERSION;
  c.value = static_cast<H5FD_class_value_t>(421);  // 256-511: drivers not registered with The HDF Group
#endif
  c.name = "nsmodal_posix";
  c.maxaddr = kMaxAddress;
  c.fc_degree = H5F_CLOSE_WEAK;
  c.open = DriverOpen;
  c.close = DriverClose;
  c.cmp = DriverCompare;
  c.query = DriverQuery;
  c.get_eoa = DriverGetEoa;
  c.set_eoa = DriverSetEoa;
  c.get_eof = DriverGetEof;
  c.get_handle = DriverGetHandle;
  c.read = DriverRead;
  c.write = DriverWrite;
  c.truncate = DriverTruncate;
  const H5FD_mem_t map[] = H5FD_FLMAP_DICHOTOMY;
  std::copy(std::begin(map), std::end(map), std::begin(c.fl_map));
  id = H5FDregister(&c);
  return id;
}

// --- Errors ---------------------------------------------------------------------

// HDF5's printing off (and the thread's system error cleared) for one
// operation of the writer; the caller's printing restored after.
class Quiet {
 public:
  Quiet() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    system_error = {};
  }
  Quiet(const Quiet&) = delete;
  Quiet& operator=(const Quiet&) = delete;
  ~Quiet() {
    H5Eclear2(H5E_DEFAULT);
    H5Eset_auto2(H5E_DEFAULT, func_, data_);
  }

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

herr_t CollectError(unsigned, const H5E_error2_t* e, void* data) {
  auto* out = static_cast<std::vector<std::string>*>(data);
  std::string line = e->func_name != nullptr ? e->func_name : "";
  if (e->desc != nullptr && *e->desc != '\0') line.append(line.empty() ? "" : ": ").append(e->desc);
  out->push_back(std::move(line));
  return 0;
}

// HDF5's account of the failure of `what`: the API call and the innermost cause.
std::string Hdf5Reason(const std::string& what) {
  std::vector<std::string> stack;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, CollectError, &stack);
  H5Eclear2(H5E_DEFAULT);
  std::string reason = "HDF5 " + what + " failed";
  if (!stack.empty()) reason += " (" + stack.back() + ")";
  return reason;
}

// An HDF5 id closed at scope exit (unless released).
class Id {
 public:
  Id() = default;
  Id(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  ~Id() {
    if (id_ >= 0) close_(id_);
  }
  hid_t get() const { return id_; }
  hid_t release() { return std::exchange(id_, -1); }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

std::logic_error Bug(const std::string& what) {
  return std::logic_error("internal error: " + what + "; please report it");
}

const char* KindName(ColumnKind k) {
  switch (k) {
    case ColumnKind::kReal: return "real";
    case ColumnKind::kInteger: return "integer";
    case ColumnKind::kBool: return "boolean";
    case ColumnKind::kText: return "text";
  }
  return "?";
}

const char* CellKindName(const Cell& c) {
  switch (c.index()) {
    case 0: return "a missing cell";
    case 1: return "a real";
    case 2: return "an integer";
    case 3: return "a boolean";
    default: return "text";
  }
}

constexpr const char* kMissingGroup = "missing";
constexpr std::size_t kMaxChunkRows = 1024;
constexpr const char* kConventions =
    "one dataset per column, named as in the CSV, in the order of the attribute 'columns'; "
    "real: float64, NaN where missing (a value is never NaN or inf); integer: int64, never missing; "
    "bool: enum FALSE=0/TRUE=1 over int8 (numpy bool in h5py), FALSE where missing and TRUE in missing/NAME, "
    "which exists only for a boolean column with a missing cell; text: UTF-8, empty where missing";

}  // namespace

// --- The writer ------------------------------------------------------------------

struct Hdf5Writer::Impl {
  // A column's dataset is opened for each block and closed after it: an open
  // dataset costs HDF5 some 17 KB more than a closed one (100 MB for the
  // 6,011 columns of a 1,000-mass orbits table), for about 10 us a block.
  struct Buffer {
    std::string name;
    ColumnKind kind = ColumnKind::kReal;
    bool has_mask = false;  // missing/NAME made (a boolean column with a missing cell)
    std::vector<double> reals;
    std::vector<std::int64_t> integers;
    std::vector<std::int8_t> bools, missing;
    std::vector<std::string> texts;
  };

  Impl(const OutputDir& d, const std::string& table_name) : dir(d), table(table_name) {}

  const OutputDir& dir;
  std::string table, file_name, temp_name;
  std::filesystem::path temp, final;
  std::vector<Buffer> columns;
  std::size_t block = 0;    // rows per block: a whole number of chunks
  std::size_t chunk = 0;    // rows per chunk
  std::size_t pending = 0;  // rows buffered
  std::size_t written = 0;  // rows in the file
  hid_t file = -1, bool_type = -1, text_type = -1, missing_group = -1, lcpl = -1;
  bool failed = false, committed = false;
  std::vector<const char*> text_pointers;

  // Closes every id (ignoring failures: the file is abandoned; its last
  // writes not made) and removes the temporary.
  void Abandon() {
    discarding = true;
    if (missing_group >= 0) H5Gclose(missing_group);
    if (bool_type >= 0) H5Tclose(bool_type);
    if (text_type >= 0) H5Tclose(text_type);
    if (lcpl >= 0) H5Pclose(lcpl);
    if (file >= 0) H5Fclose(file);
    missing_group = bool_type = text_type = lcpl = file = -1;
    discarding = false;
    std::error_code ec;
    std::filesystem::remove(temp, ec);
  }

  // The failure of the HDF5 call `what`: the file abandoned, OutputError.
  [[noreturn]] void Fail(const std::string& what) {
    const SystemError cause = system_error;
    std::string message;
    if (cause.error != 0) {
      message = (cause.at_open ? "cannot write '" + final.string() + "': "
                               : "writing '" + final.string() + "' failed: ") +
                std::strerror(cause.error);
      H5Eclear2(H5E_DEFAULT);
    } else {
      message = "writing '" + final.string() + "' failed: " + Hdf5Reason(what);
    }
    failed = true;
    Abandon();
    throw OutputError(message);
  }

  // The status of an HDF5 call, and the driver's record of the system's.
  template <class T>
  T Check(T status, const char* what) {
    if (status < 0 || system_error.error != 0) Fail(what);
    return status;
  }

  void CheckUsable() const {
    if (committed) throw Bug("the HDF5 table '" + final.string() + "' was used after its Commit()");
    if (failed) throw OutputError("'" + final.string() + "' was not written: an earlier write failed");
  }

  // A 1-D dataset of `type`, `size` rows, chunked, extendible.
  void CreateDataset(hid_t where, const std::string& name, hid_t type, std::size_t size, bool fill_zero) {
    const hsize_t dims = size, max_dims = H5S_UNLIMITED, chunk_dims = chunk;
    const Id space(Check(H5Screate_simple(1, &dims, &max_dims), "H5Screate_simple"), H5Sclose);
    const Id dcpl(Check(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate"), H5Pclose);
    Check(H5Pset_chunk(dcpl.get(), 1, &chunk_dims), "H5Pset_chunk");
    if (fill_zero) {
      // Rows before the dataset existed read as this (never written).
      const std::int8_t zero = 0;
      Check(H5Pset_fill_value(dcpl.get(), type, &zero), "H5Pset_fill_value");
    } else if (H5Tis_variable_str(type) <= 0) {
      // Every row is written: no fill at allocation (not allowed, and not
      // needed, for variable-length strings: their fill is a null pointer).
      Check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), "H5Pset_fill_time");
    }
    Id dataset(Check(H5Dcreate2(where, name.c_str(), type, space.get(), lcpl, dcpl.get(), H5P_DEFAULT), "H5Dcreate2"),
               H5Dclose);
    Check(H5Dclose(dataset.release()), "H5Dclose");
  }

  void WriteStringAttribute(const char* name, const std::vector<const char*>& values, bool scalar) {
    const hsize_t n = values.size();
    const Id space(Check(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr), "H5Screate"), H5Sclose);
    const Id attr(Check(H5Acreate2(file, name, text_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2"),
                  H5Aclose);
    Check(H5Awrite(attr.get(), text_type, values.data()), "H5Awrite");
  }

  void Open(std::vector<Hdf5Column> specs) {
    for (std::size_t k = 0; k < specs.size(); ++k) {
      const std::string& n = specs[k].name;
      if (n.empty() || n == "." || n.find('/') != std::string::npos) {
        throw Bug("column '" + n + "' of table " + table + " cannot name an HDF5 dataset");
      }
      if (n == kMissingGroup) throw Bug("column 'missing' of table " + table + " is the HDF5 group of missing cells");
      for (std::size_t j = 0; j < k; ++j) {
        if (specs[j].name == n) throw Bug("table " + table + " has two columns named '" + n + "'");
      }
    }
    file_name = Hdf5FileName(table);
    temp_name = "." + file_name + ".partial";
    temp = dir.path() / temp_name;
    final = dir.path() / file_name;

    const Id fcpl(Check(H5Pcreate(H5P_FILE_CREATE), "H5Pcreate"), H5Pclose);
    // h5py lists the datasets in creation order: the CSV's.
    Check(H5Pset_link_creation_order(fcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED),
          "H5Pset_link_creation_order");
    const Id fapl(Check(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate"), H5Pclose);
    Check(H5Pset_driver(fapl.get(), Check(Driver(), "H5FDregister"), nullptr), "H5Pset_driver");
    Check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V18), "H5Pset_libver_bounds");
    Check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), "H5Pset_fclose_degree");
    // No chunk cache: a block is whole chunks, written straight to the file,
    // so memory stays one block.
    Check(H5Pset_cache(fapl.get(), 0, 1, 0, 1.0), "H5Pset_cache");
    file = Check(H5Fcreate(temp.c_str(), H5F_ACC_TRUNC, fcpl.get(), fapl.get()), "H5Fcreate");

    lcpl = Check(H5Pcreate(H5P_LINK_CREATE), "H5Pcreate");
    Check(H5Pset_char_encoding(lcpl, H5T_CSET_UTF8), "H5Pset_char_encoding");
    bool_type = Check(H5Tenum_create(H5T_NATIVE_INT8), "H5Tenum_create");
    const std::int8_t no = 0, yes = 1;
    Check(H5Tenum_insert(bool_type, "FALSE", &no), "H5Tenum_insert");
    Check(H5Tenum_insert(bool_type, "TRUE", &yes), "H5Tenum_insert");
    text_type = Check(H5Tcopy(H5T_C_S1), "H5Tcopy");
    Check(H5Tset_size(text_type, H5T_VARIABLE), "H5Tset_size");
    Check(H5Tset_cset(text_type, H5T_CSET_UTF8), "H5Tset_cset");

    std::vector<const char*> names;
    columns.resize(specs.size());
    for (std::size_t k = 0; k < specs.size(); ++k) {
      Buffer& b = columns[k];
      b.name = std::move(specs[k].name);
      b.kind = specs[k].kind;
      names.push_back(b.name.c_str());
      hid_t type = -1;
      switch (b.kind) {
        case ColumnKind::kReal:
          b.reals.resize(block);
          type = H5T_IEEE_F64LE;
          break;
        case ColumnKind::kInteger:
          b.integers.resize(block);
          type = H5T_STD_I64LE;
          break;
        case ColumnKind::kBool:
          b.bools.resize(block);
          b.missing.resize(block);
          type = bool_type;
          break;
        case ColumnKind::kText:
          b.texts.resize(block);
          type = text_type;
          break;
      }
      CreateDataset(file, b.name, type, 0, false);
    }
    const std::vector<const char*> table_name{table.c_str()};
    WriteStringAttribute("table", table_name, true);
    WriteStringAttribute("columns", names, false);
    WriteStringAttribute("conventions", {kConventions}, true);
  }

  // Rows [written, written + pending) of the dataset `name` from `data`.
  void WriteRows(hid_t where, const std::string& name, hid_t mem_type, hid_t mem_space, const void* data) {
    const hsize_t start = written, count = pending, size = written + pending;
    Id dataset(Check(H5Dopen2(where, name.c_str(), H5P_DEFAULT), "H5Dopen2"), H5Dclose);
    Check(H5Dset_extent(dataset.get(), &size), "H5Dset_extent");
    {
      const Id file_space(Check(H5Dget_space(dataset.get()), "H5Dget_space"), H5Sclose);
      Check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &start, nullptr, &count, nullptr),
            "H5Sselect_hyperslab");
      Check(H5Dwrite(dataset.get(), mem_type, mem_space, file_space.get(), H5P_DEFAULT, data), "H5Dwrite");
    }
    Check(H5Dclose(dataset.release()), "H5Dclose");
  }

  void Flush() {
    if (pending == 0) return;
    const hsize_t count = pending;
    const Id mem_space(Check(H5Screate_simple(1, &count, nullptr), "H5Screate_simple"), H5Sclose);
    for (Buffer& b : columns) {
      switch (b.kind) {
        case ColumnKind::kReal: WriteRows(file, b.name, H5T_NATIVE_DOUBLE, mem_space.get(), b.reals.data()); break;
        case ColumnKind::kInteger:
          WriteRows(file, b.name, H5T_NATIVE_INT64, mem_space.get(), b.integers.data());
          break;
        case ColumnKind::kBool: {
          WriteRows(file, b.name, bool_type, mem_space.get(), b.bools.data());
          const bool any_missing = std::any_of(b.missing.begin(), b.missing.begin() + pending,
                                               [](std::int8_t m) { return m != 0; });
          if (any_missing && !b.has_mask) {
            if (missing_group < 0) {
              missing_group = Check(H5Gcreate2(file, kMissingGroup, lcpl, H5P_DEFAULT, H5P_DEFAULT), "H5Gcreate2");
            }
            CreateDataset(missing_group, b.name, bool_type, written, true);
            b.has_mask = true;
          }
          if (b.has_mask) WriteRows(missing_group, b.name, bool_type, mem_space.get(), b.missing.data());
          break;
        }
        case ColumnKind::kText:
          text_pointers.resize(pending);
          for (std::size_t i = 0; i < pending; ++i) text_pointers[i] = b.texts[i].c_str();
          WriteRows(file, b.name, text_type, mem_space.get(), text_pointers.data());
          break;
      }
    }
    written += pending;
    pending = 0;
  }

  void Close() {
    if (missing_group >= 0) Check(H5Gclose(std::exchange(missing_group, -1)), "H5Gclose");
    Check(H5Tclose(std::exchange(bool_type, -1)), "H5Tclose");
    Check(H5Tclose(std::exchange(text_type, -1)), "H5Tclose");
    Check(H5Pclose(std::exchange(lcpl, -1)), "H5Pclose");
    // Flushes the metadata, truncates to the end of the data, closes (a
    // failed write recorded, the file released all the same). Not tried
    // again if it fails anyway: a second H5Fclose crashes 1.10.
    Check(H5Fclose(std::exchange(file, -1)), "H5Fclose");
  }
};

std::size_t Hdf5Writer::DefaultBlockRows(std::size_t columns) {
  const std::size_t budget = std::size_t{8} << 20;
  return std::clamp<std::size_t>(budget / (8 * std::max<std::size_t>(columns, 1)), 256, 65536);
}

Hdf5Writer::Hdf5Writer(const OutputDir& dir, const std::string& table, std::vector<Hdf5Column> columns,
                       std::size_t block_rows)
    : impl_(std::make_unique<Impl>(dir, table)) {
  // Chunks of at most kMaxChunkRows, a block a whole number of them: the
  // last chunk, partly filled, takes a whole chunk on disk.
  const std::size_t block = block_rows > 0 ? block_rows : DefaultBlockRows(columns.size());
  const std::size_t chunks = (block + kMaxChunkRows - 1) / kMaxChunkRows;
  impl_->chunk = (block + chunks - 1) / chunks;
  impl_->block = impl_->chunk * chunks;
  const Quiet quiet;
  try {
    impl_->Open(std::move(columns));
  } catch (...) {
    impl_->Abandon();
    throw;
  }
}

Hdf5Writer::Hdf5Writer(Hdf5Writer&&) noexcept = default;

Hdf5Writer::~Hdf5Writer() {
  if (!impl_ || impl_->committed) return;
  const Quiet quiet;
  impl_->Abandon();
}

void Hdf5Writer::Set(std::size_t column, Cell cell) {
  Impl& w = *impl_;
  w.CheckUsable();
  if (column >= w.columns.size()) {
    throw Bug("column " + std::to_string(column) + " of the HDF5 table " + w.table + " does not exist");
  }
  Impl::Buffer& b = w.columns[column];
  const std::size_t i = w.pending;
  auto mismatch = [&] {
    return Bug("the " + std::string(KindName(b.kind)) + " column " + b.name + " of table " + w.table + " holds " +
               CellKindName(cell));
  };
  switch (b.kind) {
    case ColumnKind::kReal:
      if (const double* v = std::get_if<double>(&cell)) {
        if (!std::isfinite(*v)) throw Bug("column " + b.name + " holds " + (std::isnan(*v) ? "nan" : "inf") + " as a value");
        b.reals[i] = *v;
      } else if (std::holds_alternative<std::monostate>(cell)) {
        b.reals[i] = std::numeric_limits<double>::quiet_NaN();
      } else {
        throw mismatch();
      }
      break;
    case ColumnKind::kInteger:
      if (const long* v = std::get_if<long>(&cell)) {
        b.integers[i] = *v;
      } else if (std::holds_alternative<std::monostate>(cell)) {
        throw Bug("the integer column " + b.name + " of table " + w.table +
                  " has a missing cell (a count that may be missing is declared real)");
      } else {
        throw mismatch();
      }
      break;
    case ColumnKind::kBool:
      if (const bool* v = std::get_if<bool>(&cell)) {
        b.bools[i] = *v ? 1 : 0;
        b.missing[i] = 0;
      } else if (std::holds_alternative<std::monostate>(cell)) {
        b.bools[i] = 0;
        b.missing[i] = 1;
      } else {
        throw mismatch();
      }
      break;
    case ColumnKind::kText:
      if (std::string* s = std::get_if<std::string>(&cell)) {
        b.texts[i] = std::move(*s);
      } else if (std::holds_alternative<std::monostate>(cell)) {
        b.texts[i].clear();
      } else {
        throw mismatch();
      }
      break;
  }
}

void Hdf5Writer::EndRow() {
  Impl& w = *impl_;
  w.CheckUsable();
  if (++w.pending < w.block) return;
  const Quiet quiet;
  w.Flush();
}

void Hdf5Writer::Commit() {
  Impl& w = *impl_;
  w.CheckUsable();
  {
    const Quiet quiet;
    w.Flush();
    w.Close();
  }
  w.failed = true;  // until published: Publish removes the temporary when it throws
  w.dir.Publish(w.temp_name, w.file_name);
  w.failed = false;
  w.committed = true;
}

const std::filesystem::path& Hdf5Writer::path() const { return impl_->final; }
std::size_t Hdf5Writer::rows() const { return impl_->written + impl_->pending; }
std::size_t Hdf5Writer::block_rows() const { return impl_->block; }

TableFormat ParseTableFormat(const std::string& text, const std::string& field) {
  if (text == "csv") return TableFormat::kCsv;
  if (text == "hdf5") return TableFormat::kHdf5;
  throw InputError(field, "must be csv or hdf5, got '" + text + "'");
}

std::string TableFileName(const std::string& table, TableFormat format) {
  return format == TableFormat::kHdf5 ? Hdf5FileName(table) : table + ".csv";
}

std::vector<std::string> TableFileNames(const std::vector<std::string>& tables) {
  std::vector<std::string> names;
  for (const std::string& t : tables) {
    names.push_back(TableFileName(t, TableFormat::kCsv));
    names.push_back(TableFileName(t, TableFormat::kHdf5));
  }
  return names;
}

}  // namespace nsmodal::report
