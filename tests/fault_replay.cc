// The fault fuzzer's rule (fuzz/fault_check.h) run deterministically in the
// test suite. Each case runs once whole, which counts the bytes it writes (B)
// and the stop polls it makes (P); then again with every write failing from
// the first byte, from B/3, from 2B/3 and at the last byte (after the
// earlier results were committed: only the run's rollback removes them), and
// with a SIGINT at the first poll and a SIGTERM at poll P/2 and at the last
// poll. A broken rule traps, naming the run. The files given as arguments
// (the fuzzer's corpus, or an input it saved) are replayed too.
#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <vector>

#include "fault_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
  int runs = 0;
  for (int i = 1; i < argc; ++i) {
    std::ifstream in(argv[i], std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    ++runs;
  }
  using nsmodal::fault::RunAndCheck;
  for (const nsmodal::fault::Case& c : nsmodal::fault::Cases()) {
    const nsmodal::fault::Run whole = RunAndCheck(c, -1, 0, 0);
    if (whole.status != 0) {
      std::fprintf(stderr, "%s: exit %d without a fault\n", c.args[0].c_str(), whole.status);
      return 1;
    }
    const long b = whole.bytes_written, p = whole.polls;
    for (long budget : {0L, b / 3, 2 * b / 3, b - 1}) RunAndCheck(c, budget, 0, 0);
    RunAndCheck(c, -1, 1, SIGINT);
    RunAndCheck(c, -1, std::max(1L, p / 2), SIGTERM);
    RunAndCheck(c, -1, std::max(1L, p), SIGTERM);
    runs += 8;
    std::printf("%s %s: %ld bytes, %ld polls\n", c.args[0].c_str(), c.args[3].c_str(), b, p);
  }
  std::printf("%d fault runs: no half-written result\n", runs);
  return 0;
}
