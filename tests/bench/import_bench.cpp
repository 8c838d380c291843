// SPDX-License-Identifier: Apache-2.0
// Benchmark of a large import: `ncqual import circle` of a ballbar-like file of --points points
// (default 1,000,000, both directions) into a real ncqual-historian and ncqual-solver over Fast DDS
// on a private domain, their SQLite files in a temporary directory, as a plant would run it.
// Prints, beside their targets:
//   import        from starting `ncqual import` until it exits 0 (the historian stored the set and
//                 the solver saved its result: the command waits for both acknowledgements)
//   per point     that time over the points
//   peak memory   of the historian and the solver (VmHWM: the most each held at once)
// The file is written first and not timed. Exits 0 once measured (whatever the figures), 1 when
// the import failed (its output and the services' logs are printed), 2 for bad usage.
#include "bench_support.hpp"
#include "harness.hpp"

#include <sys/types.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace {

using namespace ncqual;
using Clock = std::chrono::steady_clock;

// Targets (issue 13): a 1,000,000-point file imports in under a minute. Memory: a service that
// holds a set of a million points holds about 100 MB of it per copy (DDS sample, model, SQLite
// statement); 2 GB leaves a plant's historian host room for everything else.
constexpr double kTargetImportS = 60;
constexpr double kTargetPeakMb = 2048;

struct Options {
  int points = 1000000;
};

// The bench's command line: what it does and Options.
void add_options(CLI::App& app, Options& options) {
  app.description(
      "The time and memory of a large import: `ncqual import circle` of a generated file into "
      "a real ncqual-historian and ncqual-solver.");
  bench::add_bounded(app, "--points", options.points, "points in the circle file (both directions)",
                     2, 5000000);
}

// The largest resident size `pid` has had, in MB, from /proc (0 when it cannot be read).
double peak_mb(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0;
}

void print_row(const char* figure, double value, const char* target, const char* judged) {
  std::printf("  %-28s %12.2f   %-10s %s\n", figure, value, target, judged);
}

const char* judge(bool met) { return met ? "PASS" : "MISS"; }

int run(const Options& options) {
  testing::Plant plant("import-bench", testing::TestDomain::ImportBench);
  plant.add_machine("pm1", "extends: " NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml\n");
  plant.write_plant("[]");
  testing::Process& historian = plant.start("historian");
  testing::Process& solver = plant.start("solver");

  // Both directions of a 150 mm circle with 2 um of ovality, as a ballbar exports it.
  const std::string file = (plant.dir() / "circle.csv").string();
  {
    std::ofstream out(file);
    out.precision(10);
    out << "x_mm,y_mm,direction\n";
    const int per_direction = options.points / 2;
    for (int d = 0; d < 2; ++d) {
      for (int i = 0; i < per_direction; ++i) {
        const double a = 2 * 3.14159265358979323846 * i / per_direction;
        const double r = 150 + 0.002 * std::cos(2 * a);
        out << r * std::cos(a) << "," << (d == 0 ? 1 : -1) * r * std::sin(a) << ","
            << (d == 0 ? "ccw" : "cw") << "\n";
      }
    }
  }
  const int points = options.points / 2 * 2;
  std::printf("ncqual import bench: %d points (%s)\n", points, file.c_str());
  std::printf("  historian %s, DDS domain %d\n\n", plant.db_path().c_str(), plant.domain());

  const Clock::time_point start = Clock::now();
  const testing::Outcome import = testing::run(testing::Launch(
      {testing::Plant::executable("ncqual"), "import", "circle", file, "--machine", "pm1",
       "--plant", plant.plant_file(), "--domain", std::to_string(plant.domain())},
      testing::Output::Merged));
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  if (import.exit_code != 0) {
    std::fprintf(stderr,
                 "import bench: ncqual import exited %d after %.1f s:\n%s\n--- historian ---\n%s\n"
                 "--- solver ---\n%s\n",
                 import.exit_code, seconds, import.out.c_str(), plant.log("historian").c_str(),
                 plant.log("solver").c_str());
    return 1;
  }
  const double historian_mb = peak_mb(historian.pid());
  const double solver_mb = peak_mb(solver.pid());
  std::printf("  %-28s %12s   %-10s\n", "figure", "value", "target");
  // The target is for a million points; a smaller file's time is mostly the fixed cost of
  // discovery and acknowledgements, so it is shown and not judged.
  print_row("import, s", seconds, "<= 60",
            points >= 1000000 ? judge(seconds <= kTargetImportS) : "(judged at 1e6 points)");
  print_row("per point, us", seconds * 1e6 / points, "", "");
  print_row("historian peak memory, MB", historian_mb, "<= 2048",
            judge(historian_mb <= kTargetPeakMb));
  print_row("solver peak memory, MB", solver_mb, "<= 2048", judge(solver_mb <= kTargetPeakMb));
  std::printf(
      "\n  import: from starting `ncqual import` until both acknowledgements (stored, "
      "judged)\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main(argc, argv, "ncqual_import_bench", add_options, run);
}
