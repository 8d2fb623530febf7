#include "nsmodal/output.h"

#include <fnmatch.h>

#include <cerrno>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <system_error>

#include "nsmodal/error.h"

namespace nsmodal::report {
namespace {

std::string Reason() { return errno != 0 ? std::strerror(errno) : "unknown error"; }

bool Matches(const std::string& name, const std::vector<std::string>& patterns) {
  for (const std::string& p : patterns) {
    if (fnmatch(p.c_str(), name.c_str(), FNM_PERIOD) == 0) return true;
  }
  // Leftovers of an interrupted run (FNM_PERIOD off: they start with a dot).
  return name.size() > 9 && name.front() == '.' && name.ends_with(".partial");
}

}  // namespace

OutputDir OutputDir::Prepare(const std::string& path, const std::vector<std::string>& owned,
                             const std::string& field) {
  if (path.empty()) throw InputError(field, "is empty");
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) throw InputError(field, "cannot create directory '" + path + "': " + ec.message());
  if (!fs::is_directory(path, ec)) throw InputError(field, "'" + path + "' is not a directory");
  // Writable: a probe file created and removed.
  const fs::path probe = fs::path(path) / ".nsmodal-write-probe.partial";
  {
    std::ofstream p(probe);
    p << "probe";
    p.close();
    if (p.fail()) {
      const std::string reason = Reason();
      fs::remove(probe, ec);
      throw InputError(field, "cannot write in '" + path + "': " + reason);
    }
  }
  fs::remove(probe, ec);
  for (const fs::directory_entry& e : fs::directory_iterator(path, ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file(ec) && Matches(name, owned)) {
      fs::remove(e.path(), ec);
      if (ec) throw InputError(field, "cannot remove the previous result '" + e.path().string() + "': " + ec.message());
    }
  }
  if (ec) throw InputError(field, "cannot list '" + path + "': " + ec.message());
  return OutputDir(fs::path(path));
}

std::string OutputDir::Describe(const std::string& name) const { return (path_ / name).string(); }

ResultFile::ResultFile(const OutputDir& dir, const std::string& name)
    : temp_(dir.path() / ("." + name + ".partial")), final_(dir.path() / name) {
  errno = 0;
  out_.open(temp_);
  if (!out_) throw OutputError("cannot write '" + final_.string() + "': " + Reason());
  out_ << std::setprecision(17);
}

ResultFile::~ResultFile() {
  if (committed_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(temp_, ec);
}

void ResultFile::Commit() {
  errno = 0;
  out_.flush();
  const bool written = static_cast<bool>(out_);
  out_.close();
  if (!written || out_.fail()) {
    const std::string reason = Reason();
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
    throw OutputError("writing '" + final_.string() + "' failed: " + reason);
  }
  std::error_code ec;
  std::filesystem::rename(temp_, final_, ec);
  if (ec) {
    std::filesystem::remove(temp_, ec);
    throw OutputError("cannot rename the finished '" + final_.string() + "': " + ec.message());
  }
  committed_ = true;
}

void WriteResult(const OutputDir& dir, const std::string& name, const std::string& text) {
  ResultFile f(dir, name);
  f << text;
  f.Commit();
}

void CheckStdout() {
  errno = 0;
  std::cout.flush();
  if (!std::cout) throw OutputError("writing to standard output failed: " + Reason());
}

}  // namespace nsmodal::report
