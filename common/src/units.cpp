// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/units.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace ncqual::units {

std::optional<double> to_internal_factor(Dimension dim, std::string_view unit) {
  if (dim == Dimension::Length) {
    if (unit == "mm") return 1.0;
    if (unit == "um") return 1e-3;
    if (unit == "m") return 1e3;
    if (unit == "in") return kMmPerInch;
    return std::nullopt;
  }
  if (unit == "rad") return 1.0;
  if (unit == "mrad") return 1e-3;
  if (unit == "urad") return 1e-6;
  if (unit == "deg") return kRadPerDeg;
  if (unit == "arcsec") return kRadPerArcsec;
  return std::nullopt;
}

double parse_quantity(Dimension dim, std::string_view text, std::string_view default_unit) {
  const char* allowed = dim == Dimension::Length ? "mm, um, m, in" : "rad, mrad, urad, deg, arcsec";
  const std::string s(text);
  const char* begin = s.c_str();
  char* end = nullptr;
  errno = 0;
  const double number = std::strtod(begin, &end);
  if (end == begin || errno == ERANGE || !std::isfinite(number)) {
    throw std::invalid_argument("'" + s + "' is not a number with a unit (" + allowed + ")");
  }
  std::string_view rest(end);
  while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
  while (!rest.empty() && rest.back() == ' ') rest.remove_suffix(1);
  const std::string_view unit = rest.empty() ? default_unit : rest;
  const auto factor = to_internal_factor(dim, unit);
  if (!factor) {
    throw std::invalid_argument("'" + s + "' has unit '" + std::string(unit) +
                                "'; expected one of " + allowed);
  }
  return number * *factor;
}

}  // namespace ncqual::units
