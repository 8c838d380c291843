// SPDX-License-Identifier: Apache-2.0
// `ncqual wait`: waits until the historian has stored a whole check, N results, or the end of a
// machine's cycle.
//
//   ncqual wait [--plant F | --db F] (--request ID | --count N [--machine M] |
//               --settled --machine M [--since-ns T]) [--timeout S]
//
// Waits on the database itself: the historian's commit is the event waited for; the database
// is re-read every 100 ms until the condition holds or the deadline passes. Prints the check's
// verdict (--request) or the machine's state (--settled). Exit codes: 0, 5 timed out, 2 bad usage
// (and a machine the plant config does not configure).
#include "commands.hpp"

#include "ncqual/storage/database.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <thread>

namespace ncqual::cli {
namespace {

struct Options {
  std::string plant;
  std::optional<std::string> db, request, machine;
  int count = -1;
  bool settled = false;
  std::int64_t since_ns = 0;
  double timeout_s = 60;
};

int run(const Options& o) {
  if (!o.request && o.count < 0 && !o.settled) {
    throw UsageError("pass --request ID, --count N or --settled --machine M");
  }
  if (o.settled && !o.machine) throw UsageError("--settled needs --machine M");
  // Checked against the plant config only: the historian may not hold the machine yet.
  if (o.machine) (void)check_machines_configured({*o.machine}, o.plant);
  const std::string path = database_path(o.db, o.plant);
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(static_cast<long long>(o.timeout_s * 1000));
  // The whole check: request, measurement set and result (topics arrive independently); an
  // imported set (`ncqual import`) has no request.
  auto complete = [](const std::optional<storage::CheckRecord>& rec) {
    return rec && rec->measurement && rec->result &&
           (rec->request || rec->measurement->instrument == kImportedInstrument);
  };
  while (true) {
    if (std::filesystem::exists(path)) {
      try {
        auto db = storage::Database::open_readonly(path);
        if (o.request) {
          auto rec = db.find_check(*o.request);
          if (complete(rec)) {
            std::cout << to_string(rec->result->verdict) << "\n";
            return kExitOk;
          }
        } else if (o.settled) {
          // The machine's cycle is over when its newest status says QUALIFIED, OVERDUE or
          // NEEDS_INTERVENTION and the check that decided it is stored whole.
          const auto status = db.latest_status(*o.machine);
          if (status && status->time_ns >= o.since_ns &&
              (status->state == MachineState::Qualified || status->state == MachineState::Overdue ||
               status->state == MachineState::NeedsIntervention) &&
              (status->request_id.empty() || complete(db.find_check(status->request_id)))) {
            std::cout << to_string(status->state) << "\n";
            return kExitOk;
          }
        } else if (db.count_results(o.machine) >= o.count) {
          return kExitOk;
        }
      } catch (const storage::StorageError&) {
        // The historian is creating the schema right now: look again.
      }
    }
    if (std::chrono::steady_clock::now() >= deadline) {
      std::cerr << "ncqual wait: timed out after " << o.timeout_s << " s\n";
      return kExitTimedOut;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

}  // namespace

void add_wait(CLI::App& app, Commands& commands) {
  const auto [cmd, o] =
      add_command(app, commands, "wait",
                  "wait until the historian has stored that whole check (or N results)", run);
  add_historian_options(cmd, o->plant, o->db);
  cmd->add_option("--request", o->request, "until this request's check is stored whole")
      ->type_name("ID");
  cmd->add_option("--count", o->count, "until N results are stored (of --machine)")->type_name("N");
  cmd->add_flag("--settled", o->settled,
                "until --machine's cycle is over (QUALIFIED, OVERDUE or NEEDS_INTERVENTION)");
  add_machine_option(cmd, o->machine, "the machine of --count or --settled");
  cmd->add_option("--since-ns", o->since_ns, "--settled: a status from this time on (ns, UTC)")
      ->type_name("T");
  cmd->add_option("--timeout", o->timeout_s, "give up after S seconds")
      ->type_name("S")
      ->capture_default_str();
}

}  // namespace ncqual::cli
