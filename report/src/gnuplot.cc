#include "nsmodal/gnuplot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>
#include <utility>
#include <vector>

#include "nsmodal/check.h"
#include "nsmodal/stop.h"
#include "nsmodal/style.h"

extern char** environ;

namespace nsmodal::report {
namespace {

bool IsPlainName(const std::string& name) {
  if (name.empty()) return false;
  for (char ch : name) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
                    ch == '-' || ch == '.';
    if (!ok) return false;
  }
  return name.front() != '.';
}

// Runs argv[0] (searched on PATH) in `cwd` with stdout and stderr to the file
// `log_name` in `cwd`, and waits. Returns "" on exit status 0, else what went
// wrong.
std::string Run(const std::vector<std::string>& argv, const std::filesystem::path& cwd,
                const std::string& log_name) {
  const std::filesystem::path log = cwd / log_name;
  // The log is opened after the chdir: its name is relative to cwd (a
  // relative cwd joined to it would point nowhere from there).
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_name.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    return rc == ENOENT ? argv[0] + " not found on PATH, or " + log.string() + " cannot be created"
                        : "cannot start " + argv[0] + ": " + std::strerror(rc);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return "waiting for " + argv[0] + ": " + std::strerror(errno);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) return argv[0] + " could not be run (see " + log.string() + ")";
  return argv[0] + " failed (see " + log.string() + ")";
}

// Whether the image gnuplot wrote ends as its format ends: gnuplot exits 0
// when cairo's writes fail on a full disk, leaving a truncated file. PNG: the
// IEND chunk (its length, type and CRC, 12 fixed bytes); PDF: "%%EOF"; SVG:
// "</svg>" (each followed at most by line ends).
std::string IncompleteImage(const std::filesystem::path& path, const std::string& ext) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return "gnuplot wrote no " + path.filename().string() + ": " + ec.message();
  static const std::string kPngEnd("\0\0\0\0IEND\xae\x42\x60\x82", 12);
  const std::string end = ext == "png" ? kPngEnd : ext == "svg" ? "</svg>" : "%%EOF";
  std::ifstream in(path, std::ios::binary);
  const std::uintmax_t tail = std::min<std::uintmax_t>(size, 64);
  in.seekg(static_cast<std::streamoff>(size - tail));
  std::string last(tail, '\0');
  in.read(last.data(), static_cast<std::streamsize>(tail));
  if (!in) return "cannot read back " + path.string();
  if (ext != "png") {
    while (!last.empty() && (last.back() == '\n' || last.back() == '\r')) last.pop_back();
  }
  if (last.size() < end.size() || last.compare(last.size() - end.size(), end.size(), end) != 0) {
    return "gnuplot's " + ext + " image is incomplete (" + std::to_string(size) +
           " bytes, no end marker): was the disk full?";
  }
  return "";
}

}  // namespace

ChartStatus DrawChart(const OutputDir& dir, const std::string& name, const std::string& body, double aspect) {
  NSMODAL_CHECK(IsPlainName(name));
  ThrowIfStopRequested();  // between charts: a signal ends the set here (stop.h)
  // PNG and SVG for the screen; PDF for print, vector, at the final size
  // (the PNG's aspect) of a 17 cm page width and of an 8.5 cm journal column
  // (NAME.column.pdf), each sized and scaled by report/style.toml.
  for (const style::Format& f : style::Formats()) {
    const std::string& ext = f.extension;
    const std::string image = name + "." + ext, script = image + ".gp", temp = "." + image + ".partial";
    // The image name is a variable so that the run below can draw under a
    // temporary name while the script, rerun by hand, draws NAME.EXT.
    WriteResult(dir, script,
                "set terminal " + f.Terminal(aspect) + "\nif (!exists('nsmodal_output')) nsmodal_output = '" + image +
                    "'\nset output nsmodal_output\n" + style::ChartSetup(f) + body + "\n");
    const std::string log = script + ".log";
    std::string error = Run({"gnuplot", "-e", "nsmodal_output='" + temp + "'", script}, dir.path(), log);
    // A signal that reached gnuplot too (Ctrl-C reaches the whole process
    // group) is the user's stop, not gnuplot's failure.
    std::error_code ec;
    if (StopRequested()) {
      std::filesystem::remove(dir.path() / temp, ec);
      std::filesystem::remove(dir.path() / log, ec);
    }
    ThrowIfStopRequested();
    const std::string format = ext == "column.pdf" ? "pdf" : ext;
    if (error.empty()) error = IncompleteImage(dir.path() / temp, format);
    if (!error.empty()) {
      std::filesystem::remove(dir.path() / temp, ec);
      // The log is kept for the reader of the message, unless it is empty.
      if (std::filesystem::is_empty(dir.path() / log, ec) && !ec) std::filesystem::remove(dir.path() / log, ec);
      return {false, error};
    }
    try {
      dir.Publish(temp, image);
    } catch (const OutputError& e) {
      return {false, e.what()};
    }
    std::filesystem::remove(dir.path() / log, ec);
  }
  return {true, ""};
}

}  // namespace nsmodal::report
