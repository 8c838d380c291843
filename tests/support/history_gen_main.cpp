// SPDX-License-Identifier: Apache-2.0
// ncqual-generate-history: writes a generated historian (history_gen.hpp) and says what it made.
//   ncqual-generate-history --machines N --days D --out FILE.db [--seed S] [--watch] [--monthly]
//                           [--start 2026-01-05T00:00:00Z] [--machine-file
//                           deploy/machines/pm1.yaml]
// The file must not exist yet. Exit 0 when written, 2 for a bad command line, 1 for a failure.
#include "history_gen.hpp"

#include "ncqual/common/clock.hpp"

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

namespace {

int usage(const std::string& problem) {
  std::fprintf(stderr,
               "ncqual-generate-history: %s\n"
               "usage: ncqual-generate-history --machines N --days D --out FILE.db [--seed S] "
               "[--watch] [--monthly] [--start ISO8601] [--machine-file FILE]\n",
               problem.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  ncqual::history::GenerateOptions options;
  options.machine_file = std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml";
  std::string out;
  try {
    for (int i = 1; i < argc; ++i) {
      if (ncqual::history::read_generate_option(argc, argv, i, options)) continue;
      const std::string arg = argv[i];
      if (arg == "--out") {
        out = ncqual::history::option_value(argc, argv, i);
      } else if (arg == "--machine-file") {
        options.machine_file = ncqual::history::option_value(argc, argv, i);
      } else if (arg == "--start") {
        const std::string text = ncqual::history::option_value(argc, argv, i);
        const auto t = ncqual::parse_iso8601(text);
        if (!t) throw std::invalid_argument("--start '" + text + "' is not an ISO 8601 UTC time");
        options.start_ns = *t;
      } else {
        return usage("unknown argument '" + arg + "'");
      }
    }
  } catch (const std::exception& e) {
    return usage(e.what());
  }
  if (out.empty()) return usage("--out FILE.db is required");
  if (options.machines < 1 || options.days < 1) return usage("--machines and --days must be >= 1");
  if (std::filesystem::exists(out)) return usage("'" + out + "' exists already");
  try {
    ncqual::history::GenerateReport r;
    {
      auto db = ncqual::storage::Database::open(out);
      const int every = options.days >= 60 ? 30 : 0;
      options.progress = [&](int day) {
        if (every && (day + 1) % every == 0) {
          std::fprintf(stderr, "  day %d of %d\n", day + 1, options.days);
        }
      };
      r = ncqual::history::generate_history(db, options);
    }
    char first[32], last[32];
    std::printf("generated %s: %d machines (%d drifting, %d sudden faults), %d days from %s\n",
                out.c_str(), options.machines, r.drifting, r.faults, options.days,
                std::string(ncqual::format_iso8601(options.start_ns, first)).c_str());
    std::printf("  checks %lld (pass %lld, fail %lld, invalid %lld; monthly tracker %lld)\n",
                static_cast<long long>(r.checks), static_cast<long long>(r.passed),
                static_cast<long long>(r.failed), static_cast<long long>(r.invalid),
                static_cast<long long>(r.monthly_checks));
    std::printf("  interventions %lld, compensations %lld, status changes %lld\n",
                static_cast<long long>(r.interventions), static_cast<long long>(r.compensations),
                static_cast<long long>(r.statuses));
    if (options.watch) {
      std::printf("  trend warnings raised %lld, ended %lld\n",
                  static_cast<long long>(r.warnings_raised),
                  static_cast<long long>(r.warnings_ended));
    }
    std::printf("  samples from %s to %s\n",
                std::string(ncqual::format_iso8601(r.first_ns, first)).c_str(),
                std::string(ncqual::format_iso8601(r.last_ns, last)).c_str());
    std::printf(
        "  file %.1f MB; wall time %.1f s (storing %.1f s, monthly tracker %.1f s, trend "
        "watch %.1f s)\n",
        static_cast<double>(std::filesystem::file_size(out)) / (1024.0 * 1024.0), r.seconds,
        r.store_seconds, r.monthly_seconds, r.watch_seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ncqual-generate-history: %s\n", e.what());
    return 1;
  }
}
