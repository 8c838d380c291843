// SPDX-License-Identifier: Apache-2.0
// Benchmark of acknowledged storage (docs/architecture.md, "Acknowledged storage"): what the
// outbox and the historian's acknowledgement cost a producer, side by side with plain DDS writes.
// A real ncqual-historian (Fast DDS on a private domain, its SQLite file in a temporary directory)
// stores CheckResults as the solver sends them: one monument check of deploy/machines/pm1.yaml,
// simulated and judged by the solver library, renamed per sample over --machines machines.
//   with     every result goes through a ncqual::dds::Outbox (in a state file of its own,
//            awaiting the historian) as services/solver sends it; latency: from handing it to the
//            outbox to the historian's acknowledgement; throughput: a burst until the outbox is
//            empty.
//   without  the same results through the same DataWriter, no outbox; latency: from the write
//            until the row is visible in the historian's file (read-only, polled every 0.05 ms);
//            throughput: a burst until the file holds all of them.
// Throughput comes from a burst of --samples results (one acknowledgement pass of the receive
// loop between two sends, as the solver takes them between two sets). Latency comes from
// --latency-samples results sent one at a time, each once the one before is acknowledged or
// visible, with and without alternating so that both see the same load of the machine: the delay
// of one check, not of a queue. A check is one CheckResult here; the solver's outbox also awaits
// the scheduler, whose part is not measured.
//
// Prints figures with targets and PASS/MISS beside them; exits 0 once measured (whatever the
// figures), 1 when the historian did not store or acknowledge everything in time, 2 for bad usage.
#include "harness.hpp"
#include "bench_support.hpp"
#include "test_participant.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/acknowledged.hpp"
#include "ncqual/dds/service.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/storage/state_file.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/common/version.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
#include <vector>

