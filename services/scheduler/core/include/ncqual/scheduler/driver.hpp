// SPDX-License-Identifier: Apache-2.0
// How ncqual-scheduler drives its Scheduler over time, without DDS: its command line's choices and
// the simulated clock's run. The executable wires DDS to these; the tests drive them directly.
#pragma once

#include "ncqual/scheduler/scheduler.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/storage/state_file.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace CLI {
class App;
}  // namespace CLI

namespace ncqual::scheduler {

// ---- The command line's choices ---------------------------------------------------------------

// The plant as one scheduler serves it: with --machine ID[,ID...] only those machines (one
// scheduler per machine or group), the ids of the others (their commands and interventions are
// another scheduler's business, not errors), and a state file of its own, scheduler-<ids>.db
// beside the plant's. Throws ConfigError naming a bad entry.
struct ServedPlant {
  PlantConfig plant;
  std::set<std::string> others;
};
ServedPlant serve_only(PlantConfig plant, const std::optional<std::string>& machine_list);

// "kind,kind,...": the --cycle list; "" is none. Throws std::invalid_argument naming the entry.
std::vector<CheckKind> check_kind_list(const std::string& text);

// When a simulated run ends: --until (an ISO 8601 UTC time), or --days after the plant's clock
// start; none: it runs until stopped. Throws std::invalid_argument naming the flag for a bad
// value, or for either on a plant on the wall clock.
std::optional<std::int64_t> simulated_run_end(const PlantConfig& plant, std::optional<double> days,
                                              const std::optional<std::string>& until);

// ---- Running ------------------------------------------------------------------------------------

// What the simulated run waits on: the process's received samples (results, commands,
// interventions), delivered to the Scheduler by whoever owns the readers.
struct Events {
  // Delivers what arrives within `patience` of wall time; true as soon as anything was
  // delivered, false when nothing came.
  std::function<bool(std::chrono::milliseconds patience)> wait_for_progress;
  // True once the process is asked to stop.
  std::function<bool()> stopping = [] { return false; };
};

struct SimulatedRunOptions {
  // Stop once the scheduler is idle and nothing is due before this time; none: run until stopped.
  std::optional<std::int64_t> until_ns;
  // Wall time without an answer before the clock runs on to the next deadline (a timeout), so a
  // dead acquisition is retried and reported as it would be in a plant.
  std::chrono::milliseconds stall{30000};
  // How long to wait for the operator when nothing is pending and nothing is due to jump to.
  std::chrono::milliseconds operator_patience{500};
  // Stop after this many such waits in a row that brought nothing (none: wait for ever, as the
  // service does; tests whose events answer at once set it).
  std::optional<int> give_up_after_idle_waits;
  // At most this many simulated seconds per wall second, counted from the start of the run (none:
  // as fast as the checks come back). The clock waits (for events) rather than jump ahead of it;
  // checks that follow each other directly still run as fast as they come back. A plant watching
  // a demo, or a fault campaign that needs the run to last while it kills services, sets it. The
  // decisions are the same at any speed.
  std::optional<double> speed;
  // The wall clock the speed is measured on (tests pass their own).
  std::function<std::chrono::steady_clock::time_point()> wall_now = [] {
    return std::chrono::steady_clock::now();
  };
};

// The command line's flags as given (ncqual-scheduler --help says each).
struct Flags {
  std::optional<std::string> machine_list;  // --machine ID[,ID...]
  std::optional<std::string> cycle;         // --cycle KIND,KIND,...
  std::optional<std::string> state;         // --state FILE
  std::optional<double> days;               // --days N
  std::optional<std::string> until;         // --until ISO-TIME
  double stall_s = 30;                      // --stall-s S
  std::optional<double> speed;              // --speed X
};

// Adds the flags (their help texts) to the service's command line.
void add_flags(CLI::App& app, Flags& flags);

// What the flags settle for a plant: the machines served, the checks to run once at start (the
// --cycle; else none with a calendar, the plant's scheduler.startup_checks without one), the state
// file (--state, else the served plant's), and the simulated run's end, stall and speed. Throws
// ConfigError or std::invalid_argument naming the flag (--speed or --days on the wall clock).
struct Settings {
  ServedPlant served;
  std::vector<CheckKind> cycle;
  std::string state_file;
  SimulatedRunOptions run;
};
Settings settle(PlantConfig plant, const Flags& flags);

// The plant calendar on a simulated clock, as fast as the checks come back: whenever no check is
// waiting for a result the clock jumps to the next thing due (a shift start, a part, a timeout);
// when a check gets no answer for `stall` of wall time the clock runs on to its deadline; with a
// `speed`, no jump goes further than the speed allows yet.
// Persists the clock with the scheduler's state at every jump.
void run_simulated(Scheduler& scheduler, SimulatedClock& clock, const Events& events,
                   const SimulatedRunOptions& options);

}  // namespace ncqual::scheduler
