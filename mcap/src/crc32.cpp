// SPDX-License-Identifier: Apache-2.0
// CRC32 of the reflected polynomial 0xEDB88320 (mcap.hpp's crc32, crc32_portable,
// crc32_combine): carry-less multiplication where the CPU has it, else eight bytes a step from
// tables.
#include "ncqual/mcap/mcap.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <array>
#include <cstddef>
#include <cstdint>

namespace ncqual::mcap {
namespace {

// Slicing-by-8 (Kounavis and Berry, "A Systematic Approach to Building High Performance
// Software-based CRC Generators", 2005): table[0] is the classic byte table, table[k][b] the CRC
// of byte b followed by k zero bytes, so eight bytes are folded in per step. About six times the
// byte-at-a-time loop, which a recorder's every byte passes through twice (a chunk's records,
// the data section).
using CrcTables = std::array<std::array<std::uint32_t, 256>, 8>;
CrcTables make_crc_tables() {
  CrcTables t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    t[0][i] = c;
  }
  for (std::uint32_t i = 0; i < 256; ++i) {
    for (std::size_t k = 1; k < 8; ++k) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFU];
  }
  return t;
}

// The CRC register (not inverted) after `n` bytes at `p`, eight bytes a step.
std::uint32_t crc32_tables(std::uint32_t c, const unsigned char* p, std::size_t n) {
  static const CrcTables t = make_crc_tables();
  for (; n >= 8; n -= 8, p += 8) {
    // The eight bytes as two little-endian words, whatever the host's byte order.
    const std::uint32_t lo = c ^ (std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 |
                                  std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24);
    const std::uint32_t hi = std::uint32_t{p[4]} | std::uint32_t{p[5]} << 8 |
                             std::uint32_t{p[6]} << 16 | std::uint32_t{p[7]} << 24;
    c = t[7][lo & 0xFFU] ^ t[6][(lo >> 8) & 0xFFU] ^ t[5][(lo >> 16) & 0xFFU] ^ t[4][lo >> 24] ^
        t[3][hi & 0xFFU] ^ t[2][(hi >> 8) & 0xFFU] ^ t[1][(hi >> 16) & 0xFFU] ^ t[0][hi >> 24];
  }
  for (; n > 0; --n, ++p) c = t[0][(c ^ *p) & 0xFFU] ^ (c >> 8);
  return c;
}

#if defined(__x86_64__)
// Folding with carry-less multiplication (Gopal et al., Intel, "Fast CRC Computation for Generic
// Polynomials Using PCLMULQDQ Instruction", 2009), for the reflected polynomial: four 128-bit
// lanes folded 64 bytes a step, then into one lane, then 128 -> 64 bits and a Barrett reduction
// to 32. The constants are x^k mod P for the fold distances, bit-reflected and shifted as the
// paper gives them for P = 0x104C11DB7: k1 = x^(4*128+32), k2 = x^(4*128-32), k3 = x^(128+32),
// k4 = x^(128-32), k5 = x^64, and mu = floor(x^64 / P). Several times the table's speed on a
// CPU that has the instruction; `n` is at least 64, the last n % 16 bytes are left to the caller.
__attribute__((target("pclmul,sse4.1"))) __m128i load(const unsigned char* at) {
  return _mm_loadu_si128(reinterpret_cast<const __m128i*>(at));
}
// x folded forward by the distance whose constants k holds, onto `next`.
__attribute__((target("pclmul,sse4.1"))) __m128i fold(__m128i x, __m128i k, __m128i next) {
  return _mm_xor_si128(
      _mm_xor_si128(_mm_clmulepi64_si128(x, k, 0x00), _mm_clmulepi64_si128(x, k, 0x11)), next);
}