namespace {

using namespace ncqual;
using Clock = std::chrono::steady_clock;
using bench::quantile;
using ResultTopic = ncqual::dds::CheckResultTopic;

// Targets of the acknowledged path (the "with" column):
// - throughput >= 50 checks/s: a real plant makes far less than one check a second (20 machines,
//   a check every few minutes each); 50/s leaves room for the simulated-calendar runs (the demo's
//   --weeks, the fleet and campaign tests), which replay weeks of checks in seconds.
// - latency median <= 50 ms, p95 <= 250 ms: the scheduler's next step and `ncqual check` /
//   `wait` wait on acknowledgements; a quarter of a second goes unnoticed after a check whose
//   probing takes minutes.
// - latency max <= 1000 ms: well inside the outbox's first resend (2 s), so no sample is written
//   twice only because its acknowledgement was slow.
constexpr double kTargetChecksPerS = 50;
constexpr double kTargetMedianMs = 50;
constexpr double kTargetP95Ms = 250;
constexpr double kTargetMaxMs = 1000;
// The read-only poll of the historian's file for the "without" figures.
constexpr auto kPollPeriod = std::chrono::microseconds(50);

struct Options {
  int samples = 500;
  int latency_samples = 500;
  int machines = 10;
  int timeout_s = 60;
};

// The bench's command line: what it does and Options.
void add_options(CLI::App& app, Options& options) {
  app.description(
      "The cost of acknowledged storage: checks per second and latency with the outbox and the "
      "historian's acknowledgement, and with plain writes, against a real ncqual-historian.");
  // The durable topics keep the last 500 samples per machine: a plain burst of more per machine
  // than the historian takes meanwhile loses the oldest (what the outbox is there for).
  bench::add_bounded(app, "--samples", options.samples,
                     "results in the throughput burst (keep it under 500 per machine)", 1, 100000);
  bench::add_bounded(app, "--latency-samples", options.latency_samples,
                     "results sent one at a time for the latencies", 1, 100000);
  bench::add_bounded(app, "--machines", options.machines,
                     "machines the results are spread over (at most 200, the QoS's instances)", 1,
                     200);
  bench::add_timeout_option(app, options.timeout_s);
}

// What a phase measured: checks per second (a burst) or latencies (one at a time).
struct Figures {
  double per_s = 0;
  std::vector<double> latency_ms;
};

double ms_between(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

// A result as the solver sends it: a daily monument check of pm1, simulated and judged.
CheckResult judged_check() {
  const MachineConfig machine =
      load_machine_config(std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml");
  const sim::MachineSimulator simulator(machine, machine.simulator);
  CheckRequest request;
  request.machine_id = machine.machine_id;
  request.request_id = machine.machine_id + "-monument_positioning-bench";
  request.kind = CheckKind::MonumentPositioning;
  const std::int64_t now = WallClock().now_ns();
  CheckResult result = solver::solve(simulator.perform(request, now), machine, now);
  result.produced_by = version_line("ncqual-solver");
  return result;
}

class Failed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The producer side: one service (participant, receive loop, heartbeat) with the outbox of the
// "with" figures and the writer both columns share, and a read-only connection to the historian.
// The producer's service: "bench", a participant of the plant as the services' are.
ncqual::dds::ServiceOptions service_options(const testing::Plant& plant) {
  ncqual::dds::ServiceOptions o;
  o.service = "bench";
  o.participant = testing::test_participant(plant, "ncqual-bench");
  return o;
}

class Producer {
 public:
  Producer(testing::Plant& plant, const Options& options, CheckResult check)
      : plant_(plant),
        options_(options),
        check_(std::move(check)),
        service_(service_options(plant)),
        state_(storage::StateFile::open((plant.dir() / "bench-outbox.db").string())),
        writer_(service_.participant()),
        acks_(service_.participant()),
        outbox_(service_, state_) {
    for (int m = 0; m < options_.machines; ++m) {
      char id[16];
      std::snprintf(id, sizeof id, "bm%02d", m + 1);
      machines_.emplace_back(id);
    }
    outbox_.route(writer_);
    outbox_.start();
    // Every acknowledgement of ours from the historian, with the time it arrived.
    service_.dispatcher().on(acks_, [this](const ncqual::dds::Received<Acknowledgement>& in) {
      const Acknowledgement& a = in.value;
      if (!in.error.empty() || a.topic != ResultTopic::kName || a.by != roles::kHistorian) return;
      if (a.outcome == AckOutcome::Refused) refused_ = a.sample_id + ": " + a.detail;
      acked_.emplace(a.sample_id, Clock::now());
    });
  }

  // Until the historian's reader and acknowledgement writer are matched; then one pass of the
  // receive loop, so that the outbox's resend timer has seen the reader before the first send
  // (a reader new to it gets every pending sample written again).
  void connect() {
    const auto patience = timeout();
    if (!writer_.wait_for_readers(1, patience) || !acks_.wait_for_writers(1, patience)) {
      throw Failed("the historian's reader or acknowledgement writer did not match");
    }
    pass();
    db_.emplace(storage::Database::open_readonly(plant_.db_path()));
  }

  // A burst of `n` through the outbox: checks per second until the outbox is empty.
  Figures burst_with(const std::string& phase, int n) {
    const auto t0 = Clock::now();
    for (int i = 0; i < n; ++i) {
      outbox_.send<ResultTopic>(sample(phase, i), {roles::kHistorian});
      if (acks_.condition().get_trigger_value()) pass();
    }
    run_until([this] { return outbox_.depth() == 0; }, "the outbox to empty");
    const double s = ms_between(t0, Clock::now()) / 1000.0;
    check_refused();
    return Figures{n / s, {}};
  }

  // A burst of `n` with the plain writer: checks per second until the file holds them all.
  Figures burst_without(const std::string& phase, int n) {
    const std::int64_t base = db_->count_results();
    std::vector<std::string> ids;
    const auto t0 = Clock::now();
    for (int i = 0; i < n; ++i) {
      const CheckResult r = sample(phase, i);
      if (!writer_.write(r)) throw Failed("a plain write of " + r.request_id + " was refused");
      ids.push_back(r.request_id);
    }
    poll_until_stored(base + n);
    const double s = ms_between(t0, Clock::now()) / 1000.0;
    // Not timed: their acknowledgements, so that they do not wait in our readers meanwhile.
    run_until([&] { return acked_all(ids); }, "the acknowledgements of plain writes");
    check_refused();
    return Figures{n / s, {}};
  }

  // `n` one at a time, alternating with and without; each column's latencies.
  std::pair<Figures, Figures> one_at_a_time(const std::string& phase, int n) {
    Figures with, without;
    for (int i = 0; i < n; ++i) {
      const CheckResult a = sample(phase + "-with", i);
      auto t0 = Clock::now();
      outbox_.send<ResultTopic>(a, {roles::kHistorian});
      run_until([&] { return acked_.count(a.request_id) > 0; }, "an acknowledgement");
      with.latency_ms.push_back(ms_between(t0, acked_.at(a.request_id)));
      run_until([this] { return outbox_.depth() == 0; }, "the outbox to empty");

      const CheckResult b = sample(phase + "-without", i);
      const std::int64_t base = db_->count_results();
      t0 = Clock::now();
      if (!writer_.write(b)) throw Failed("a plain write of " + b.request_id + " was refused");
      without.latency_ms.push_back(ms_between(t0, poll_until_stored(base + 1)));
      run_until([&] { return acked_.count(b.request_id) > 0; }, "an acknowledgement");
    }
    check_refused();
    return {with, without};
  }

 private:
  std::chrono::milliseconds timeout() const { return std::chrono::seconds(options_.timeout_s); }

  CheckResult sample(const std::string& phase, int i) const {
    CheckResult r = check_;
    r.machine_id = machines_[static_cast<std::size_t>(i) % machines_.size()];
    r.request_id = r.machine_id + "-monument_positioning-" + phase + "-" + std::to_string(i);
    r.time_ns = WallClock().now_ns();
    return r;
  }

  // One pass of the receive loop; returns at once when something waits.
  void pass() {
    bool passed = false;
    service_.dispatcher().run_until([&passed] { return std::exchange(passed, true); },
                                    std::chrono::milliseconds(100));
  }

  void run_until(const std::function<bool()>& done, const char* what) {
    if (!service_.dispatcher().run_until(done, timeout())) {
      throw Failed(std::string(service_.dispatcher().stopping() ? "interrupted" : "timed out") +
                   " waiting for " + what);
    }
  }

  // Polls the historian's file until it holds `count` results; when it was first seen.
  Clock::time_point poll_until_stored(std::int64_t count) {
    const auto deadline = Clock::now() + timeout();
    for (std::int64_t held = db_->count_results(); held < count; held = db_->count_results()) {
      if (Clock::now() > deadline || service_.dispatcher().stopping()) {
        // A plain writer keeps the last 500 per machine (the QoS): a burst of more loses some.
        throw Failed("the historian's file holds " + std::to_string(held) + " results, not " +
                     std::to_string(count) +
                     " (a plain burst of more than 500 per machine loses "
                     "the oldest)");
      }
      std::this_thread::sleep_for(kPollPeriod);
    }
    return Clock::now();
  }

  bool acked_all(const std::vector<std::string>& ids) const {
    return std::all_of(ids.begin(), ids.end(),
                       [this](const std::string& id) { return acked_.count(id) > 0; });
  }

  void check_refused() const {
    if (!refused_.empty()) throw Failed("the historian refused " + refused_);
  }

  testing::Plant& plant_;
  Options options_;
  CheckResult check_;
  std::vector<std::string> machines_;
  ncqual::dds::Service service_;
  storage::StateFile state_;
  ncqual::dds::Writer<ResultTopic> writer_;
  ncqual::dds::Reader<ncqual::dds::AcknowledgementTopic> acks_;
  ncqual::dds::Outbox outbox_;
  std::unordered_map<std::string, Clock::time_point> acked_;  // by sample id: its first ack
  std::string refused_;
  std::optional<storage::Database> db_;
};

const char* verdict(bool pass) { return pass ? "PASS" : "MISS"; }

void print_row(const char* figure, double with, double without, const char* target,
               std::optional<bool> pass) {
  std::printf("  %-22s %12.1f %12.1f %8.2fx   %-10s %s\n", figure, with, without,
              without > 0 ? with / without : 0.0, target, pass ? verdict(*pass) : "");
}

int run(const Options& options) {
  // The outbox and the receive loop log at info and warn; the table is the output here.
  spdlog::set_level(spdlog::level::err);
  const CheckResult check = judged_check();

  testing::Plant plant("ack-bench", testing::TestDomain::AckBench);
  plant.write_plant("[]");
  // At the level a plant runs it (the harness's default is debug: a log line per sample); on the
  // plant's domain whatever NCQUAL_DOMAIN says.
  plant.start("historian", {"--log-level", "info", "--domain", std::to_string(plant.domain())});
  const auto ready = [](storage::Database& db) { return !db.services().empty(); };
  if (!plant.wait_for_db(ready, std::chrono::seconds(options.timeout_s))) {
    std::fprintf(stderr, "ack bench: the historian did not start:\n%s\n",
                 plant.log("historian").c_str());
    return 1;
  }
  std::printf("ncqual acknowledged-storage bench: %s\n",
              testing::Plant::executable("historian").c_str());
  std::printf("  database %s, DDS domain %d\n", plant.db_path().c_str(), plant.domain());
  std::printf("  sample: CheckResult of a monument check (%s, %zu metrics, %s), over %d machines\n",
              std::string(to_string(check.verdict)).c_str(), check.metrics.size(),
              check.produced_by.c_str(), options.machines);
  std::printf(
      "  throughput: a burst of %d; latency: %d one at a time, with and without alternating\n\n",
      options.samples, options.latency_samples);

  try {
    Producer producer(plant, options, check);
    producer.connect();
    // Not counted: the first write of every machine's instance, SQLite's first statements.
    const int warm = std::max(2 * options.machines, 20);
    producer.burst_with("warm", warm);
    producer.burst_without("warm-plain", warm);

    const Figures with = producer.burst_with("burst", options.samples);
    const Figures without = producer.burst_without("burst-plain", options.samples);
    const auto [with_lat, without_lat] = producer.one_at_a_time("one", options.latency_samples);

    const double med_w = quantile(with_lat.latency_ms, 0.5);
    const double med_o = quantile(without_lat.latency_ms, 0.5);
    const double p95_w = quantile(with_lat.latency_ms, 0.95);
    const double p95_o = quantile(without_lat.latency_ms, 0.95);
    const double max_w = quantile(with_lat.latency_ms, 1.0);
    const double max_o = quantile(without_lat.latency_ms, 1.0);
    std::printf("  %-22s %12s %12s %9s   %-10s\n", "figure", "with", "without", "ratio",
                "target (with)");
    print_row("throughput, checks/s", with.per_s, without.per_s, ">= 50",
              with.per_s >= kTargetChecksPerS);
    print_row("latency median, ms", med_w, med_o, "<= 50", med_w <= kTargetMedianMs);
    print_row("latency p95, ms", p95_w, p95_o, "<= 250", p95_w <= kTargetP95Ms);
    print_row("latency max, ms", max_w, max_o, "<= 1000", max_w <= kTargetMaxMs);
    std::printf(
        "\n  with: outbox (state file, awaiting the historian) until the historian's "
        "acknowledgement;\n  without: plain write until the row is visible in the file (polled "
        "every %.2f ms)\n",
        std::chrono::duration<double, std::milli>(kPollPeriod).count());
  } catch (const Failed& e) {
    std::fprintf(stderr, "ack bench failed: %s\n--- historian log ---\n%s\n", e.what(),
                 plant.log("historian").c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main(argc, argv, "ncqual_ack_bench", add_options, run);
}
