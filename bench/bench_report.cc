// Writing a large table (issue 25): the orbits table of the 100-mass 1-ipp
// sweep (T = 0.5:60:0.01: 5,951 rows of 611 columns, every multiplier) as CSV
// and as HDF5, from synthetic rows of that shape, streamed as the orbits
// command streams them (a row at a time into one open result). The files go
// to the system's temporary directory; the counters give the file's size.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <string>
#include <vector>

#include "nsmodal/hdf5.h"
#include "nsmodal/output.h"
#include "nsmodal/tables.h"

namespace nsmodal {
namespace {

namespace fs = std::filesystem;
constexpr int kDofs = 100;

// Rows shaped as the sweep's: every other period potential (multipliers and
// the verdict), the others without stability (those cells missing).
const std::vector<OrbitRecord>& Rows(std::size_t n) {
  static std::vector<OrbitRecord> rows;
  if (rows.size() != n) {
    rows.clear();
    for (std::size_t i = 0; i < n; ++i) {
      OrbitRecord r;
      const double period = 0.5 + 0.01 * static_cast<double>(i);
      r.orbit.period = period;
      r.orbit.z0 = Eigen::VectorXd::LinSpaced(2 * kDofs, -1.0, 1.0) * std::sin(period);
      r.orbit.energy = 0.5 * period * period + 1.0 / 3.0;
      r.orbit.potential = i % 2 == 0;
      r.orbit.admissible = i % 4 == 0;
      r.orbit.periodicity_residual = 1.234e-15 * period;
      r.orbit.nc2_residual = 3.3e-16 * period;
      r.orbit.max_excess = -0.0123 * period;
      if (r.orbit.potential) {
        Stability s;
        s.multipliers.resize(2 * kDofs);
        for (int k = 0; k < 2 * kDofs; ++k) s.multipliers[k] = std::polar(1.0 + 1e-3 * k / period, 0.37 * k + period);
        s.max_modulus = std::abs(s.multipliers[2 * kDofs - 1]);
        s.stable = i % 8 == 0;
        r.stability = s;
      }
      rows.push_back(std::move(r));
    }
  }
  return rows;
}

fs::path Dir() { return fs::temp_directory_path() / ("nsmodal-bench-report-" + std::to_string(::getpid())); }

void BM_OrbitsCsv(benchmark::State& state) {
  const std::vector<OrbitRecord>& rows = Rows(static_cast<std::size_t>(state.range(0)));
  const auto columns = report::OrbitColumns(kDofs);
  const report::OutputDir dir = report::OutputDir::Prepare(Dir().string(), {"orbits.csv"});
  for (auto _ : state) {
    report::ResultFile out(dir, "orbits.csv");
    report::WriteCsvHeader(out.stream(), columns);
    for (const OrbitRecord& r : rows) report::WriteCsvRow(out.stream(), columns, r);
    out.Commit();
  }
  state.counters["MB"] = static_cast<double>(fs::file_size(Dir() / "orbits.csv")) / 1e6;
  state.counters["columns"] = static_cast<double>(columns.size());
  fs::remove_all(Dir());
}

void BM_OrbitsHdf5(benchmark::State& state) {
  const std::vector<OrbitRecord>& rows = Rows(static_cast<std::size_t>(state.range(0)));
  const auto columns = report::OrbitColumns(kDofs);
  const report::OutputDir dir = report::OutputDir::Prepare(Dir().string(), {"orbits.h5"});
  for (auto _ : state) {
    report::Hdf5Table<OrbitRecord> out(dir, "orbits", columns);
    for (const OrbitRecord& r : rows) out.Append(r);
    out.Commit();
  }
  state.counters["MB"] = static_cast<double>(fs::file_size(Dir() / "orbits.h5")) / 1e6;
  state.counters["columns"] = static_cast<double>(columns.size());
  fs::remove_all(Dir());
}

BENCHMARK(BM_OrbitsCsv)->Arg(5951)->Arg(11902)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OrbitsHdf5)->Arg(5951)->Arg(11902)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace nsmodal

BENCHMARK_MAIN();
