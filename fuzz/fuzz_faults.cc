// libFuzzer target: faults in the middle of real commands. Each input picks a
// short command on a shipped scene, a number of bytes after which every write
// fails with ENOSPC (output.h's FailWritesAfter, as on a full disk) and a poll
// at which a SIGINT or SIGTERM is requested (stop.h's RequestStopAtPoll, as if
// the signal arrived there). The command runs in-process; then:
// - its exit status is a documented one (0 done, 2 bad input, 3 simulation
//   stopped, 4 validation failed, 5 a result not written, 130 / 143 stopped);
// - a run that did not end with a verdict (any status but 0, 3, 4) leaves
//   nothing in its output directory: no result, no temporary;
// - a run that did keeps every result it names and no temporary.
// Charts are left out (gnuplot would be a process per input): their
// completeness check has its own test (tests/cli_fault_test.sh).
#include <unistd.h>

#include <climits>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "command_line.h"
#include "fault_check.h"
#include "nsmodal/output.h"
#include "nsmodal/stop.h"

namespace nsmodal::fault {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void Fail(const std::string& what, const std::string& log) {
  std::fprintf(stderr, "fault check: %s\n--- the command's messages ---\n%s\n", what.c_str(), log.c_str());
  __builtin_trap();
}

}  // namespace

const std::vector<Case>& Cases() {
  const std::string configs = NSMODAL_SOURCE_DIR "/configs/";
  static const std::vector<Case> cases{
      {{"orbits", configs + "paper.toml", "--impacts", "1", "--period", "1:8:0.25", "--threads", "1"},
       {"orbits.csv", "transitions.csv"}},
      {{"orbits", configs + "paper.toml", "--impacts", "2", "--period", "3:6:0.5", "--threads", "1"}, {"orbits.csv"}},
      {{"simulate", configs + "paper-simulate.toml", "--t-end", "40", "--sample-dt", "0.5"},
       {"trajectory.csv", "impacts.csv", "summary.json"}},
      {{"simulate", configs + "forced.toml", "--t-end", "60", "--sample-dt", "1"},
       {"trajectory.csv", "impacts.csv", "summary.json"}},
      {{"validate", configs + "paper.toml", "--period", "4:7.5:0.5", "--impacts", "1", "--periods", "20", "--threads",
        "1"},
       {"validation.csv", "summary.json"}},
  };
  return cases;
}

Run RunAndCheck(const Case& c, long budget, long poll, int signal) {
  static const fs::path out = fs::temp_directory_path() / ("nsmodal-fault-check-" + std::to_string(getpid()));
  std::error_code ec;
  fs::remove_all(out, ec);
  std::vector<std::string> args{"nsmodal"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  args.push_back("--out");
  args.push_back(out.string());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());

  // The command's messages are kept for a failure report, not printed.
  std::ostringstream log;
  std::streambuf* cout_buf = std::cout.rdbuf(log.rdbuf());
  std::streambuf* cerr_buf = std::cerr.rdbuf(log.rdbuf());
  // Unarmed, the budget and the countdown still count (from a huge start).
  const long kHuge = LONG_MAX / 4;
  report::FailWritesAfter(budget >= 0 ? budget : kHuge);
  ClearStopRequest();
  RequestStopAtPoll(poll > 0 ? poll : kHuge, signal);
  Run r;
  {
    cli::CommandLine cl;
    cl.app.parse(static_cast<int>(argv.size()), argv.data());
    r.status = cl.Run();
  }
  r.bytes_written = (budget >= 0 ? budget : kHuge) - report::WriteBudgetLeft();
  r.polls = (poll > 0 ? poll : kHuge) - internal::stop_countdown.load();
  report::FailWritesAfter(-1);
  ClearStopRequest();
  std::cout.rdbuf(cout_buf);
  std::cerr.rdbuf(cerr_buf);
  std::cout.clear();
  std::cerr.clear();

  const std::string what = "'" + args[1] + " " + args[2] + "', write budget " + std::to_string(budget) +
                           (poll > 0 ? ", stop at poll " + std::to_string(poll) : "") + ": exit " +
                           std::to_string(r.status);
  const int s = r.status;
  if (s != 0 && s != 2 && s != 3 && s != 4 && s != 5 && s != 128 + SIGINT && s != 128 + SIGTERM) {
    Fail(what + " is not a documented exit status", log.str());
  }
  const bool verdict = s == 0 || s == 3 || s == 4;
  for (const fs::directory_entry& e : fs::directory_iterator(out, ec)) {
    const std::string name = e.path().filename().string();
    if (!verdict) Fail(what + " left " + name, log.str());
    if (name.front() == '.') Fail(what + " left the temporary " + name, log.str());
  }
  if (verdict) {
    for (const std::string& name : c.results) {
      if (!fs::is_regular_file(out / name)) Fail(what + " but " + name + " is missing", log.str());
    }
  }
  fs::remove_all(out, ec);
  return r;
}

}  // namespace nsmodal::fault

namespace {

unsigned Read(const std::uint8_t* data, std::size_t size, std::size_t at, int bytes) {
  unsigned v = 0;
  for (int i = 0; i < bytes; ++i) v = v << 8 | (at + i < size ? data[at + i] : 0u);
  return v;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using nsmodal::fault::Cases;
  // Byte 0: the case. Byte 1: the write budget's scale (8: no budget);
  // bytes 2-3: its mantissa (0 to 16 MB, most inputs within the first
  // kilobytes where the tables are written). Byte 4: 0 no stop, else bytes
  // 5-6 the poll (1 to 65,536) and byte 4's parity the signal.
  const nsmodal::fault::Case& c = Cases()[Read(data, size, 0, 1) % Cases().size()];
  const unsigned scale = Read(data, size, 1, 1) % 9;
  const long budget = scale == 8 ? -1 : static_cast<long>(Read(data, size, 2, 2)) << scale;
  const unsigned stop = Read(data, size, 4, 1);
  const long poll = stop == 0 ? 0 : static_cast<long>(Read(data, size, 5, 2)) + 1;
  nsmodal::fault::RunAndCheck(c, budget, poll, stop % 2 ? SIGINT : SIGTERM);
  return 0;
}
