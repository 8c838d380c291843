// SPDX-License-Identifier: Apache-2.0
// A generated historian: months of checks of many simulated machines, made in this process (no
// DDS, no services) for the tests and the benches that need a big file (docs/history-bench.md).
//
// Every machine is a copy of deploy/machines/pm1.yaml (machine_id pm001, pm002, ...) with its own
// simulator seed; a share of them drifts (simulator.drift: the machine creeping along X or Y, the
// tool length growing, the fixture's zeros moving, at rates drawn per machine), and any machine
// may take a sudden fault (the machine knocked off its position) on any working day. Each working
// day (Monday to Friday, from 05:00 UTC) runs what the plant calendar runs: with `monthly`, the
// tracker's global grid on the first Monday of the month; the four daily monument checks; the
// weekly fixture pre-calibration on Mondays (the scheduler's configuration rotation), and when it
// issues zero offsets the Compensation, applied to the simulated fixture, and the
// post-calibration that verifies them. The measurements are SimulatedInstruments', the verdicts
// solver::solve's; the requests, sets, results, statuses, compensations and interventions are
// stored with storage::Database::store as the historian would. A check that does not pass holds
// the machine (NEEDS_INTERVENTION; the checks after it that day are not run); the next working day
// begins with an Intervention that repairs the simulated fault (the drift restarts from then, the
// truth back at nominal) and the checks run again. With `watch`, the historian's trend watch runs
// after every result, intervention and compensation, so trend_warnings is filled as the historian
// fills it. Deterministic for a seed.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/storage/database.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ncqual::history {

struct GenerateOptions {
  int machines = 50;
  int days = 365;  // calendar days from start_ns
  std::uint64_t seed = 1;
  bool monthly = false;  // the tracker's global grid on the first Monday of each month
  bool watch = false;    // the historian's trend watch (trend_warnings)
  std::int64_t start_ns = 1767571200LL * 1'000'000'000;  // Monday 2026-01-05T00:00:00Z
  std::string machine_file;  // the machine every generated one copies (deploy/machines/pm1.yaml)
  double drift_share = 0.4;  // of the machines, this share drifts
  double fault_per_day = 0.001;  // chance of a sudden fault, per machine and working day
  // Called after each simulated day with the day's index (0-based), e.g. to print progress.
  std::function<void(int day)> progress;
};

struct GenerateReport {
  std::vector<std::string> machine_ids;
  int drifting = 0;  // machines with a drift
  int faults = 0;    // sudden faults injected
  std::int64_t checks = 0, passed = 0, failed = 0, invalid = 0;
  std::int64_t interventions = 0, compensations = 0, statuses = 0;
  std::int64_t monthly_checks = 0;
  std::int64_t warnings_raised = 0, warnings_ended = 0;  // by the trend watch
  std::int64_t first_ns = 0, last_ns = 0;                // of the stored samples
  double seconds = 0;                                    // wall time of the whole generation
  double monthly_seconds = 0;  // of it: measuring and solving the monthly tracker checks
  double watch_seconds = 0;    // of it: the trend watch
  double store_seconds = 0;    // of it: storing
};

// The machine `index` (0-based) as generated: pmNNN (three digits, more when needed), the
// simulator seed and the drift drawn for it from `options.seed`, the drift starting at start_ns.
MachineConfig generated_machine(const GenerateOptions& options, int index);
// "pm001" for index 0.
std::string generated_machine_id(int index);

// A plant of the generated machines (ids `machine_ids`, every other section from
// options.machine_file) on a simulated clock: what `ncqual status` and the dashboard would be
// given to read the generated file.
PlantConfig generated_plant(const GenerateOptions& options,
                            const std::vector<std::string>& machine_ids);

// Generates into `db` (a fresh read-write database). Throws what the storage, the config or the
// simulator throws.
GenerateReport generate_history(storage::Database& db, const GenerateOptions& options);

// The command lines of ncqual-generate-history and the history bench, read one argument at a
// time (for (int i = 1; i < argc; ++i)):
//
// The value of the option argv[i]: the next argument (i moves onto it). Throws
// std::invalid_argument when there is none.
std::string option_value(int argc, char** argv, int& i);
// When argv[i] is one of the options both take (--machines N, --days D, --seed S, --watch,
// --monthly), reads it into `options` (i moves past its value) and returns true; else false.
// Throws std::invalid_argument for a missing or unreadable value.
bool read_generate_option(int argc, char** argv, int& i, GenerateOptions& options);

}  // namespace ncqual::history
