// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/request_random.hpp"

#include <cmath>

namespace ncqual::sim {

std::uint64_t fnv1a_64(std::string_view text) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const char ch : text) {
    hash ^= static_cast<unsigned char>(ch);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

std::uint64_t request_seed(std::uint64_t seed, std::string_view request_id) {
  // splitmix64 finaliser: spreads nearby seeds and ids over the whole state.
  std::uint64_t z = (seed ^ fnv1a_64(request_id)) + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double NormalSource::uniform_open_closed() {
  // 53 random bits -> [0, 1) in steps of 2^-53; 1 - u lies in (0, 1].
  const double u = static_cast<double>(engine_() >> 11) * 0x1.0p-53;
  return 1.0 - u;
}

double NormalSource::next() {
  // Box-Muller: for u1 in (0, 1], u2 in [0, 1),
  //   z0 = sqrt(-2 ln u1) cos(2 pi u2),  z1 = sqrt(-2 ln u1) sin(2 pi u2)
  // are independent standard normal deviates.
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  const double u1 = uniform_open_closed();
  const double u2 = 1.0 - uniform_open_closed();
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * 3.14159265358979323846 * u2;
  spare_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
}

}  // namespace ncqual::sim
