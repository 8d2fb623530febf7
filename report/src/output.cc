#include "nsmodal/output.h"

#include <fcntl.h>
#include <fnmatch.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <exception>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <system_error>

#include "nsmodal/error.h"

namespace nsmodal::report {
namespace {

std::string Reason(int error) { return error != 0 ? std::strerror(error) : "unknown error"; }
std::string Reason() { return Reason(errno); }

// FailWritesAfter's budget: bytes left before writes fail (negative: no limit).
std::atomic<long> write_budget{-1};

// write(2) of all `size` bytes (a short write is continued); 0 or the errno.
int WriteAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    std::size_t chunk = size;
    const long budget = write_budget.load(std::memory_order_relaxed);
    if (budget >= 0) {
      if (budget == 0) return ENOSPC;
      chunk = std::min<std::size_t>(chunk, static_cast<std::size_t>(budget));
      write_budget.fetch_sub(static_cast<long>(chunk), std::memory_order_relaxed);
    }
    const ssize_t n = ::write(fd, data, chunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno != 0 ? errno : EIO;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return 0;
}

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
    FileBuffer p(probe);
    if (!p.Close()) {
      const std::string reason = Reason(p.error());
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

OutputDir::OutputDir(std::filesystem::path p)
    : path_(std::move(p)),
      published_(std::make_unique<std::vector<std::filesystem::path>>()),
      exceptions_at_prepare_(std::uncaught_exceptions()) {}

OutputDir::~OutputDir() {
  if (!published_ || std::uncaught_exceptions() <= exceptions_at_prepare_) return;
  for (const std::filesystem::path& p : *published_) {
    std::error_code ec;
    std::filesystem::remove(p, ec);
  }
}

std::string OutputDir::Describe(const std::string& name) const { return (path_ / name).string(); }

void OutputDir::Publish(const std::string& temp, const std::string& name) const {
  std::error_code ec;
  const std::filesystem::path final = path_ / name;
  std::filesystem::rename(path_ / temp, final, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(path_ / temp, ignored);
    throw OutputError("cannot rename the finished '" + final.string() + "': " + ec.message());
  }
  published_->push_back(final);
}

FileBuffer::FileBuffer(const std::filesystem::path& path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) error_ = errno != 0 ? errno : EIO;
  setp(buffer_, buffer_ + sizeof buffer_);
}

FileBuffer::~FileBuffer() {
  if (fd_ >= 0) ::close(fd_);
}

bool FileBuffer::Drain() {
  if (error_ == 0 && pptr() > pbase()) error_ = WriteAll(fd_, pbase(), static_cast<std::size_t>(pptr() - pbase()));
  setp(buffer_, buffer_ + sizeof buffer_);
  return error_ == 0;
}

FileBuffer::int_type FileBuffer::overflow(int_type ch) {
  if (!Drain()) return traits_type::eof();
  if (!traits_type::eq_int_type(ch, traits_type::eof())) {
    *pptr() = traits_type::to_char_type(ch);
    pbump(1);
  }
  return traits_type::not_eof(ch);
}

int FileBuffer::sync() { return Drain() ? 0 : -1; }

bool FileBuffer::Close() {
  Drain();
  if (fd_ >= 0) {
    if (::close(fd_) != 0 && error_ == 0) error_ = errno != 0 ? errno : EIO;
    fd_ = -1;
  }
  return error_ == 0;
}

void FailWritesAfter(long bytes) { write_budget.store(bytes, std::memory_order_relaxed); }
long WriteBudgetLeft() { return write_budget.load(std::memory_order_relaxed); }

ResultFile::ResultFile(const OutputDir& dir, const std::string& name)
    : dir_(dir),
      name_(name),
      temp_(dir.path() / ("." + name + ".partial")),
      final_(dir.path() / name),
      buffer_(temp_),
      out_(&buffer_) {
  if (buffer_.error() != 0) throw OutputError("cannot write '" + final_.string() + "': " + Reason(buffer_.error()));
  out_ << std::setprecision(17);
}

ResultFile::~ResultFile() {
  if (committed_) return;
  buffer_.Close();
  std::error_code ec;
  std::filesystem::remove(temp_, ec);
}

void ResultFile::Commit() {
  out_.flush();
  const bool written = static_cast<bool>(out_);
  if (!buffer_.Close() || !written) {
    // The stream's own failures (a bad formatting state) carry no errno.
    const std::string reason = buffer_.error() != 0 ? Reason(buffer_.error()) : "the stream failed";
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
    throw OutputError("writing '" + final_.string() + "' failed: " + reason);
  }
  dir_.Publish(temp_.filename().string(), name_);
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
