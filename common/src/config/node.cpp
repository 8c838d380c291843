// SPDX-License-Identifier: Apache-2.0
#include "node.hpp"

#include "ncqual/common/text.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace ncqual::config {
namespace fs = std::filesystem;

namespace {

// A bare decimal number (what std::stod reads, all of it); nullopt otherwise.
std::optional<double> plain_number(const std::string& text) {
  try {
    std::size_t used = 0;
    const double d = std::stod(text, &used);
    if (used == text.size()) return d;
  } catch (const std::logic_error&) {}
  return std::nullopt;
}

std::string join(const std::set<std::string>& keys) {
  std::string list;
  for (const auto& k : keys) list += (list.empty() ? "" : ", ") + k;
  return list;
}

}  // namespace

std::string format_number(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

// ---- Diagnostics
// ---------------------------------------------------------------------------------

void Diagnostics::problem(const std::string& file, const std::string& path,
                          const std::string& value, const std::string& why) {
  if (!seen_.insert({file, path}).second) return;
  problems_.push_back(path.empty() ? file + ": " + why
                                   : file + ": " + path + " = " + value + ": " + why);
}

void Diagnostics::file_problem(const std::string& file, const std::string& why) {
  if (!seen_.insert({file, ""}).second) return;
  problems_.push_back(file + ": " + why);
}

void Diagnostics::resolved(const std::string& file, const std::string& path,
                           const std::string& value, bool defaulted) {
  values_.push_back({file, path, value, defaulted});
}

bool Diagnostics::has_problem_under(const std::string& file, const std::string& path) const {
  for (auto it = seen_.lower_bound({file, path}); it != seen_.end() && it->first == file; ++it) {
    const std::string& p = it->second;
    if (p.compare(0, path.size(), path) != 0) break;
    if (p.size() == path.size() || p[path.size()] == '.' || p[path.size()] == '[') return true;
  }
  return false;
}

void Diagnostics::throw_if_any() const {
  if (problems_.empty()) return;
  throw ConfigError(problems_);
}

// ---- Node
// ----------------------------------------------------------------------------------------

Node::Node(const YAML::Node& yaml, std::string file, Diagnostics& diagnostics, std::string path,
           std::string unit_key)
    : yaml_(std::make_shared<const YAML::Node>(yaml)),
      file_(std::move(file)),
      diagnostics_(&diagnostics),
      path_(std::move(path)),
      unit_key_(std::move(unit_key)) {}

std::string Node::describe() const {
  if (!present()) return "(missing)";
  if (yaml_->IsScalar()) return "'" + yaml_->Scalar() + "'";
  return "(not a single value)";
}

std::string Node::child_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

// Children are constructed, never assigned: yaml-cpp's assignment copies content and throws for
// the invalid node a missing key gives.
Node Node::operator[](const std::string& key) const {
  return Node(present() && yaml_->IsMap() ? (*yaml_)[key] : YAML::Node(), file_, *diagnostics_,
              child_path(key), key);
}

Node Node::operator[](std::size_t index) const {
  return Node(
      present() && yaml_->IsSequence() && index < yaml_->size() ? (*yaml_)[index] : YAML::Node(),
      file_, *diagnostics_, path_ + "[" + std::to_string(index) + "]", unit_key_);
}

bool Node::present() const { return yaml_->IsDefined() && !yaml_->IsNull(); }

std::vector<Node> Node::items() const {
  std::vector<Node> out;
  for (std::size_t i = 0; i < size(); ++i) out.push_back((*this)[i]);
  return out;
}

std::vector<std::pair<std::string, Node>> Node::entries() const {
  std::vector<std::pair<std::string, Node>> out;
  if (!is_map()) return out;
  for (const auto& kv : *yaml_) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("?");
    out.emplace_back(key, Node(kv.second, file_, *diagnostics_, child_path(key), key));
  }
  return out;
}

bool Node::problem(const std::string& why) const {
  diagnostics_->problem(file_, path_, describe(), why);
  return false;
}

