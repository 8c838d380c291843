// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/fixture.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

namespace ncqual {
namespace {

// ---- Small parsers of the names ---------------------------------------------------------------

// A decimal integer >= 1 without sign or leading zeros, at the start of `text`; advances it.
std::optional<int> take_positive_int(std::string_view& text) {
  std::size_t n = 0;
  while (n < text.size() && std::isdigit(static_cast<unsigned char>(text[n]))) ++n;
  if (n == 0 || n > 6 || text[0] == '0') return std::nullopt;
  const int value = std::stoi(std::string(text.substr(0, n)));
  text.remove_prefix(n);
  return value;
}

// As above but 0 is allowed (a configuration index).
std::optional<int> take_index(std::string_view& text) {
  if (!text.empty() && text[0] == '0') {
    if (text.size() > 1 && std::isdigit(static_cast<unsigned char>(text[1]))) return std::nullopt;
    text.remove_prefix(1);
    return 0;
  }
  return take_positive_int(text);
}

bool take_literal(std::string_view& text, std::string_view literal) {
  if (text.substr(0, literal.size()) != literal) return false;
  text.remove_prefix(literal.size());
  return true;
}

constexpr const char* kAxisNames[] = {"x", "y", "z"};

}  // namespace

// ---- Labels and names ---------------------------------------------------------------------------

std::string pogo_label(int column, int row) {
  return "C" + std::to_string(column) + "R" + std::to_string(row);
}

std::optional<PogoId> parse_pogo_label(std::string_view label) {
  PogoId id;
  if (!take_literal(label, "C")) return std::nullopt;
  const auto column = take_positive_int(label);
  if (!column || !take_literal(label, "R")) return std::nullopt;
  const auto row = take_positive_int(label);
  if (!row || !label.empty()) return std::nullopt;
  id.column = *column;
  id.row = *row;
  return id;
}

bool fixture_has_pogo(const FixtureConfig& fixture, const PogoId& pogo) {
  return pogo.column >= 1 && pogo.column <= fixture.columns() && pogo.row >= 1 &&
         pogo.row <= fixture.rows();
}

std::string_view to_string(RowSelection rows) {
  switch (rows) {
    case RowSelection::Odd: return "odd rows";
    case RowSelection::Even: return "even rows";
    default: return "all rows";
  }
}

bool row_selected(RowSelection rows, int row) {
  switch (rows) {
    case RowSelection::Odd: return row % 2 == 1;
    case RowSelection::Even: return row % 2 == 0;
    default: return true;
  }
}

RowSelection precalibration_rows(const FixtureConfig& fixture, int k) {
  return k < static_cast<int>(fixture.z_planes_mm.size()) ? RowSelection::Odd : RowSelection::Even;
}

std::vector<PogoPlacement> precalibration_configuration(const FixtureConfig& fixture, int k) {
  const int count = fixture.precalibration_configuration_count();
  if (k < 0 || k >= count) {
    throw std::out_of_range("fixture '" + fixture.fixture_id + "': pre-calibration configuration " +
                            std::to_string(k) + " is not in 0.." + std::to_string(count - 1));
  }
  // k < n: odd rows at plane k; k >= n: even rows at plane k - n. Home X and Y.
  const int n = static_cast<int>(fixture.z_planes_mm.size());
  const double z = fixture.z_planes_mm[static_cast<std::size_t>(k % n)];
  const RowSelection rows = precalibration_rows(fixture, k);
  std::vector<PogoPlacement> out;
  for (int c = 1; c <= fixture.columns(); ++c) {
    for (int r = 1; r <= fixture.rows(); ++r) {
      if (!row_selected(rows, r)) continue;
      out.push_back({pogo_label(c, r), c, r,
                     Eigen::Vector3d(fixture.column_home_x_mm[static_cast<std::size_t>(c - 1)],
                                     fixture.row_home_y_mm[static_cast<std::size_t>(r - 1)], z)});
    }
  }
  return out;
}

std::vector<std::vector<PogoPlacement>> postcalibration_configurations(const FixtureConfig& fixture,
                                                                       RowSelection rows) {
  const PostCalibrationPattern& p = fixture.postcalibration;
  std::vector<std::vector<PogoPlacement>> out;
  for (double z : p.z_mm) {
    for (double dy : p.y_offsets_mm) {
      for (double dx : p.x_offsets_mm) {
        std::vector<PogoPlacement> configuration;
        for (int c = 1; c <= fixture.columns(); ++c) {
          for (int r = 1; r <= fixture.rows(); ++r) {
            if (!row_selected(rows, r)) continue;
            configuration.push_back(
                {pogo_label(c, r), c, r,
                 Eigen::Vector3d(fixture.column_home_x_mm[static_cast<std::size_t>(c - 1)] + dx,
                                 fixture.row_home_y_mm[static_cast<std::size_t>(r - 1)] + dy, z)});
          }
        }
        out.push_back(std::move(configuration));
      }
    }
  }
  return out;
}

std::string_view to_string(PogoFace face) {
  switch (face) {
    case PogoFace::Top: return "top";
    case PogoFace::XMinus: return "x-";
    case PogoFace::XPlus: return "x+";
    case PogoFace::YMinus: return "y-";
    case PogoFace::YPlus: return "y+";
  }
  return "?";
}

// Written out component by component: negating a unit vector would give signed zeros.
Eigen::Vector3d outward_normal(PogoFace face) {
  switch (face) {
    case PogoFace::XMinus: return Eigen::Vector3d(-1, 0, 0);
    case PogoFace::XPlus: return Eigen::Vector3d(1, 0, 0);
    case PogoFace::YMinus: return Eigen::Vector3d(0, -1, 0);
    case PogoFace::YPlus: return Eigen::Vector3d(0, 1, 0);
    default: return Eigen::Vector3d(0, 0, 1);
  }
}

Eigen::Vector3d approach_direction(PogoFace face) {
  switch (face) {
    case PogoFace::XMinus: return Eigen::Vector3d(1, 0, 0);
    case PogoFace::XPlus: return Eigen::Vector3d(-1, 0, 0);
    case PogoFace::YMinus: return Eigen::Vector3d(0, 1, 0);
    case PogoFace::YPlus: return Eigen::Vector3d(0, -1, 0);
    default: return Eigen::Vector3d(0, 0, -1);
  }
}

Eigen::Vector3d face_offset(const FixtureConfig& fixture, PogoFace face) {
  if (face == PogoFace::Top) return Eigen::Vector3d::Zero();
  Eigen::Vector3d offset = fixture.block_half_size_mm() * outward_normal(face);
  offset.z() = -fixture.probe_depth_mm;
  return offset;
}

std::string pogo_touch_feature(std::string_view pogo, int configuration, PogoFace face) {
  return "pogo:" + std::string(pogo) + ":cfg" + std::to_string(configuration) + ":" +
         std::string(to_string(face));
}

std::optional<PogoTouchFeature> parse_pogo_touch_feature(std::string_view feature) {
  PogoTouchFeature out;
  if (!take_literal(feature, "pogo:")) return std::nullopt;
  const std::size_t colon = feature.find(':');
  if (colon == std::string_view::npos) return std::nullopt;
  const std::string_view label = feature.substr(0, colon);
  const auto id = parse_pogo_label(label);
  if (!id) return std::nullopt;
  feature.remove_prefix(colon + 1);
  if (!take_literal(feature, "cfg")) return std::nullopt;
  const auto index = take_index(feature);
  if (!index || !take_literal(feature, ":")) return std::nullopt;
  for (PogoFace face : kPogoFaces) {
    if (feature == to_string(face)) {
      out.pogo = std::string(label);
      out.id = *id;
      out.configuration = *index;
      out.face = face;
      return out;
    }
  }
  return std::nullopt;
}

std::string zero_offset_name(std::string_view pogo, int axis) {
  return std::string(pogo) + ".d" + kAxisNames[axis];
}

std::optional<ZeroOffsetName> parse_zero_offset_name(std::string_view name) {
  const std::size_t dot = name.find('.');
  if (dot == std::string_view::npos) return std::nullopt;
  const auto id = parse_pogo_label(name.substr(0, dot));
  if (!id) return std::nullopt;
  const std::string_view axis = name.substr(dot + 1);
  for (int a = 0; a < 3; ++a) {
    if (axis == std::string("d") + kAxisNames[a]) {
      return ZeroOffsetName{std::string(name.substr(0, dot)), *id, a};
    }
  }
  return std::nullopt;
}

}  // namespace ncqual
