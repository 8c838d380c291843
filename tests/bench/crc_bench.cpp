// SPDX-License-Identifier: Apache-2.0
// Benchmark of the MCAP library's CRC32 (mcap/src/crc32.cpp: its own carry-less folding, zlib's
// crc32_z for the rest) beside zlib's crc32_z alone, the rule of issue 36 being zlib where it is
// as fast and our own only where it wins clearly (by kClearWin or more on every size): MB/s on
// 1 KiB, 64 KiB and 4 MiB buffers, each as a multiple of zlib's. What of the own CRC did not
// win is zlib's already (the slicing-by-8 tables at 0.52-0.77 x zlib's, crc32_combine at
// 0.08-0.13 x; the figures are in crc32.cpp). Each figure is the best of --runs runs of about
// --mib MiB. Prints the figures and whether the folding still wins clearly; exits 0 once
// measured (whatever the figures), 1 when the two disagree on a CRC, 2 for bad usage.
#include "bench_support.hpp"

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

// The bench's command line: what it does and Options.
void add_options(CLI::App& app, Options& options) {
  app.description("The MCAP library's CRC32 beside zlib's crc32_z alone.");
  bench::add_bounded(app, "--mib", options.mib, "MiB checksummed in each run of each buffer size",
                     1, 4096);
  bench::add_bounded(app, "--runs", options.runs, "runs whose best is shown", 1, 100);
}

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

int run(const Options& o) {
#if defined(__x86_64__)
  const bool folds = __builtin_cpu_supports("pclmul") && __builtin_cpu_supports("sse4.1");
#else
  const bool folds = false;
#endif
  std::printf(
      "ncqual CRC32 bench: mcap::crc32 (carry-less folding: %s) beside zlib %s "
      "crc32_z, best of %d runs of %d MiB\n\n",
      folds ? "yes" : "no, zlib's alone", zlibVersion(), o.runs, o.mib);
  std::printf("  %-9s  %-18s %14s\n", "buffer", "mcap::crc32", "zlib crc32_z");
  const auto total = static_cast<std::size_t>(o.mib) << 20;
  Worst worst;
  bool agree = true;
  for (const std::size_t size : kSizes) {
    const std::string bytes = pattern(size);
    const std::string_view view(bytes);
    const auto* data = reinterpret_cast<const Bytef*>(bytes.data());
    const std::size_t calls = std::max<std::size_t>(1, total / size);
    std::uint32_t own = 0;
    std::uint32_t zlib = 0;
    const double own_s = best_seconds(
        o.runs, calls, [&](std::uint32_t c) { return mcap::crc32(view, c); }, own);
    const double zlib_s = best_seconds(
        o.runs, calls,
        [&](std::uint32_t c) { return static_cast<std::uint32_t>(crc32_z(c, data, size)); }, zlib);
    agree = agree && own == zlib;
    const double mb = static_cast<double>(calls * size) / 1e6;
    worst.add(zlib_s / own_s);
    std::printf("  %-9s  %6.0f MB/s %5.2f x %9.0f MB/s\n", size_name(size).c_str(), mb / own_s,
                zlib_s / own_s, mb / zlib_s);
  }
  if (!agree) {
    std::printf("\n  mcap's and zlib's CRCs DISAGREE\n");
    return 1;
  }
  std::printf(
      "\n  mcap::crc32 is %.2f x zlib's crc32_z at the least: %s (issue 36: %.1f x on every "
      "size)\n",
      worst.ratio,
      worst.ratio >= kClearWin ? "the folding wins clearly, keep it"
                               : "zlib is as fast, drop the folding",
      kClearWin);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return bench::bench_main(argc, argv, "ncqual_crc_bench", add_options, run);
}
