// SPDX-License-Identifier: Apache-2.0
// Command lines of the ncqual executables, on CLI11 (Debian's libcli11-dev, 2.1): the settings
// every executable shares, --version, the options every service takes, and parsing with
// ncqual's exit codes (0 after --help and --version, 2 for bad usage). An unknown flag or a
// missing value is an error that names the flag, so a typo never silently changes behaviour.
// Link ncqual_command_line.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <string>

namespace ncqual::command_line {

// The exit code of bad usage, for every ncqual executable.
constexpr int kUsageExit = 2;

// Sets up `app` as every ncqual executable's: "usage:" help, a repeated option's last value
// wins (as it always did), and --version printing version_line(app name).
void configure(CLI::App& app);

// Parses the command line. Returns nothing when the program goes on; else the code to exit
// with: 0 after printing the help or the version (stdout), kUsageExit after reporting bad usage
// through `on_usage_error`, by default "<app>: <message>" and a pointer to --help on stderr.
using UsageReporter = std::function<void(const CLI::App& app, const std::string& message)>;
std::optional<int> parse(CLI::App& app, int argc, char** argv,
                         const UsageReporter& on_usage_error = {});

// The options every service takes. Empty plant and domain -1 mean "not given": the plant file
// then comes from NCQUAL_PLANT (dds::plant_file_from), the domain from NCQUAL_DOMAIN or the plant
// (dds::resolve_domain_id).
struct ServiceOptions {
  std::string plant;
  int domain = -1;
  std::string log_level = "info";
  std::string secure;    // --secure DIR: ncqual-pki's material (else the plant's security.dir)
  std::string identity;  // --identity NAME (else the service's own: docs/deploy.md)
};

// Adds --plant FILE, --domain N, --log-level LEVEL, --secure DIR and --identity NAME to a
// service's `app`.
void add_service_options(CLI::App& app, ServiceOptions& options);

// Every executable's main: runs `body` and returns its exit code; an exception that escapes it
// (building the command line can throw too) is printed as "<program>: <what>" on stderr and
// exits 1. main() itself then never throws.
int guarded_main(const char* program, const std::function<int()>& body) noexcept;

}  // namespace ncqual::command_line
