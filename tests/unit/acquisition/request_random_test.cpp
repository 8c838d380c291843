// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/request_random.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

namespace ncqual::sim {
namespace {

TEST(RequestRandom, Fnv1aMatchesPublishedTestVectors) {
  // Test vectors from the FNV reference (Fowler, Noll, Vo), 64-bit FNV-1a.
  EXPECT_EQ(fnv1a_64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(fnv1a_64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(fnv1a_64("foobar"), 0x85944171f73967e8ULL);
}

TEST(RequestRandom, SeedsDifferAcrossIdsAndConfigSeeds) {
  std::set<std::uint64_t> seen;
  for (int s = 0; s < 10; ++s) {
    for (int i = 0; i < 100; ++i) {
      seen.insert(request_seed(static_cast<std::uint64_t>(s), "req-" + std::to_string(i)));
    }
  }
  EXPECT_EQ(seen.size(), 1000u);
  EXPECT_EQ(request_seed(42, "r"), request_seed(42, "r"));
}

TEST(RequestRandom, NormalSourceIsStandardNormal) {
  NormalSource source(request_seed(3, "stats"));
  const int n = 200000;
  double sum = 0, sum_sq = 0;
  int beyond_2 = 0;
  for (int i = 0; i < n; ++i) {
    const double z = source.next();
    ASSERT_TRUE(std::isfinite(z));
    sum += z;
    sum_sq += z * z;
    beyond_2 += std::abs(z) > 2 ? 1 : 0;
  }
  const double mean = sum / n;
  const double var = sum_sq / n - mean * mean;
  // Standard errors: mean 1/sqrt(n) = 0.0022, variance sqrt(2/n) = 0.0032; allow 5 of them.
  EXPECT_NEAR(mean, 0.0, 5 / std::sqrt(n));
  EXPECT_NEAR(var, 1.0, 5 * std::sqrt(2.0 / n));
  // P(|z| > 2) = 0.0455; binomial standard error sqrt(p (1 - p) / n) = 0.00047.
  EXPECT_NEAR(static_cast<double>(beyond_2) / n, 0.0455, 5 * 0.00047);
}

TEST(RequestRandom, SameSeedSameSequence) {
  NormalSource a(99), b(99), c(100);
  bool any_different = false;
  for (int i = 0; i < 100; ++i) {
    const double x = a.next();
    EXPECT_EQ(x, b.next());
    any_different |= x != c.next();
  }
  EXPECT_TRUE(any_different);
}

}  // namespace
}  // namespace ncqual::sim
