// SPDX-License-Identifier: Apache-2.0
// CRC32 of MCAP (mcap.hpp's crc32 and crc32_combine): zlib's, but for the bytes that a CPU with
// carry-less multiplication folds here, 16 at a time, in buffers of 64 or more.
//
// Why the folding stays our own (issue 36: zlib where it is as fast, our own only where it wins
// clearly): tests/bench/crc_bench.cpp on the development machine (Debian 12's zlib 1.2.13, a
// 2-core Xeon with PCLMULQDQ, best of 7 runs of 256 MiB) had it at 20.6, 22.4 and 20.1 GB/s on
// 1 KiB, 64 KiB and 4 MiB buffers against crc32_z's 2.5, 3.2 and 3.6 GB/s: 8.4, 7.0 and 5.6
// times as fast (4.7 to 12 times over four runs beside other builds). What this file had besides
// did not win and is zlib's now: the slicing-by-8 tables for other CPUs and short tails (1.8-1.9
// GB/s, 0.52-0.77 x crc32_z; crc32_portable, which tested them, went with them) and a
// crc32_combine by squaring in GF(2) (645-1233 ns a call, zlib's table of powers 85-99 ns).
#include "ncqual/mcap/mcap.hpp"

#include <zlib.h>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <cstddef>
#include <cstdint>

namespace ncqual::mcap {
namespace {

// zlib's CRC32 of `n` bytes at `p` after `previous` (a finished CRC, as crc32 takes and gives).
std::uint32_t zlib_crc32(std::uint32_t previous, const unsigned char* p, std::size_t n) {
  if (n == 0) return previous;  // crc32_z answers 0 for a null pointer, whatever `previous`
  return static_cast<std::uint32_t>(crc32_z(previous, p, n));
}

#if defined(__x86_64__)
// Folding with carry-less multiplication (Gopal et al., Intel, "Fast CRC Computation for Generic
// Polynomials Using PCLMULQDQ Instruction", 2009), for the reflected polynomial: four 128-bit
// lanes folded 64 bytes a step, then into one lane, then 128 -> 64 bits and a Barrett reduction
// to 32. The constants are x^k mod P for the fold distances, bit-reflected and shifted as the
// paper gives them for P = 0x104C11DB7: k1 = x^(4*128+32), k2 = x^(4*128-32), k3 = x^(128+32),
// k4 = x^(128-32), k5 = x^64, and mu = floor(x^64 / P). Several times zlib's speed on a
// CPU that has the instruction (the figures are at the top); `n` is at least 64, the last n % 16
// bytes are left to the caller.
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
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  std::size_t n = bytes.size();
#if defined(__x86_64__)
  if (n >= 64 && cpu_folds()) {
    // The folding works on the CRC register, which is the finished CRC inverted.
    const std::size_t folded = n - n % 16;
    previous = ~crc32_folded(~previous, p, folded);
    p += folded;
    n -= folded;
  }
#endif
  return zlib_crc32(previous, p, n);
}

std::uint32_t crc32_combine(std::uint32_t crc_a, std::uint32_t crc_b, std::uint64_t length_b) {
  // z_off_t is 64 bits on the 64-bit targets ncqual builds for: no length is cut.
  static_assert(sizeof(z_off_t) >= sizeof(std::uint64_t), "z_off_t must hold any length");
  return static_cast<std::uint32_t>(::crc32_combine(crc_a, crc_b, static_cast<z_off_t>(length_b)));
}

}  // namespace ncqual::mcap
