#include "ncqual/fixture.hpp"

#include "ncqual/config.hpp"
#include "ncqual/units.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

namespace ncqual {
namespace {

using yaml::fail;

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

// ---- YAML readers: keys are named in full ("fixture.columns.pitch_mm") in errors -------------

YAML::Node required_map(const YAML::Node& parent, const std::string& key, const std::string& full,
                        const std::string& where) {
  const YAML::Node node = parent[key];
  if (!node) fail(where, full, node, "required section");
  if (!node.IsMap()) fail(where, full, node, "expected a mapping");
  return node;
}

// The unit of a bare number follows the key's suffix: _in inches, _um micrometres, else mm.
std::string_view unit_of(const std::string& key) {
  if (key.size() > 3 && key.compare(key.size() - 3, 3, "_in") == 0) return "in";
  if (key.size() > 3 && key.compare(key.size() - 3, 3, "_um") == 0) return "um";
  return "mm";
}

double length_value(const YAML::Node& value, const std::string& full_key, std::string_view unit,
                    const std::string& where) {
  if (!value.IsScalar()) fail(where, full_key, value, "expected a length");
  try {
    return units::parse_quantity(units::Dimension::Length, value.Scalar(), unit);
  } catch (const std::invalid_argument& e) {
    fail(where, full_key, value, e.what());
  }
}

std::optional<double> length_or_none(const YAML::Node& node, const std::string& key,
                                     const std::string& prefix, const std::string& where) {
  const YAML::Node v = node[key];
  if (!v) return std::nullopt;
  return length_value(v, prefix + key, unit_of(key), where);
}

double required_length(const YAML::Node& node, const std::string& key, const std::string& prefix,
                       const std::string& where) {
  const auto v = length_or_none(node, key, prefix, where);
  if (!v) fail(where, prefix + key, node[key], "required");
  return *v;
}

// A list of lengths under "<stem>_mm" or "<stem>_in" (at most one of them); std::nullopt when
// neither is present. `key_out` receives the key used, for later error messages.
std::optional<std::vector<double>> length_list(const YAML::Node& node, const std::string& stem,
                                               const std::string& prefix, const std::string& where,
                                               std::string* key_out) {
  std::optional<std::vector<double>> out;
  std::string found;
  for (const char* suffix : {"_mm", "_in"}) {
    const std::string key = stem + suffix;
    const YAML::Node v = node[key];
    if (!v) continue;
    if (!found.empty()) fail(where, prefix + key, v, "also given as " + prefix + found + "; give one");
    found = key;
    if (!v.IsSequence() || v.size() == 0) fail(where, prefix + key, v, "expected a non-empty list of lengths");
    std::vector<double> values;
    for (std::size_t i = 0; i < v.size(); ++i) {
      values.push_back(
          length_value(v[i], prefix + key + "[" + std::to_string(i) + "]", unit_of(key), where));
    }
    out = std::move(values);
  }
  if (key_out) *key_out = prefix + found;
  return out;
}

std::string format_mm(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

int count_value(const YAML::Node& node, const std::string& key, const std::string& prefix,
                int minimum, const std::string& where) {
  const YAML::Node value = node[key];
  double v = -1;
  if (value && value.IsScalar()) {
    try {
      std::size_t used = 0;
      v = std::stod(value.Scalar(), &used);
      if (used != value.Scalar().size()) v = -1;
    } catch (const std::logic_error&) {
      v = -1;
    }
  }
  if (!(v >= minimum && v <= 999 && v == std::floor(v))) {
    fail(where, prefix + key, node[key],
         "must be an integer from " + std::to_string(minimum) + " to 999");
  }
  return static_cast<int>(v);
}

void require_increasing(const std::vector<double>& values, const std::string& key,
                        const YAML::Node& node, const std::string& where) {
  for (std::size_t i = 1; i < values.size(); ++i) {
    if (!(values[i] > values[i - 1])) {
      fail(where, key, node, "values must be strictly increasing");
    }
  }
}

// One axis of pogo homes: `home_<a>_mm: [...]`, or `count` + `first_<a>_mm` + `pitch_mm`.
//   home[i] = first + i * pitch,  i = 0 .. count - 1
std::vector<double> homes(const YAML::Node& section, const std::string& axis,
                          const std::string& prefix, int minimum_count, const std::string& where) {
  yaml::refuse_unknown_keys(section,
                      {"count", "first_" + axis + "_mm", "pitch_mm", "home_" + axis + "_mm",
                       "home_" + axis + "_in"}, prefix,
                      where);
  std::string list_key;
  auto listed = length_list(section, "home_" + axis, prefix, where, &list_key);
  if (listed) {
    for (const char* other : {"pitch_mm"}) {
      if (section[other]) fail(where, prefix + other, section[other], "not with " + list_key);
    }
    if (section["first_" + axis + "_mm"]) {
      fail(where, prefix + "first_" + axis + "_mm", section["first_" + axis + "_mm"],
           "not with " + list_key);
    }
    if (static_cast<int>(listed->size()) < minimum_count) {
      fail(where, list_key, section[list_key.substr(prefix.size())],
           "needs at least " + std::to_string(minimum_count) + " values");
    }
    if (section["count"] &&
        count_value(section, "count", prefix, minimum_count, where) != static_cast<int>(listed->size())) {
      fail(where, prefix + "count", section["count"],
           "does not match the " + std::to_string(listed->size()) + " values of " + list_key);
    }
    require_increasing(*listed, list_key, section[list_key.substr(prefix.size())], where);
    return *listed;
  }
  const int count = count_value(section, "count", prefix, minimum_count, where);
  const double first = required_length(section, "first_" + axis + "_mm", prefix, where);
  const double pitch = required_length(section, "pitch_mm", prefix, where);
  if (!(pitch > 0)) fail(where, prefix + "pitch_mm", section["pitch_mm"], "must be positive");
  std::vector<double> out;
  for (int i = 0; i < count; ++i) out.push_back(first + i * pitch);
  return out;
}

std::vector<double> default_z_planes() {
  std::vector<double> planes;
  for (double in : {0.0, 6.0, 12.0, 18.0, 24.0}) planes.push_back(units::inch_to_mm(in));
  return planes;
}

void require_distinct(const std::vector<double>& values, const std::string& key,
                      const YAML::Node& node, const std::string& where) {
  std::set<double> seen(values.begin(), values.end());
  if (seen.size() != values.size()) fail(where, key, node, "values must be distinct");
}

PostCalibrationPattern parse_postcalibration(const YAML::Node& node, const FixtureConfig& f,
                                             const std::string& where) {
  // Defaults: 2 Z (the second and fourth planes, or the first and last when fewer than four),
  // 2 Y and 3 X positions, as in the patent's example.
  PostCalibrationPattern p;
  const auto& planes = f.z_planes_mm;
  if (planes.size() >= 4) {
    p.z_mm = {planes[1], planes[3]};
  } else if (planes.size() >= 2) {
    p.z_mm = {planes.front(), planes.back()};
  } else {
    p.z_mm = {planes.front()};
  }
  p.y_offsets_mm = {-75.0, 75.0};
  p.x_offsets_mm = {-150.0, 0.0, 150.0};
  if (!node || node.IsNull()) return p;
  const std::string prefix = "fixture.postcalibration.";
  if (!node.IsMap()) fail(where, "fixture.postcalibration", node, "expected a mapping");
  yaml::refuse_unknown_keys(node,
                      {"z_mm", "z_in", "y_offsets_mm", "y_offsets_in", "x_offsets_mm",
                       "x_offsets_in"}, prefix,
                      where);
  struct {
    const char* stem;
    std::vector<double>* values;
  } lists[] = {{"z", &p.z_mm}, {"y_offsets", &p.y_offsets_mm}, {"x_offsets", &p.x_offsets_mm}};
  for (const auto& list : lists) {
    std::string key;
    if (auto values = length_list(node, list.stem, prefix, where, &key)) {
      require_distinct(*values, key, node[key.substr(prefix.size())], where);
      *list.values = std::move(*values);
    }
  }
  for (std::size_t i = 0; i < p.z_mm.size(); ++i) {
    if (p.z_mm[i] < planes.front() - 1e-9 || p.z_mm[i] > planes.back() + 1e-9) {
      const std::string key = node["z_in"] ? "z_in" : "z_mm";
      fail(where, prefix + key + "[" + std::to_string(i) + "]", node[key][i],
           "outside the Z travel of the planes (" + format_mm(planes.front()) + " to " +
               format_mm(planes.back()) + " mm)");
    }
  }
  return p;
}

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
    case RowSelection::Odd:
      return "odd rows";
    case RowSelection::Even:
      return "even rows";
    default:
      return "all rows";
  }
}

bool row_selected(RowSelection rows, int row) {
  switch (rows) {
    case RowSelection::Odd:
      return row % 2 == 1;
    case RowSelection::Even:
      return row % 2 == 0;
    default:
      return true;
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
    case PogoFace::Top:
      return "top";
    case PogoFace::XMinus:
      return "x-";
    case PogoFace::XPlus:
      return "x+";
    case PogoFace::YMinus:
      return "y-";
    case PogoFace::YPlus:
      return "y+";
  }
  return "?";
}

// Written out component by component: negating a unit vector would give signed zeros.
Eigen::Vector3d outward_normal(PogoFace face) {
  switch (face) {
    case PogoFace::XMinus:
      return Eigen::Vector3d(-1, 0, 0);
    case PogoFace::XPlus:
      return Eigen::Vector3d(1, 0, 0);
    case PogoFace::YMinus:
      return Eigen::Vector3d(0, -1, 0);
    case PogoFace::YPlus:
      return Eigen::Vector3d(0, 1, 0);
    default:
      return Eigen::Vector3d(0, 0, 1);
  }
}

Eigen::Vector3d approach_direction(PogoFace face) {
  switch (face) {
    case PogoFace::XMinus:
      return Eigen::Vector3d(1, 0, 0);
    case PogoFace::XPlus:
      return Eigen::Vector3d(-1, 0, 0);
    case PogoFace::YMinus:
      return Eigen::Vector3d(0, 1, 0);
    case PogoFace::YPlus:
      return Eigen::Vector3d(0, -1, 0);
    default:
      return Eigen::Vector3d(0, 0, -1);
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

// ---- The `fixture:` section ---------------------------------------------------------------------

FixtureConfig parse_fixture_config(const YAML::Node& node, const std::string& where) {
  if (!node.IsMap()) fail(where, "fixture", node, "expected a mapping");
  const std::string prefix = "fixture.";
  yaml::refuse_unknown_keys(node,
                      {"fixture_id", "origin_mm", "columns", "rows", "z_planes_mm", "z_planes_in",
                       "reference_block", "probe_depth_mm", "postcalibration"}, prefix,
                      where);
  FixtureConfig f;

  f.fixture_id = yaml::string_or(node, "fixture_id", "", where);
  if (f.fixture_id.empty()) fail(where, prefix + "fixture_id", node["fixture_id"], "required");
  for (char ch : f.fixture_id) {
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.')) {
      fail(where, prefix + "fixture_id", node["fixture_id"],
           "use letters, digits, '-', '_' and '.' only");
    }
  }

  if (const YAML::Node origin = node["origin_mm"]) {
    if (!origin.IsSequence() || origin.size() != 3) {
      fail(where, prefix + "origin_mm", origin, "expected a list of 3 lengths");
    }
    for (int i = 0; i < 3; ++i) {
      f.origin_mm[i] = length_value(origin[static_cast<std::size_t>(i)],
                                    prefix + "origin_mm[" + std::to_string(i) + "]", "mm", where);
    }
  }

  // Columns move in X; at least one. Rows move in Y along each column; at least two, so that
  // the odd and the even rows of the weekly rotation both exist.
  f.column_home_x_mm = homes(required_map(node, "columns", prefix + "columns", where), "x",
                             prefix + "columns.", 1, where);
  f.row_home_y_mm =
      homes(required_map(node, "rows", prefix + "rows", where), "y", prefix + "rows.", 2, where);

  std::string planes_key;
  if (auto planes = length_list(node, "z_planes", prefix, where, &planes_key)) {
    require_increasing(*planes, planes_key, node[planes_key.substr(prefix.size())], where);
    f.z_planes_mm = std::move(*planes);
  } else {
    f.z_planes_mm = default_z_planes();
  }

  const YAML::Node block = required_map(node, "reference_block", prefix + "reference_block", where);
  const std::string block_prefix = prefix + "reference_block.";
  yaml::refuse_unknown_keys(block, {"size_mm", "height_mm"}, block_prefix, where);
  f.block_size_mm = required_length(block, "size_mm", block_prefix, where);
  if (!(f.block_size_mm > 0)) fail(where, block_prefix + "size_mm", block["size_mm"], "must be positive");
  f.block_height_mm = required_length(block, "height_mm", block_prefix, where);
  if (!(f.block_height_mm > 0)) {
    fail(where, block_prefix + "height_mm", block["height_mm"], "must be positive");
  }
  f.probe_depth_mm = required_length(node, "probe_depth_mm", prefix, where);
  if (!(f.probe_depth_mm > 0) || !(f.probe_depth_mm < f.block_height_mm)) {
    fail(where, prefix + "probe_depth_mm", node["probe_depth_mm"],
         "must be positive and less than reference_block.height_mm (" +
             format_mm(f.block_height_mm) + " mm)");
  }

  f.postcalibration = parse_postcalibration(node["postcalibration"], f, where);
  return f;
}

}  // namespace ncqual
