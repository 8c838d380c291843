// SPDX-License-Identifier: Apache-2.0
// The `fixture:` section of a machine config (ncqual/common/fixture.hpp).
#include "node.hpp"

#include <cctype>
#include <set>

namespace ncqual::config {
namespace {

// A list of lengths under "<stem>_mm" or "<stem>_in" (at most one of them); nullopt when neither
// is present (or it is bad). `used` receives the node of the key given.
std::optional<std::vector<double>> length_list(const Node& section, const std::string& stem,
                                               Node* used = nullptr) {
  std::optional<std::vector<double>> out;
  std::string found;
  for (const char* suffix : {"_mm", "_in"}) {
    const Node v = section[stem + suffix];
    if (!v.present()) continue;
    if (!found.empty()) {
      v.problem("also given as " + section.path() + "." + found + "; give one");
      continue;
    }
    found = stem + suffix;
    if (used) *used = v;
    if (!v.is_list() || v.size() == 0) {
      v.problem("expected a non-empty list of lengths");
      return std::nullopt;
    }
    std::vector<double> values;
    for (const Node& item : v.items()) {
      const auto mm = item.length();
      if (!mm) return std::nullopt;
      values.push_back(*mm);
    }
    out = std::move(values);
  }
  return out;
}

bool increasing(const std::vector<double>& values, const Node& node) {
  for (std::size_t i = 1; i < values.size(); ++i) {
    if (!(values[i] > values[i - 1])) return node.problem("values must be strictly increasing");
  }
  return true;
}

void distinct(const std::vector<double>& values, const Node& node) {
  std::set<double> seen(values.begin(), values.end());
  if (seen.size() != values.size()) node.problem("values must be distinct");
}

std::string format_mm(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

// One axis of pogo homes: `home_<a>_mm: [...]`, or `count` + `first_<a>_mm` + `pitch_mm`.
//   home[i] = first + i * pitch,  i = 0 .. count - 1
std::vector<double> homes(const Node& section, const std::string& axis, int minimum_count) {
  const std::string first_key = "first_" + axis + "_mm";
  if (!section.required_map_of(
          {"count", first_key, "pitch_mm", "home_" + axis + "_mm", "home_" + axis + "_in"})) {
    return {};
  }
  Node list_node = section["home_" + axis + "_mm"];
  if (auto listed = length_list(section, "home_" + axis, &list_node)) {
    const std::string& list_key = list_node.path();
    for (const std::string& other : {std::string("pitch_mm"), first_key}) {
      if (section[other].present()) section[other].problem("not with " + list_key);
    }
    if (static_cast<int>(listed->size()) < minimum_count) {
      list_node.problem("needs at least " + std::to_string(minimum_count) + " values");
    }
    if (const auto count = section["count"].integer(minimum_count, 999);
        count && *count != static_cast<int>(listed->size())) {
      section["count"].problem("does not match the " + std::to_string(listed->size()) +
                               " values of " + list_key);
    }
    increasing(*listed, list_node);
    return *listed;
  }
  const Node count = section["count"];
  if (!count.present())
    count.problem("must be an integer from " + std::to_string(minimum_count) + " to 999");
  const auto n = count.integer(minimum_count, 999);
  const auto first = section[first_key].required_length();
  const auto pitch = section["pitch_mm"].required_length();
  if (pitch && !(*pitch > 0)) section["pitch_mm"].problem("must be positive");
  std::vector<double> out;
  if (!n || !first || !pitch) return out;
  for (int i = 0; i < *n; ++i) out.push_back(*first + i * *pitch);
  return out;
}

std::vector<double> default_z_planes() {
  std::vector<double> planes;
  for (double in : {0.0, 6.0, 12.0, 18.0, 24.0}) planes.push_back(units::inch_to_mm(in));
  return planes;
}

PostCalibrationPattern read_postcalibration(const Node& node, const FixtureConfig& f) {
  // Defaults: 2 Z (the second and fourth planes, or the first and last when fewer than four),
  // 2 Y and 3 X positions, as in the patent's example.
  PostCalibrationPattern p;
  const auto& planes = f.z_planes_mm;
  if (planes.empty()) return p;
  if (planes.size() >= 4) {
    p.z_mm = {planes[1], planes[3]};
  } else if (planes.size() >= 2) {
    p.z_mm = {planes.front(), planes.back()};
  } else {
    p.z_mm = {planes.front()};
  }
  p.y_offsets_mm = {-75.0, 75.0};
  p.x_offsets_mm = {-150.0, 0.0, 150.0};
  if (!node.map_of(
          {"z_mm", "z_in", "y_offsets_mm", "y_offsets_in", "x_offsets_mm", "x_offsets_in"})) {
    return p;
  }
  const std::pair<const char*, std::vector<double>*> lists[] = {
      {"z", &p.z_mm}, {"y_offsets", &p.y_offsets_mm}, {"x_offsets", &p.x_offsets_mm}};
  for (const auto& [stem, values] : lists) {
    Node used = node[std::string(stem) + "_mm"];
    if (auto read = length_list(node, stem, &used)) {
      distinct(*read, used);
      *values = std::move(*read);
    }
  }
  const Node z_node = node["z_in"].present() ? node["z_in"] : node["z_mm"];
  for (std::size_t i = 0; i < p.z_mm.size(); ++i) {
    if (p.z_mm[i] < planes.front() - 1e-9 || p.z_mm[i] > planes.back() + 1e-9) {
      z_node[i].problem("outside the Z travel of the planes (" + format_mm(planes.front()) +
                        " to " + format_mm(planes.back()) + " mm)");
    }
  }
  return p;
}

}  // namespace

bool valid_id(const std::string& id) {
  for (char ch : id) {
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.')) {
      return false;
    }
  }
  return !id.empty();
}

FixtureConfig read_fixture(const Node& node) {
  FixtureConfig f;
  if (!node.map_of({"fixture_id", "origin_mm", "columns", "rows", "z_planes_mm", "z_planes_in",
                    "reference_block", "probe_depth_mm", "postcalibration"})) {
    return f;
  }
  const Node id = node["fixture_id"];
  f.fixture_id = id.required_text().value_or("");
  if (id.present() && !valid_id(f.fixture_id)) {
    id.problem(f.fixture_id.empty() ? "required" : "use letters, digits, '-', '_' and '.' only");
  }
  f.origin_mm = node["origin_mm"].lengths(3, f.origin_mm);

  // Columns move in X; at least one. Rows move in Y along each column; at least two, so that
  // the odd and the even rows of the weekly rotation both exist.
  f.column_home_x_mm = homes(node["columns"], "x", 1);
  f.row_home_y_mm = homes(node["rows"], "y", 2);

  Node planes_node = node["z_planes_mm"];
  if (auto planes = length_list(node, "z_planes", &planes_node)) {
    increasing(*planes, planes_node);
    f.z_planes_mm = std::move(*planes);
  } else if (!node["z_planes_mm"].present() && !node["z_planes_in"].present()) {
    f.z_planes_mm = default_z_planes();
  }

  const Node block = node["reference_block"];
  if (block.required_map_of({"size_mm", "height_mm"})) {
    f.block_size_mm = block["size_mm"].required_length().value_or(0);
    if (block["size_mm"].present() && !(f.block_size_mm > 0)) {
      block["size_mm"].problem("must be positive");
    }
    f.block_height_mm = block["height_mm"].required_length().value_or(0);
    if (block["height_mm"].present() && !(f.block_height_mm > 0)) {
      block["height_mm"].problem("must be positive");
    }
  }
  const Node depth = node["probe_depth_mm"];
  f.probe_depth_mm = depth.required_length().value_or(0);
  if (depth.present() && (!(f.probe_depth_mm > 0) || !(f.probe_depth_mm < f.block_height_mm))) {
    depth.problem("must be positive and less than reference_block.height_mm (" +
                  format_mm(f.block_height_mm) + " mm)");
  }
  f.postcalibration = read_postcalibration(node["postcalibration"], f);
  return f;
}

}  // namespace ncqual::config
