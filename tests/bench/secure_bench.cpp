// SPDX-License-Identifier: Apache-2.0
// Benchmark of DDS Security (docs/deploy.md, "Security"): the end-to-end latency of a check on a
// secured plant beside an open one. Two plants run at once on two private domains, each a real
// ncqual-historian, ncqual-solver and ncqual-scheduler (discovery: peers on this host): the open
// one as deploy/qos says, the secured one with deploy/security/ncqual-pki's plant CA, governance
// (authentication, encryption of every RTPS message) and permissions. The bench writes each
// MeasurementSet as the machine's acquisition would (secured: as identity acquisition-pm1, in the
// machine's partition) and times it from the write until the historian's file holds its
// CheckResult (read-only, polled every 0.05 ms): the solver's read, solve and write, the
// historian's read and commit. Checks alternate between the plants, one at a time, so both see
// the same load of the machine.
//
// Prints median, p95, p99 and max of each plant and their ratio beside the target (secured
// median and p99 within 1.5 times the open plant's); exits 0 once measured, 1 when a plant did
// not store a result in time, 2 for bad usage.
#include "harness.hpp"
#include "bench_support.hpp"
#include "test_participant.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/common/model.hpp"
#include "ncqual/sim/machine_simulator.hpp"
#include "ncqual/storage/database.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace ncqual;
using Clock = std::chrono::steady_clock;
using bench::quantile;

// Secured within 1.5 times the open plant: the handshakes are done once at start; what stays is
// AES-GCM of each message and its MAC, small beside the solver's work and SQLite's commit.
constexpr double kTargetRatio = 1.5;
constexpr auto kPollPeriod = std::chrono::microseconds(50);

struct Options {
  int checks = 200;
  int timeout_s = 60;
};

// The bench's command line: what it does and Options.
void add_options(CLI::App& app, Options& options) {
  app.description(
      "The cost of DDS Security: a check's latency from MeasurementSet to stored CheckResult on "
      "a secured plant beside an open one, both real ncqual services.");
  bench::add_bounded(app, "--checks", options.checks, "checks per plant", 1, 100000);
  bench::add_timeout_option(app, options.timeout_s);
}

class Failed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::string run_pki(const std::vector<std::string>& args) {
  const auto out = testing::ncqual_pki(args);
  if (out.exit_code != 0) throw Failed("ncqual-pki " + args.front() + " failed:\n" + out.out);
  return out.out;
}

// One plant: its services, the bench's writer of pm1's sets, a read-only view of its historian.
class BenchPlant {
 public:
  BenchPlant(const char* name, testing::TestDomain domain, bool secured, const Options& options)
      : plant_(name, domain), secured_(secured), timeout_(std::chrono::seconds(options.timeout_s)) {
    plant_.add_machine("pm1",
                       testing::machine_yaml("pm1", "    machine_shift_mm: [0.002, 0, 0]\n"));
    std::string sections = "network: {discovery: peers, peers: [127.0.0.1]}\n";
    if (secured_) {
      plant_.write_plant();  // ncqual-pki reads the plant's machines from it
      const std::string dir = (plant_.dir() / "pki").string();
      run_pki({"init", "--plant", plant_.plant_file(), "--out", dir});
      sections += "security: {dir: " + dir + "}\n";
    }
    plant_.write_plant_with(sections, "[]");
    machine_ = load_machine_config((plant_.dir() / "pm1.yaml").string());
    for (const char* service : {"historian", "solver", "scheduler"}) {
      plant_.start(service, {"--log-level", "info"});
    }
    ncqual::dds::ParticipantOptions o = testing::test_participant(plant_, "ncqual-bench");
    if (secured_) o.security.identity = "acquisition-pm1";
    participant_ = std::make_unique<ncqual::dds::Participant>(o);
    sets_ = std::make_unique<ncqual::dds::MachineWriters<ncqual::dds::MeasurementSetTopic>>(
        *participant_, std::vector<std::string>{"pm1"});
    // The historian's and the solver's readers.
    if (!sets_->of("pm1").wait_for_readers(2, timeout_)) {
      throw Failed(std::string(name) + ": the historian's and solver's readers did not match:\n" +
                   plant_.log("solver"));
    }
    if (!plant_.wait_for_db([](storage::Database&) { return true; }, timeout_)) {
      throw Failed(std::string(name) + ": no historian database");
    }
    db_.emplace(storage::Database::open_readonly(plant_.db_path()));
  }

