// SPDX-License-Identifier: Apache-2.0
// What the benches share: summarising latencies, and the command line of their main().
#pragma once

#include "ncqual/common/command_line.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace ncqual::bench {

// Nearest-rank quantile, q in [0, 1] (0 for no values).
inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

// Adds the option `flag` to `app`, read into `value`, which must lie in [low, high]; --help shows
// its default.
inline CLI::Option* add_bounded(CLI::App& app, const std::string& flag, int& value,
                                const std::string& help, int low, int high) {
  return app.add_option(flag, value, help)->check(CLI::Range(low, high))->capture_default_str();
}

// --timeout-s: the patience, in seconds, of each of a bench's waits.
inline CLI::Option* add_timeout_option(CLI::App& app, int& timeout_s) {
  return add_bounded(app, "--timeout-s", timeout_s, "patience of each wait", 1, 3600);
}

// A bench's main(): parses the command line of `program` (add_options(app, options) describes
// the bench and adds its options) with ncqual's exit codes, then returns run(options). Guarded as
// every ncqual executable's main (command_line::guarded_main): it never throws.
template <class Options>
int bench_main(int argc, char** argv, const char* program,
               void (*add_options)(CLI::App& app, Options& options), int (*run)(const Options&)) {
  return command_line::guarded_main(program, [&] {
    CLI::App app("", program);
    command_line::configure(app);
    Options options;
    add_options(app, options);
    if (const auto code = command_line::parse(app, argc, argv)) return *code;
    return run(options);
  });
}

}  // namespace ncqual::bench
