// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/command_line.hpp"

#include "ncqual/common/version.hpp"

#include <iostream>

namespace ncqual::command_line {

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
    if (on_usage_error) {
      on_usage_error(app, e.what());
    } else {
      std::cerr << app.get_name() << ": " << e.what() << "\n(" << app.get_name()
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
