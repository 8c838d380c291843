// SPDX-License-Identifier: Apache-2.0
// `ncqual intervene`: the record of a physical intervention, which re-arms a held check.
//
//   ncqual intervene --machine M --check KIND --note TEXT [--operator NAME] [--plant F]
//                    [--domain N]
//     Publishes an Intervention and waits until the scheduler acknowledged it (it re-arms the
//     held check when KIND names it, and keeps the intervention in its outbox until the historian
//     stored it). Prints its id, and what the scheduler said when it changed nothing.
//
// Exit codes: 0, 1 when no scheduler acknowledges it, 2 bad usage, 9 refused by the scheduler.
#include "commands.hpp"

#include "ncqual/dds/acknowledged_send.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/participant.hpp"
#include "ncqual/dds/topics.hpp"

#include <chrono>
#include <iostream>

namespace ncqual::cli {
namespace {

struct Options {
  DdsOptions dds;
  std::string machine, note;
  std::optional<CheckKind> kind;
  std::optional<std::string> who;
};

int run(const Options& o) {
  const PlantConfig plant = plant_from(o.dds.plant);
  const std::string machine = configured_machine(plant, o.machine).machine_id;
  const std::string kind_name(to_string(*o.kind));
  if (o.note.find_first_not_of(" \t") == std::string::npos) {
    throw UsageError("--note is empty: say what was done (e.g. \"stylus replaced\")");
  }
  const std::string who = o.who.value_or(operator_name());
  const Intervention iv{machine, new_sample_id("iv", machine), *o.kind, o.note,
                        who,     WallClock().now_ns()};
  const ncqual::dds::ParticipantOptions options =
      command_participant(plant, o.dds, "ncqual-cli", operator_identity());
  const int domain = options.domain_id;
  ncqual::dds::Participant participant(options);
  ncqual::dds::Writer<ncqual::dds::InterventionTopic> writer(participant);
  const ncqual::dds::OrderOutcome order = ncqual::dds::send_acknowledged(
      participant, writer, iv, {roles::kScheduler}, std::chrono::seconds(15));
  if (!order.silent.empty()) {
    std::cerr << "ncqual intervene: no scheduler acknowledged intervention " << iv.intervention_id
              << " within 15 s: is a scheduler serving " << machine << " running on domain "
              << domain << "?\n";
    return kExitError;
  }
  if (const Acknowledgement* refused = order.refused()) {
    std::cerr << "ncqual intervene: the scheduler refused " << iv.intervention_id << ": "
              << refused->detail << "\n";
    return kExitRefused;
  }
  std::cerr << "recorded intervention on " << machine << " for " << kind_name << " by " << who
            << "\n";
  const std::string& said = order.answers.at(roles::kScheduler).detail;
  if (!said.empty()) std::cerr << "the scheduler: " << said << "\n";
  std::cout << iv.intervention_id << "\n";
  return kExitOk;
}

}  // namespace

void add_intervene(CLI::App& app, Commands& commands) {
  const auto [cmd, o] =
      add_command(app, commands, "intervene",
                  "record a physical intervention: re-arms the machine's held check", run);
  add_machine_option(cmd, o->machine, "the machine worked on");
  add_kind_option(cmd, "--check", o->kind, "the held check the intervention answers")->required();
  cmd->add_option("--note", o->note, "what was done (e.g. \"stylus replaced\")")
      ->type_name("TEXT")
      ->required();
  cmd->add_option("--operator", o->who, "who did it (default: $USER)")->type_name("NAME");
  add_dds_options(cmd, o->dds);
}

}  // namespace ncqual::cli
