// SPDX-License-Identifier: Apache-2.0
#include "ncqual/charts/svg.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>

namespace ncqual::charts::svg {
namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

// The length of the valid UTF-8 sequence at the start of `s`, 0 when it is not one (overlong
// forms, surrogates and code points above U+10FFFF are not valid).
std::size_t utf8_sequence_length(std::string_view s) {
  const auto b0 = static_cast<unsigned char>(s[0]);
  if (b0 < 0x80) return 1;
  std::size_t n = 0;
  std::uint32_t cp = 0;
  if ((b0 & 0xE0) == 0xC0) {
    n = 2;
    cp = b0 & 0x1F;
  } else if ((b0 & 0xF0) == 0xE0) {
    n = 3;
    cp = b0 & 0x0F;
  } else if ((b0 & 0xF8) == 0xF0) {
    n = 4;
    cp = b0 & 0x07;
  } else {
    return 0;
  }
  if (s.size() < n) return 0;
  for (std::size_t i = 1; i < n; ++i) {
    const auto b = static_cast<unsigned char>(s[i]);
    if ((b & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (b & 0x3F);
  }
  static constexpr std::array<std::uint32_t, 5> kSmallest = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < kSmallest[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  // U+FFFE and U+FFFF are not XML characters either.
  if (cp == 0xFFFE || cp == 0xFFFF) return 0;
  return n;
}

}  // namespace

std::string escape(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 8);
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    switch (c) {
      case '&':
        out += "&amp;";
        ++i;
        continue;
      case '<':
        out += "&lt;";
        ++i;
        continue;
      case '>':
        out += "&gt;";
        ++i;
        continue;
      case '"':
        out += "&quot;";
        ++i;
        continue;
      case '\'':
        out += "&#39;";
        ++i;
        continue;
      default: break;
    }
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x20 && c != '\t' && c != '\n' && c != '\r') {
      out += kReplacement;
      ++i;
      continue;
    }
    const std::size_t n = utf8_sequence_length(text.substr(i));
    if (n == 0) {
      out += kReplacement;
      ++i;
      continue;
    }
    out.append(text.substr(i, n));
    i += n;
  }
  return out;
}

std::string fixed(double v, int decimals) {
  decimals = std::clamp(decimals, 0, 12);
  if (!std::isfinite(v)) v = 0;
  std::array<char, 400> buf{};
  const auto res =
      std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::fixed, decimals);
  std::string s(buf.data(), res.ptr);
  if (!s.empty() && s[0] == '-' &&
      std::all_of(s.begin() + 1, s.end(), [](char ch) { return ch == '0' || ch == '.'; })) {
    s.erase(0, 1);
  }
  return s;
}

std::string coord(double v) { return fixed(v, 2); }

std::string exact(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::array<char, 64> buf{};
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), res.ptr);
}

std::string typographic_minus(std::string text) {
  std::string out;
  out.reserve(text.size() + 4);
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool digit_follows =
        i + 1 < text.size() && ((text[i + 1] >= '0' && text[i + 1] <= '9') || text[i + 1] == '.');
    if (text[i] == '-' && digit_follows) {
      out += "\xE2\x88\x92";
    } else {
      out += text[i];
    }
  }
  return out;
}

Path& Path::move_to(double x, double y) {
  if (!d_.empty()) d_ += ' ';
  d_ += 'M';
  d_ += coord(x);
  d_ += ' ';
  d_ += coord(y);
  return *this;
}

Path& Path::line_to(double x, double y) {
  d_ += " L";
  d_ += coord(x);
  d_ += ' ';
  d_ += coord(y);
  return *this;
}

Path& Path::arc_to(double r, bool large_arc, bool sweep, double x, double y) {
  d_ += " A";
  d_ += coord(r);
  d_ += ' ';
  d_ += coord(r);
  d_ += " 0 ";
  d_ += large_arc ? '1' : '0';
  d_ += ' ';
  d_ += sweep ? '1' : '0';
  d_ += ' ';
  d_ += coord(x);
  d_ += ' ';
  d_ += coord(y);
  return *this;
}

Path& Path::close() {
  d_ += " Z";
  return *this;
}

void Writer::start(std::string_view tag, Attrs attrs) {
  out_ += '<';
  out_ += tag;
  for (const auto& [name, value] : attrs) {
    if (value.empty()) continue;
    out_ += ' ';
    out_ += name;
    out_ += "=\"";
    out_ += escape(value);
    out_ += '"';
  }
}

void Writer::open(std::string_view tag, Attrs attrs) {
  start(tag, attrs);
  out_ += ">\n";
}

void Writer::close(std::string_view tag) {
  out_ += "</";
  out_ += tag;
  out_ += ">\n";
}

void Writer::leaf(std::string_view tag, Attrs attrs) {
  start(tag, attrs);
  out_ += "/>\n";
}

void Writer::text(std::string_view tag, Attrs attrs, std::string_view text) {
  start(tag, attrs);
  out_ += '>';
  out_ += escape(text);
  close(tag);
}

}  // namespace ncqual::charts::svg