bool Node::map_of(const std::set<std::string>& keys) const {
  if (!present()) return false;
  if (!yaml_->IsMap()) return problem("expected a mapping");
  const std::vector<std::string_view> known(keys.begin(), keys.end());
  for (const auto& [key, child] : entries()) {
    if (keys.count(key)) continue;
    const auto nearest = closest_word(key, known);
    child.problem("unknown key; " +
                  (nearest ? "did you mean '" + std::string(*nearest) + "'? " : std::string()) +
                  "expected one of: " + join(keys));
  }
  return true;
}

bool Node::required_map_of(const std::set<std::string>& keys) const {
  if (!present()) return problem("required section");
  return map_of(keys);
}

bool Node::require() const { return present() || problem("required"); }

bool key_ends_with(std::string_view key, std::string_view suffix) {
  return key.size() > suffix.size() &&
         key.compare(key.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string_view length_unit_of(std::string_view key) {
  if (key_ends_with(key, "_in")) return "in";
  if (key_ends_with(key, "_um")) return "um";
  return "mm";
}

std::string_view angle_unit_of(std::string_view key) {
  if (key_ends_with(key, "_deg")) return "deg";
  if (key_ends_with(key, "_arcsec")) return "arcsec";
  if (key_ends_with(key, "_urad")) return "urad";
  return "rad";
}

void Node::log(const std::string& value) const {
  diagnostics_->resolved(file_, path_, value, false);
}
void Node::log_default(const std::string& value) const {
  diagnostics_->resolved(file_, path_, value, true);
}

std::optional<double> Node::quantity(units::Dimension dim, std::string_view default_unit) const {
  if (!present()) return std::nullopt;
  if (!yaml_->IsScalar()) {
    problem("expected a number");
    return std::nullopt;
  }
  double value = 0;
  try {
    value = units::parse_quantity(dim, yaml_->Scalar(), default_unit);
  } catch (const std::invalid_argument& e) {
    problem(e.what());
    return std::nullopt;
  }
  if (!std::isfinite(value)) {
    problem("must be finite");
    return std::nullopt;
  }
  // Shown in the internal unit, and as written when that was another unit.
  const std::string_view internal = dim == units::Dimension::Length ? "mm" : "rad";
  const bool bare = plain_number(yaml_->Scalar()).has_value();
  std::string shown = format_number(value) + " " + std::string(internal);
  if (!bare) shown += " (written " + yaml_->Scalar() + ")";
  if (bare && default_unit != internal) {
    shown += " (written " + yaml_->Scalar() + " " + std::string(default_unit) + ")";
  }
  log(shown);
  return value;
}

std::optional<double> Node::length() const {
  return quantity(units::Dimension::Length, length_unit_of(unit_key_));
}

std::optional<double> Node::angle() const {
  return quantity(units::Dimension::Angle, angle_unit_of(unit_key_));
}

std::optional<double> Node::number() const {
  if (!present()) return std::nullopt;
  const auto d = yaml_->IsScalar() ? plain_number(yaml_->Scalar()) : std::nullopt;
  if (!d) {
    problem("expected a number");
    return std::nullopt;
  }
  if (!std::isfinite(*d)) {
    problem("must be finite");
    return std::nullopt;
  }
  log(format_number(*d));
  return d;
}

std::optional<int> Node::integer(int lo, int hi) const {
  if (!present()) return std::nullopt;
  const auto d = yaml_->IsScalar() ? plain_number(yaml_->Scalar()) : std::nullopt;
  if (!d || !(*d >= lo && *d <= hi) || *d != std::floor(*d)) {
    problem("must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    return std::nullopt;
  }
  log(std::to_string(static_cast<int>(*d)));
  return static_cast<int>(*d);
}

std::optional<std::string> Node::text() const {
  if (!present()) return std::nullopt;
  if (!yaml_->IsScalar()) {
    problem("expected a string");
    return std::nullopt;
  }
  log("\"" + yaml_->Scalar() + "\"");
  return yaml_->Scalar();
}

std::optional<bool> Node::flag() const {
  if (!present()) return std::nullopt;
  const std::string s = scalar();
  if (s != "true" && s != "false") {
    problem("expected true or false");
    return std::nullopt;
  }
  log(s);
  return s == "true";
}

std::optional<Eigen::VectorXd> Node::list_of(int n, std::optional<double> (Node::*read)() const,
                                             const char* what) const {
  if (!present()) return std::nullopt;
  if (!yaml_->IsSequence() || static_cast<int>(yaml_->size()) != n) {
    problem("expected a list of " + std::to_string(n) + " " + what);
    return std::nullopt;
  }
  Eigen::VectorXd out(n);
  bool ok = true;
  for (int i = 0; i < n; ++i) {
    const auto v = ((*this)[static_cast<std::size_t>(i)].*read)();
    if (v) out[i] = *v;
    ok = ok && v.has_value();
  }
  if (!ok) return std::nullopt;
  return out;
}

std::optional<Eigen::VectorXd> Node::lengths(int n) const {
  return list_of(n, static_cast<std::optional<double> (Node::*)() const>(&Node::length), "lengths");
}

std::optional<Eigen::VectorXd> Node::angles(int n) const {
  return list_of(n, static_cast<std::optional<double> (Node::*)() const>(&Node::angle), "angles");
}

std::optional<Eigen::VectorXd> Node::numbers(int n) const {
  return list_of(n, static_cast<std::optional<double> (Node::*)() const>(&Node::number), "numbers");
}

double Node::length(double fallback) const {
  if (!present()) log_default(format_number(fallback) + " mm");
  return length().value_or(fallback);
}

double Node::angle(double fallback) const {
  if (!present()) log_default(format_number(fallback) + " rad");
  return angle().value_or(fallback);
}

double Node::number(double fallback) const {
  if (!present()) log_default(format_number(fallback));
  return number().value_or(fallback);
}

int Node::integer(int lo, int hi, int fallback) const {
  if (!present()) log_default(std::to_string(fallback));
  return integer(lo, hi).value_or(fallback);
}

std::string Node::text(const std::string& fallback) const {
  if (!present()) log_default("\"" + fallback + "\"");
  return text().value_or(fallback);
}

bool Node::flag(bool fallback) const {
  if (!present()) log_default(fallback ? "true" : "false");
  return flag().value_or(fallback);
}

Eigen::VectorXd Node::lengths(int n, const Eigen::VectorXd& fallback) const {
  if (!present()) {
    std::string shown = "[";
    for (int i = 0; i < fallback.size(); ++i) shown += (i ? ", " : "") + format_number(fallback[i]);
    log_default(shown + "] mm");
  }
  return lengths(n).value_or(fallback);
}

std::optional<double> Node::required_length() const {
  if (!require()) return std::nullopt;
  return length();
}

std::optional<std::string> Node::required_text() const {
  if (!require()) return std::nullopt;
  return text();
}

// ---- Files
// ---------------------------------------------------------------------------------------

Node load_file(const std::string& path, Diagnostics& diagnostics) {
  if (!fs::exists(path)) {
    diagnostics.file_problem(path, "file not found");
    return Node(YAML::Node(), path, diagnostics);
  }
  try {
    YAML::Node document = YAML::LoadFile(path);
    // An empty file, or one cut after its comments: nothing to read, said so (not a default
    // plant or machine made of nothing).
    if (!document.IsDefined() || document.IsNull()) {
      diagnostics.file_problem(path, "no settings in it (empty, or only comments)");
      return Node(YAML::Node(), path, diagnostics);
    }
    return Node(document, path, diagnostics);
  } catch (const YAML::Exception& e) {
    diagnostics.file_problem(path, std::string("not valid YAML: ") + e.what());
    return Node(YAML::Node(), path, diagnostics);
  }
}

Node parse_text(std::string_view text, const std::string& file, Diagnostics& diagnostics) {
  try {
    return Node(YAML::Load(std::string(text)), file, diagnostics);
  } catch (const YAML::Exception& e) {
    diagnostics.file_problem(file, std::string("not valid YAML: ") + e.what());
    return Node(YAML::Node(), file, diagnostics);
  }
}

}  // namespace ncqual::config
