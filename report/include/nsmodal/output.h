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
// Every failed write throws OutputError naming the file and the system's reason.
#include <filesystem>
#include <fstream>
#include <ostream>
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

  const std::filesystem::path& path() const { return path_; }
  std::string Describe(const std::string& name) const;  // "DIR/NAME", for messages

 private:
  explicit OutputDir(std::filesystem::path p) : path_(std::move(p)) {}
  std::filesystem::path path_;
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
  std::filesystem::path temp_, final_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes `text` to DIR/NAME through a ResultFile.
void WriteResult(const OutputDir& dir, const std::string& name, const std::string& text);

// Throws OutputError if standard output has failed (a closed pipe, a full
// disk behind a redirection): a command whose result is its printout has not
// produced it.
void CheckStdout();

}  // namespace nsmodal::report
