// SPDX-License-Identifier: Apache-2.0
// Units at the edges. Inside ncqual everything is millimetres, radians and seconds; inches,
// degrees and arc-seconds appear only in config files, imports and display.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace ncqual::units {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kMmPerInch = 25.4;
inline constexpr double kRadPerDeg = kPi / 180.0;
inline constexpr double kRadPerArcsec = kPi / (180.0 * 3600.0);

constexpr double inch_to_mm(double in) { return in * kMmPerInch; }
constexpr double mm_to_inch(double mm) { return mm / kMmPerInch; }
constexpr double deg_to_rad(double deg) { return deg * kRadPerDeg; }
constexpr double rad_to_deg(double rad) { return rad / kRadPerDeg; }
constexpr double arcsec_to_rad(double as) { return as * kRadPerArcsec; }
constexpr double rad_to_arcsec(double rad) { return rad / kRadPerArcsec; }

enum class Dimension { Length, Angle };

// Factor that turns a value in `unit` into the internal unit of its dimension (mm or rad);
// std::nullopt when the unit is not one of: mm, um, m, in (length); rad, mrad, urad, deg,
// arcsec (angle).
std::optional<double> to_internal_factor(Dimension dim, std::string_view unit);

// Parses "12.5", "0.5 in", "30 arcsec" into the internal unit. A bare number is taken to be in
// `default_unit`. Throws std::invalid_argument naming the text and the allowed units.
double parse_quantity(Dimension dim, std::string_view text, std::string_view default_unit);

}  // namespace ncqual::units