__attribute__((target("pclmul,sse4.1"))) std::uint32_t crc32_folded(std::uint32_t c,
                                                                    const unsigned char* p,
                                                                    std::size_t n) {
  __m128i x1 = _mm_xor_si128(load(p), _mm_cvtsi32_si128(static_cast<int>(c)));
  __m128i x2 = load(p + 16);
  __m128i x3 = load(p + 32);
  __m128i x4 = load(p + 48);
  p += 64;
  n -= 64;
  const __m128i k1k2 = _mm_set_epi64x(0x01c6e41596LL, 0x0154442bd4LL);
  for (; n >= 64; n -= 64, p += 64) {
    x1 = fold(x1, k1k2, load(p));
    x2 = fold(x2, k1k2, load(p + 16));
    x3 = fold(x3, k1k2, load(p + 32));
    x4 = fold(x4, k1k2, load(p + 48));
  }
  const __m128i k3k4 = _mm_set_epi64x(0x00ccaa009eLL, 0x01751997d0LL);
  x1 = fold(x1, k3k4, x2);
  x1 = fold(x1, k3k4, x3);
  x1 = fold(x1, k3k4, x4);
  for (; n >= 16; n -= 16, p += 16) x1 = fold(x1, k3k4, load(p));
  // 128 -> 64 bits.
  const __m128i low32 = _mm_setr_epi32(-1, 0, -1, 0);
  x1 = _mm_xor_si128(_mm_srli_si128(x1, 8), _mm_clmulepi64_si128(x1, k3k4, 0x10));
  const __m128i k5 = _mm_set_epi64x(0, 0x0163cd6124LL);
  x1 = _mm_xor_si128(_mm_clmulepi64_si128(_mm_and_si128(x1, low32), k5, 0x00),
                     _mm_srli_si128(x1, 4));
  // Barrett reduction, 64 -> 32 bits.
  const __m128i poly_mu = _mm_set_epi64x(0x01f7011641LL, 0x01db710641LL);
  __m128i t = _mm_clmulepi64_si128(_mm_and_si128(x1, low32), poly_mu, 0x10);
  t = _mm_clmulepi64_si128(_mm_and_si128(t, low32), poly_mu, 0x00);
  return static_cast<std::uint32_t>(_mm_extract_epi32(_mm_xor_si128(x1, t), 1));
}

bool cpu_folds() {
  static const bool folds = __builtin_cpu_supports("pclmul") && __builtin_cpu_supports("sse4.1");
  return folds;
}
#endif

}  // namespace

std::uint32_t crc32(std::string_view bytes, std::uint32_t previous) {
  std::uint32_t c = ~previous;
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  std::size_t n = bytes.size();
#if defined(__x86_64__)
  if (n >= 64 && cpu_folds()) {
    const std::size_t folded = n - n % 16;
    c = crc32_folded(c, p, folded);
    p += folded;
    n -= folded;
  }
#endif
  return ~crc32_tables(c, p, n);
}

std::uint32_t crc32_portable(std::string_view bytes, std::uint32_t previous) {
  return ~crc32_tables(~previous, reinterpret_cast<const unsigned char*>(bytes.data()),
                       bytes.size());
}

namespace {

// CRC arithmetic in GF(2)[x] modulo the CRC polynomial, in the reflected representation (bit 31
// is x^0): the product of two residues, and x^(8 n), the effect of n zero bytes. With them the
// CRC of a + b follows from the CRCs of a and of b and b's length alone (crc32_combine), so the
// data section's CRC need not read a chunk's records a second time.
std::uint32_t multiply_mod_p(std::uint32_t a, std::uint32_t b) {
  std::uint32_t product = 0;
  for (std::uint32_t bit = 0x80000000U; bit != 0; bit >>= 1) {
    if ((a & bit) != 0) product ^= b;
    b = (b & 1U) != 0 ? (b >> 1) ^ 0xEDB88320U : b >> 1;  // b * x
  }
  return product;
}

std::uint32_t x_to_8n_mod_p(std::uint64_t n) {
  std::uint32_t result = 0x80000000U;  // x^0
  std::uint32_t square = 0x00800000U;  // x^8, then x^16, x^32, ...: x^(8 * 2^k)
  for (; n != 0; n >>= 1) {
    if ((n & 1U) != 0) result = multiply_mod_p(square, result);
    square = multiply_mod_p(square, square);
  }
  return result;
}

}  // namespace

std::uint32_t crc32_combine(std::uint32_t crc_a, std::uint32_t crc_b, std::uint64_t length_b) {
  return multiply_mod_p(x_to_8n_mod_p(length_b), crc_a) ^ crc_b;
}

}  // namespace ncqual::mcap
