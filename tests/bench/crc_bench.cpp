// SPDX-License-Identifier: Apache-2.0
// Benchmark of the MCAP library's own CRC32 (mcap/src/crc32.cpp) beside zlib's, which a
// recording could use instead (issue 36: zlib where it is as fast; our own only where it wins
// clearly, by kClearWin or more on every size):
//   (a) MB/s of mcap::crc32 (carry-less folding where the CPU has it), of mcap::crc32_portable
//       (slicing-by-8 tables, what other CPUs and short tails get) and of zlib's crc32_z, on
//       1 KiB, 64 KiB and 4 MiB buffers, each as a multiple of zlib's;
//   (b) ns per call of mcap::crc32_combine and zlib's crc32_combine for the same lengths (the
//       writer combines an uncompressed chunk's CRC into the data section's).
// Each figure is the best of --runs runs of about --mib MiB. Prints the figures and, for each
// of the three, whether it wins clearly; exits 0 once measured (whatever the figures), 1 when
// ours and zlib's disagree on a CRC, 2 for bad usage.
#include "ncqual/common/command_line.hpp"
#include "ncqual/mcap/mcap.hpp"

#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace {

using namespace ncqual;
using Clock = std::chrono::steady_clock;

// "Wins clearly": at least this many times zlib's speed, on every size.
constexpr double kClearWin = 1.5;
constexpr std::size_t kSizes[] = {std::size_t{1} << 10, std::size_t{64} << 10,
                                  std::size_t{4} << 20};

struct Options {
  int mib = 256;
  int runs = 5;
};

// Bytes that are not all alike (a multiplicative hash of the index), the same on every run.
std::string pattern(std::size_t size) {
  std::string bytes(size, '\0');
  for (std::size_t i = 0; i < size; ++i) {
    bytes[i] = static_cast<char>((i * 2654435761U) >> 13);
  }
  return bytes;
}

// The best of `runs` times (s) of `calls` calls of `crc`, each chained onto the previous CRC;
// `last` gets the final CRC.
template <typename Crc>
double best_seconds(int runs, std::size_t calls, Crc&& crc, std::uint32_t& last) {
  double best = 0;
  for (int run = 0; run < runs; ++run) {
    const auto t0 = Clock::now();
    std::uint32_t c = 0;
    for (std::size_t i = 0; i < calls; ++i) c = crc(c);
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    if (run == 0 || s < best) best = s;
    last = c;
  }
  return best;
}

std::string size_name(std::size_t size) {
  return size >= (std::size_t{1} << 20) ? std::to_string(size >> 20) + " MiB"
                                        : std::to_string(size >> 10) + " KiB";
}

// The lowest of a speed ratio (ours / zlib's) over the sizes.
struct Worst {
  double ratio = 0;
  void add(double r) { ratio = ratio == 0 ? r : std::min(ratio, r); }
};

void verdict(const char* what, const Worst& worst) {
  std::printf("      %-28s %5.2f x zlib's at the least: %s\n", what, worst.ratio,
              worst.ratio >= kClearWin ? "wins clearly, keep it" : "zlib is as fast, use zlib");
}

int run(const Options& o) {
#if defined(__x86_64__)
  const bool folds = __builtin_cpu_supports("pclmul") && __builtin_cpu_supports("sse4.1");
#else
  const bool folds = false;
#endif
  std::printf(
      "ncqual CRC32 bench: mcap's CRC32 (carry-less folding: %s) beside zlib %s, "
      "best of %d runs of %d MiB\n\n",
      folds ? "yes" : "no, tables", zlibVersion(), o.runs, o.mib);
  std::printf("  (a) %-9s  %-18s %-18s %14s\n", "buffer", "mcap::crc32", "crc32_portable",
              "zlib crc32_z");
  const auto total = static_cast<std::size_t>(o.mib) << 20;
  Worst folded;
  Worst tables;
  Worst combined;
  bool agree = true;
  for (const std::size_t size : kSizes) {
    const std::string bytes = pattern(size);
    const std::string_view view(bytes);
    const auto* data = reinterpret_cast<const Bytef*>(bytes.data());
    const std::size_t calls = std::max<std::size_t>(1, total / size);
    std::uint32_t own = 0;
    std::uint32_t portable = 0;
    std::uint32_t zlib = 0;
    const double own_s = best_seconds(
        o.runs, calls, [&](std::uint32_t c) { return mcap::crc32(view, c); }, own);
    const double portable_s = best_seconds(
        o.runs, calls, [&](std::uint32_t c) { return mcap::crc32_portable(view, c); }, portable);
    const double zlib_s = best_seconds(
        o.runs, calls,
        [&](std::uint32_t c) { return static_cast<std::uint32_t>(crc32_z(c, data, size)); }, zlib);
    agree = agree && own == zlib && portable == zlib;
    const double mb = static_cast<double>(calls * size) / 1e6;
    folded.add(zlib_s / own_s);
    tables.add(zlib_s / portable_s);
    std::printf("      %-9s %6.0f MB/s %5.2f x %6.0f MB/s %5.2f x %9.0f MB/s\n",
                size_name(size).c_str(), mb / own_s, zlib_s / own_s, mb / portable_s,
                zlib_s / portable_s, mb / zlib_s);
  }

  std::printf("\n  (b) %-9s  %-20s %14s\n", "length", "mcap::crc32_combine", "zlib's");
  const std::uint32_t crc_a = mcap::crc32("123456789");
  const std::size_t calls = std::max<std::size_t>(1000, total >> 10);
  for (const std::size_t size : kSizes) {
    const std::uint32_t crc_b = mcap::crc32(pattern(size));
    std::uint32_t own = 0;
    std::uint32_t zlib = 0;
    // Chained through the previous CRC so that no call can be hoisted out of the loop.
    const double own_s = best_seconds(
        o.runs, calls, [&](std::uint32_t c) { return mcap::crc32_combine(c ^ crc_a, crc_b, size); },
        own);
    const double zlib_s = best_seconds(
        o.runs, calls,
        [&](std::uint32_t c) {
          return static_cast<std::uint32_t>(
              crc32_combine(c ^ crc_a, crc_b, static_cast<z_off_t>(size)));
        },
        zlib);
    agree = agree && own == zlib;
    combined.add(zlib_s / own_s);
    std::printf("      %-9s %9.0f ns %5.2f x %11.0f ns\n", size_name(size).c_str(),
                own_s / static_cast<double>(calls) * 1e9, zlib_s / own_s,
                zlib_s / static_cast<double>(calls) * 1e9);
  }

  if (!agree) {
    std::printf("\n  mcap's and zlib's CRCs DISAGREE\n");
    return 1;
  }
  std::printf("\n  issue 36: our own only where it wins clearly (%.1f x zlib's on every size)\n",
              kClearWin);
  verdict("mcap::crc32 (folding)", folded);
  verdict("crc32_portable (tables)", tables);
  verdict("mcap::crc32_combine", combined);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return command_line::guarded_main("ncqual_crc_bench", [&] {
    CLI::App app("The MCAP library's CRC32 beside zlib's crc32_z and crc32_combine.",
                 "ncqual_crc_bench");
    command_line::configure(app);
    Options options;
    app.add_option("--mib", options.mib, "MiB checksummed in each run of each buffer size")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    app.add_option("--runs", options.runs, "runs whose best is shown")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    if (const auto code = command_line::parse(app, argc, argv)) return *code;
    return run(options);
  });
}