  // One check: its set written, until its result is in the historian's file; milliseconds.
  double check(const std::string& request_id) {
    const sim::MachineSimulator simulator(machine_, machine_.simulator);
    CheckRequest request;
    request.machine_id = machine_.machine_id;
    request.request_id = request_id;
    request.kind = CheckKind::MonumentPositioning;
    const MeasurementSet set = simulator.perform(request, WallClock().now_ns());
    const std::int64_t base = db_->count_results();
    const auto t0 = Clock::now();
    if (!sets_->write(set)) throw Failed("the write of " + request_id + " was refused");
    const auto deadline = t0 + timeout_;
    while (db_->count_results() <= base) {
      if (Clock::now() > deadline) {
        throw Failed(plant_.dir().string() + ": no result of " + request_id + " stored in time:\n" +
                     plant_.log("solver") + plant_.log("historian"));
      }
      std::this_thread::sleep_for(kPollPeriod);
    }
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  }

 private:
  testing::Plant plant_;
  bool secured_;
  std::chrono::seconds timeout_;
  MachineConfig machine_;
  std::unique_ptr<ncqual::dds::Participant> participant_;
  std::unique_ptr<ncqual::dds::MachineWriters<ncqual::dds::MeasurementSetTopic>> sets_;
  std::optional<storage::Database> db_;
};

void print_row(const char* figure, double secured, double open, std::optional<bool> pass) {
  const double ratio = open > 0 ? secured / open : 0.0;
  std::printf("  %-18s %10.2f %10.2f %8.2fx   %s\n", figure, secured, open, ratio,
              pass ? (*pass ? "PASS" : "MISS") : "");
}

int run(const Options& options) {
  spdlog::set_level(spdlog::level::err);
  try {
    BenchPlant open("secure-bench-open", testing::TestDomain::SecureBenchOpen, false, options);
    BenchPlant secured("secure-bench-secured", testing::TestDomain::SecureBenchSecured, true,
                       options);
    // Not counted: each plant's first checks (SQLite's first statements, the solver's first
    // solve, the first encrypted exchanges of each endpoint).
    for (int i = 0; i < 5; ++i) {
      open.check("pm1-warm-open-" + std::to_string(i));
      secured.check("pm1-warm-secured-" + std::to_string(i));
    }
    std::vector<double> o, s;
    for (int i = 0; i < options.checks; ++i) {
      o.push_back(open.check("pm1-open-" + std::to_string(i)));
      s.push_back(secured.check("pm1-secured-" + std::to_string(i)));
    }
    std::printf(
        "ncqual DDS Security bench: MeasurementSet written -> CheckResult stored, %d checks per "
        "plant,\nalternating; historian, solver and scheduler per plant, discovery: peers on this "
        "host\n\n",
        options.checks);
    std::printf("  %-18s %10s %10s %9s   %s\n", "figure, ms", "secured", "open", "ratio",
                "target: secured <= 1.5x open");
    const double med_s = quantile(s, 0.5), med_o = quantile(o, 0.5);
    const double p99_s = quantile(s, 0.99), p99_o = quantile(o, 0.99);
    print_row("median", med_s, med_o, med_s <= kTargetRatio * med_o);
    print_row("p95", quantile(s, 0.95), quantile(o, 0.95), std::nullopt);
    print_row("p99", p99_s, p99_o, p99_s <= kTargetRatio * p99_o);
    print_row("max", quantile(s, 1.0), quantile(o, 1.0), std::nullopt);
  } catch (const Failed& e) {
    std::fprintf(stderr, "secure bench failed: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main(argc, argv, "ncqual_secure_bench", add_options, run);
}
