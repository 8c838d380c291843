// SPDX-License-Identifier: Apache-2.0
// Reproducible randomness: one generator per request, seeded from the config seed and a stable
// hash of the request id, so a request yields the same touches whatever was asked before it.
#pragma once

#include <cstdint>
#include <random>
#include <string_view>

namespace ncqual::sim {

// 64-bit FNV-1a of the bytes of `text` (offset basis 0xcbf29ce484222325, prime 0x100000001b3).
std::uint64_t fnv1a_64(std::string_view text);

// Seed of a request's generator: splitmix64(seed ^ fnv1a_64(request_id)).
std::uint64_t request_seed(std::uint64_t seed, std::string_view request_id);

// Standard normal deviates from mt19937_64 by the Box-Muller transform, written out here so the
// sequence is the same with every standard library (std::normal_distribution is not).
class NormalSource {
 public:
  explicit NormalSource(std::uint64_t seed) : engine_(seed) {}
  double next();

 private:
  double uniform_open_closed();  // in (0, 1]
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0;
};

}  // namespace ncqual::sim
