// SPDX-License-Identifier: Apache-2.0
// ncqual: the operator's command-line tool. One CLI11 app; each command is a file under
// commands/ (commands.hpp). This file builds the app, parses and dispatches. `ncqual --help`
// lists the commands with their synopses, `ncqual <command> --help` a command's options.
#include "commands/commands.hpp"
#include "exit_codes.hpp"
#include "help.hpp"

#include "ncqual/common/command_line.hpp"
#include "ncqual/common/config.hpp"
#include "ncqual/common/csv.hpp"

#include <spdlog/spdlog.h>

#include <iostream>
#include <memory>
#include <string>

namespace {

using namespace ncqual;
using namespace ncqual::cli;

constexpr const char* kFooter =
    "The plant config comes from --plant or NCQUAL_PLANT; the domain from --domain,\n"
    "NCQUAL_DOMAIN or the plant config. `ncqual <command> --help` describes a command.\n";

// The command named on the command line (first level: `analyze` for `analyze circle`), else the
// app itself.
const CLI::App& named_command(const CLI::App& app) {
  const auto parsed = app.get_subcommands();
  return parsed.empty() ? app : *parsed.front();
}

// Bad usage: the message, then the usage of the command it concerns.
void report_usage_error(const CLI::App& app, const std::string& message) {
  const CLI::App& command = named_command(app);
  const std::string name =
      &command == &app ? app.get_name() : app.get_name() + " " + command.get_name();
  // CLI11 says only that a subcommand is required when the word given is not one: name it.
  const auto extra = command.remaining();
  const bool unknown = command.get_require_subcommand_min() > 0 &&
                       command.get_subcommands().empty() && !extra.empty();
  std::cerr << name << ": " << (unknown ? "'" + extra.front() + "' is not a command" : message)
            << "\n"
            << command.get_formatter()->make_help(&command, name, CLI::AppFormatMode::Normal);
}

int run(int argc, char** argv) {
  CLI::App app("ncqual: the operator's tool of the plant's qualification process", "ncqual");
  command_line::configure(app);
  app.formatter(std::make_shared<HelpFormatter>());
  app.require_subcommand(1);
  Commands commands;
  for (auto add : {add_history, add_check, add_wait, add_count, add_budget, add_analyze, add_import,
                   add_program, add_status, add_intervene, add_trend, add_uncertainty, add_config,
                   add_db, add_export, add_backup, add_record, add_replay, add_report}) {
    add(app, commands);
  }
  for (CLI::App* command : app.get_subcommands({})) command->group("Commands");
  app.footer(std::string(kFooter) + kExitCodesHelp);  // after the commands: theirs have none
  add_completion(app, commands);  // hidden: not in the help, derived from everything above

  if (argc < 2) {  // no command: the help on stdout, as bad usage
    std::cout << app.help();
    return kExitUsage;
  }
  std::vector<char*> words(argv, argv + argc);
  std::string help_flag = "--help";
  if (argc == 2 && std::string(argv[1]) == "help") words[1] = help_flag.data();  // `ncqual help`
  if (const auto code = command_line::parse(app, static_cast<int>(words.size()), words.data(),
                                            report_usage_error)) {
    return *code;
  }

  spdlog::set_level(spdlog::level::warn);
  const std::string name = "ncqual " + named_command(app).get_name();
  for (const Command& command : commands) {
    if (!command.app->parsed()) continue;
    try {
      return command.run();
    } catch (const UsageError& e) {
      report_usage_error(app, e.what());
      return kExitUsage;
    } catch (const CsvError& e) {
      std::cerr << e.what() << "\n";  // "<file>:<line>:<column>: message"
      return kExitError;
    } catch (const std::exception& e) {
      std::cerr << name << ": " << e.what() << "\n";
      return kExitError;
    }
  }
  report_usage_error(app, "say what to do");
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  return ncqual::command_line::guarded_main("ncqual", [&] { return run(argc, argv); });
}
