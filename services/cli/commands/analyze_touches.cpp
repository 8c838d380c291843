// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze touches`: a real control's touch log of a program `ncqual program` wrote,
// judged as the solver service judges the check (judge_files, analyze.cpp).
#include "analyze.hpp"

namespace ncqual::cli::analysis {
namespace {

int run_touches(const Options& o) {
  return judge_files(o, touches_from_files, "touches", "program");
}

}  // namespace

void add_touches(CLI::App* analyze, const std::shared_ptr<Options>& o, Commands& commands) {
  CLI::App* touches = analyze->add_subcommand(
      "touches",
      "judge a real control's touch log of a program written by `ncqual program`, exactly as\n"
      "the solver service judges the check (exit code: its verdict)");
  touches->add_option("LOG", o->file, "the control's touch log")->required();
  touches->add_option("--program", o->program, "the program that wrote it")
      ->type_name("PROG")
      ->required();
  add_machine_option(touches, o->machine, "the machine that ran it");
  add_plant_option(touches, o->plant);
  add_json_flag(touches, o->json);
  commands.push_back({touches, [o] { return refusing(o->file, run_touches, *o); }});
}

}  // namespace ncqual::cli::analysis
