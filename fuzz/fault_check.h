#pragma once
// The fault fuzzer's rule (fuzz_faults.cc), shared with its deterministic
// replay in the test suite (tests/fault_replay.cc).
#include <string>
#include <vector>

namespace nsmodal::fault {

struct Case {
  std::vector<std::string> args;     // after "nsmodal", before --out
  std::vector<std::string> results;  // the files a finished run writes
};

// Short commands on the shipped scenes (NSMODAL_SOURCE_DIR/configs).
const std::vector<Case>& Cases();

struct Run {
  int status = -1;
  long bytes_written = 0;  // through the result files, counted by the budget
  long polls = 0;          // stop polls made (counted when a stop is armed)
};

// Runs `c` in-process into a fresh directory with every write after `budget`
// bytes failing (negative: none) and `signal` requested at poll `poll`
// (0: none), then checks (traps, naming the run, when broken): a documented
// exit status; nothing left in the directory unless the run ended with a
// verdict (0, 3, 4); then every result present and no temporary.
Run RunAndCheck(const Case& c, long budget, long poll, int signal);

}  // namespace nsmodal::fault
