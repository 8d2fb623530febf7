#pragma once
// Result files that are complete or absent.
//
// A run writes into an OutputDir prepared before any work: the directory is
// created, checked writable, and the results a previous run of the same
// command left there are removed, so a refused or failed run never leaves an
// older run's files beside its own. Each result is a ResultFile: written under
// a hidden temporary name (".NAME.partial") and renamed to NAME only by
// Commit(), after the stream's state and the close have been checked. A
// ResultFile destroyed without Commit() (an exception, a refused input)
// removes its temporary; a killed process leaves only the ".partial" file,
// which no reader takes for a result and the next Prepare() removes.
// A run is all or nothing: an OutputDir destroyed by an exception (a failed
// write, a refused input found late, a signal's Stopped) removes the results
// its run had already committed, so a failed command leaves no result file of
// its own. (A run that ends with a verdict, a simulation stopped at its step
// limit or a failed validation, returns normally and keeps its results.)
// Every failed write throws OutputError naming the file and the system's
// reason (the errno of the write that failed, taken where it failed).
#include <filesystem>
#include <memory>
#include <ostream>
#include <streambuf>
#include <stdexcept>
#include <string>
#include <vector>

namespace nsmodal::report {

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OutputDir {
 public:
  // Creates `path` (and its parents), checks that a file can be written in it,
  // and removes the files whose names match one of `owned` (fnmatch patterns
  // such as "orbits.csv" or "fig*.png") and stale ".*.partial" temporaries.
  // `field` names the option the path came from, for the error message.
  static OutputDir Prepare(const std::string& path, const std::vector<std::string>& owned,
                           const std::string& field = "--out");
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;
  OutputDir(OutputDir&&) = default;
  // Destroyed while an exception unwinds (more in flight than when it was
  // prepared): removes every result committed through it.
  ~OutputDir();

  const std::filesystem::path& path() const { return path_; }
  std::string Describe(const std::string& name) const;  // "DIR/NAME", for messages
  // Moves the finished DIR/TEMP to DIR/NAME and records NAME as this run's
  // result; throws OutputError (TEMP removed) when the rename fails.
  void Publish(const std::string& temp, const std::string& name) const;

 private:
  explicit OutputDir(std::filesystem::path p);
  std::filesystem::path path_;
  std::unique_ptr<std::vector<std::filesystem::path>> published_;  // results of this run
  int exceptions_at_prepare_ = 0;
};

// A file written through write(2), keeping the errno of the first write that
// failed (std::ofstream keeps only a fail bit, and errno may be overwritten
// by the time it is read: the "unknown error" of a full disk).
class FileBuffer : public std::streambuf {
 public:
  explicit FileBuffer(const std::filesystem::path& path);  // errno() != 0 when the open failed
  FileBuffer(const FileBuffer&) = delete;
  FileBuffer& operator=(const FileBuffer&) = delete;
  ~FileBuffer() override;
  // Writes what is buffered and closes; false on any failure (see error()).
  bool Close();
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override;
  int sync() override;

 private:
  bool Drain();
  int fd_ = -1;
  int error_ = 0;
  char buffer_[1 << 16];
};

class ResultFile {
 public:
  // Opens DIR/.NAME.partial; doubles are written with 17 significant digits.
  ResultFile(const OutputDir& dir, const std::string& name);
  ResultFile(const ResultFile&) = delete;
  ResultFile& operator=(const ResultFile&) = delete;
  ~ResultFile();

  std::ostream& stream() { return out_; }
  template <class T>
  ResultFile& operator<<(const T& value) {
    out_ << value;
    return *this;
  }
  // Flushes, closes and renames to NAME; throws OutputError on any failure
  // (the temporary is removed then).
  void Commit();
  // The final path.
  const std::filesystem::path& path() const { return final_; }

 private:
  const OutputDir& dir_;
  std::string name_;
  std::filesystem::path temp_, final_;
  FileBuffer buffer_;
  std::ostream out_;
  bool committed_ = false;
};

// Test hook (the fault fuzzer, the tests): every write after `bytes` more
// bytes fails with ENOSPC, as on a full disk; a negative value disarms it.
void FailWritesAfter(long bytes);
// What is left of that budget (negative when disarmed).
long WriteBudgetLeft();

// Writes `text` to DIR/NAME through a ResultFile.
void WriteResult(const OutputDir& dir, const std::string& name, const std::string& text);

// Throws OutputError if standard output has failed (a closed pipe, a full
// disk behind a redirection): a command whose result is its printout has not
// produced it.
void CheckStdout();

}  // namespace nsmodal::report
