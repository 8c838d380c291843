// SPDX-License-Identifier: Apache-2.0
// `ncqual check`: asks the scheduler to run a check now.
//
//   ncqual check --machine M --kind K [--plant F] [--domain N] [--wait SECONDS] [--json]
//
// Publishes a CheckCommand and waits until the scheduler acknowledged it
// (ncqual/dds/acknowledged_send.hpp); prints its request id. With --wait, prints the check's result
// instead (a table row, or --json) and exits with its verdict: 0 PASS, 3 FAIL, 4 INVALID, 5 no
// result in time; 9 when the scheduler refused the order, 1 when no scheduler acknowledges it.
#include "commands.hpp"

#include "ncqual/dds/acknowledged_send.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/dds/dispatcher.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/json.hpp"

#include <chrono>
#include <iostream>

namespace ncqual::cli {
namespace {

struct Options {
  DdsOptions dds;
  std::string machine;
  std::optional<CheckKind> kind;
  double wait_s = 0;
  bool json = false;
};

int run(const Options& o) {
  const PlantConfig plant = plant_from(o.dds.plant);
  const std::string machine = configured_machine(plant, o.machine).machine_id;
  const std::string kind_name(to_string(*o.kind));

  const WallClock clock;
  const CheckCommand cmd{machine,        new_sample_id("op", machine),
                         *o.kind,        "operator:" + operator_name(),
                         clock.now_ns(), {}};

  const ncqual::dds::ParticipantOptions options =
      command_participant(plant, o.dds, "ncqual-cli", operator_identity());
  const int domain = options.domain_id;
  ncqual::dds::Participant participant(options);
  ncqual::dds::Writer<ncqual::dds::CheckCommandTopic> commands(participant);
  std::optional<ncqual::dds::Reader<ncqual::dds::CheckResultTopic>> results;
  if (o.wait_s > 0) results.emplace(participant, machine);

  const ncqual::dds::OrderOutcome order = ncqual::dds::send_acknowledged(
      participant, commands, cmd, {roles::kScheduler}, std::chrono::seconds(15));
  if (!order.silent.empty()) {
    std::cerr << "ncqual check: no scheduler acknowledged order " << cmd.request_id
              << " within 15 s: is a scheduler serving " << machine << " running on domain "
              << domain << "?\n";
    return kExitError;
  }
  if (const Acknowledgement* refused = order.refused()) {
    std::cerr << "ncqual check: the scheduler refused " << cmd.request_id << ": " << refused->detail
              << "\n";
    return kExitRefused;
  }
  std::cerr << "requested " << kind_name << " on " << machine << " (" << cmd.request_id << ")\n";
  if (!results) {
    std::cout << cmd.request_id << "\n";
    return kExitOk;
  }
  std::optional<CheckResult> got;
  ncqual::dds::Dispatcher dispatcher;
  dispatcher.on(*results, [&](const ncqual::dds::Received<CheckResult>& in) {
    if (in.value.request_id == cmd.request_id) got = in.value;
  });
  dispatcher.run_until([&] { return got.has_value(); },
                       std::chrono::milliseconds(static_cast<long long>(o.wait_s * 1000)));
  if (!got) {
    std::cerr << "ncqual check: no result for " << cmd.request_id << " within " << o.wait_s
              << " s\n";
    return kExitTimedOut;
  }
  storage::CheckRecord rec;
  rec.machine_id = got->machine_id;
  rec.request_id = got->request_id;
  rec.kind = got->kind;
  rec.result = *got;
  if (o.json) {
    std::cout << storage::to_json(rec).dump(2) << "\n";
  } else {
    print_check_records({rec}, Calendar(plant.calendar.value_or(default_calendar_config())));
  }
  return exit_code_of(got->verdict);
}

}  // namespace

void add_check(CLI::App& app, Commands& commands) {
  const auto [cmd, o] =
      add_command(app, commands, "check",
                  "ask the scheduler to run a check now; with --wait, print its result", run);
  add_machine_option(cmd, o->machine, "the machine to check");
  add_kind_option(cmd, "--kind", o->kind, "the check to run")->required();
  add_dds_options(cmd, o->dds);
  cmd->add_option("--wait", o->wait_s,
                  "wait this long for the result, print it and exit with its verdict")
      ->type_name("SECONDS");
  add_json_flag(cmd, o->json);
}

}  // namespace ncqual::cli
