// SPDX-License-Identifier: Apache-2.0
// How ncqual-scheduler drives its Scheduler over time, without DDS: the simulated clock's run and
// the restart handshake with the readers of its writers. The executable wires DDS to these; the
// tests drive them directly.
#pragma once

#include "scheduler.hpp"

#include "ncqual/clock.hpp"
#include "ncqual/state_file.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

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
};

// The plant calendar on a simulated clock, as fast as the checks come back: whenever no check is
// waiting for a result the clock jumps to the next thing due (a shift start, a part, a timeout);
// when a check gets no answer for `stall` of wall time the clock runs on to its deadline.
// Persists the clock with the scheduler's state at every jump.
void run_simulated(Scheduler& scheduler, SimulatedClock& clock, const Events& events,
                   const SimulatedRunOptions& options);

// A restarted scheduler must not send before its writers have matched the readers the last run
// had (the historian, the acquisitions): a request that reached an acquisition but not the
// historian would be lost with the process if it were killed again. The counts are kept in the
// state file (document "readers").
class ReaderHandshake {
 public:
  struct Writer {
    std::function<int()> matched;                                      // readers matched now
    std::function<bool(int readers, std::chrono::milliseconds)> wait;  // until that many

    // Of anything with matched_readers() and wait_for_readers(n, patience): a dds::Writer.
    template <typename W>
    static Writer of(W& w) {
      return {[&w] { return w.matched_readers(); },
              [&w](int n, std::chrono::milliseconds t) { return w.wait_for_readers(n, t); }};
    }
  };

  ReaderHandshake(storage::StateFile& state, Writer requests, Writer statuses);
  // At start: waits up to `patience` for the readers of the last run. When they do not all come,
  // says so, and learns the smaller plant (it has changed). Returns whether all came.
  bool wait(std::chrono::milliseconds patience);
  // Remembers readers that appeared since (services started after the scheduler).
  void learn();

 private:
  storage::StateFile& state_;
  Writer requests_, statuses_;
  ReaderCounts known_;
};

}  // namespace ncqual::scheduler
