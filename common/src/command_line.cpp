// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/command_line.hpp"

#include "ncqual/common/text.hpp"
#include "ncqual/common/version.hpp"

#include <iostream>
#include <vector>

namespace ncqual::command_line {
namespace {

// The innermost (sub)command the command line named.
const CLI::App& innermost(const CLI::App& app) {
  const CLI::App* at = &app;
  for (auto parsed = at->get_subcommands(); !parsed.empty(); parsed = at->get_subcommands()) {
    at = parsed.front();
  }
  return *at;
}

// For words CLI11 did not expect: "'--machin' is not an option of ncqual history; did you mean
// '--machine'?" for the first one that looks like a flag, naming the nearest flag of the command
// it was given to when it is a likely typo; empty when no word looks like a flag.
std::string unknown_flag_message(const CLI::App& app) {
  const CLI::App& command = innermost(app);
  std::vector<std::string> flags;
  for (const CLI::Option* option : command.get_options()) {
    for (const auto& name : option->get_lnames()) flags.push_back("--" + name);
    for (const auto& name : option->get_snames()) flags.push_back("-" + name);
  }
  for (std::string word : app.remaining(true)) {
    if (word.size() < 2 || word[0] != '-') continue;
    word = word.substr(0, word.find('='));
    std::string path = command.get_name();
    for (const CLI::App* p = command.get_parent(); p; p = p->get_parent()) {
      path = p->get_name() + " " + path;
    }
    const auto best = closest_word(word, {flags.begin(), flags.end()});
    return "'" + word + "' is not an option of " + path +
           (best ? "; did you mean '" + std::string(*best) + "'?" : "");
  }
  return "";
}

}  // namespace

void configure(CLI::App& app) {
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.get_formatter()->label("Usage", "usage");
  app.set_version_flag(
      "--version", [&app] { return version_line(app.get_name()); }, "print the version and exit");
}

std::optional<int> parse(CLI::App& app, int argc, char** argv,
                         const UsageReporter& on_usage_error) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();  // the help of the (sub)command it was asked of
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion& e) {
    std::cout << e.what() << "\n";
    return 0;
  } catch (const CLI::ParseError& e) {
    std::string message = e.what();
    if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
      if (std::string flag = unknown_flag_message(app); !flag.empty()) message = flag;
    }
    if (on_usage_error) {
      on_usage_error(app, message);
    } else {
      std::cerr << app.get_name() << ": " << message << "\n(" << app.get_name()
                << " --help shows the usage)\n";
    }
    return kUsageExit;
  }
}

void add_service_options(CLI::App& app, ServiceOptions& options) {
  app.add_option("--plant", options.plant, "the plant config (default: $NCQUAL_PLANT)")
      ->type_name("FILE");
  app.add_option("--domain", options.domain,
                 "the DDS domain (default: $NCQUAL_DOMAIN, else the plant's domain_id)")
      ->type_name("N");
  app.add_option("--log-level", options.log_level, "trace, debug, info, warn or error")
      ->type_name("LEVEL")
      ->capture_default_str();
  app.add_option("--secure", options.secure,
                 "run secured with this ncqual-pki directory (default: the plant's security.dir)")
      ->type_name("DIR");
  app.add_option("--identity", options.identity,
                 "the identity to run as on a secured plant (default: the service's name; "
                 "an acquisition's: acquisition-<machine>)")
      ->type_name("NAME");
}

int guarded_main(const char* program, const std::function<int()>& body) noexcept {
  try {
    return body();
  } catch (const std::exception& e) {
    std::cerr << program << ": " << e.what() << "\n";
  } catch (...) {
    std::cerr << program << ": unknown exception\n";
  }
  return 1;
}

}  // namespace ncqual::command_line
