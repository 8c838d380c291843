// SPDX-License-Identifier: Apache-2.0
// The one YAML reader of the configuration layer (private to common/src/config: nothing outside
// this folder sees yaml-cpp).
//
// A config::Node is a cursor: a YAML node together with the file it came from and the key path
// that leads to it ("fixture.columns.pitch_mm", "budget.sources[2].metrics[0]"). Every read
// names that path in its problems, so no section has to pass prefixes around. A problem does not
// stop the reading: it is recorded in the Diagnostics ("<file>: <path> = <value>: <why>", the one
// shape of every config error), the read returns its fallback, and the loader goes on to find the
// next one; the loader throws once at the end with all of them. Only the first problem of a path
// is kept, so a bad value does not also fail the checks that use it.
//
// Units: a bare number takes the unit its key names (`_mm`, `_in`, `_um` for lengths; `_rad`,
// `_deg`, `_arcsec`, `_urad` for angles; lengths default to mm, angles to rad); a string may carry
// its own ("0.5 in", "30 arcsec"). Values come back in mm and rad. List elements take the unit of
// their list's key.
//
// Every value read is also logged with its resolved value (and whether it was a default), for
// `ncqual config check --print`.
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/units.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ncqual::config {

// What a reading found: its problems and the values it resolved.
class Diagnostics {
 public:
  // Records "<file>: <path> = <value>: <why>" unless `path` of `file` has a problem already.
  void problem(const std::string& file, const std::string& path, const std::string& value,
               const std::string& why);
  // A problem of a whole file (not found, not YAML): "<file>: <why>".
  void file_problem(const std::string& file, const std::string& why);
  void resolved(const std::string& file, const std::string& path, const std::string& value,
                bool defaulted);

  // True when `file` has a problem at `path` or below it (`path.x`, `path[0]`).
  bool has_problem_under(const std::string& file, const std::string& path) const;
  bool empty() const { return problems_.empty(); }
  std::size_t count() const { return problems_.size(); }
  const std::vector<std::string>& problems() const { return problems_; }
  const std::vector<ResolvedValue>& values() const { return values_; }
  // Throws ConfigError carrying every problem (what(): one per line) when there is any.
  void throw_if_any() const;

 private:
  std::vector<std::string> problems_;
  std::set<std::pair<std::string, std::string>> seen_;
  std::vector<ResolvedValue> values_;
};

class Node {
 public:
  Node(const YAML::Node& yaml, std::string file, Diagnostics& diagnostics, std::string path = {},
       std::string unit_key = {});

  // ---- Where we are --------------------------------------------------------------------------
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  const YAML::Node& yaml() const { return *yaml_; }
  Diagnostics& diagnostics() const { return *diagnostics_; }
  // The value as messages show it: 'text', (missing) or (not a single value).
  std::string describe() const;

  // ---- Navigation (never fails: a missing child is an absent Node) ----------------------------
  Node operator[](const std::string& key) const;
  Node operator[](std::size_t index) const;
  bool present() const;  // defined and not null
  bool is_map() const { return present() && yaml_->IsMap(); }
  bool is_list() const { return present() && yaml_->IsSequence(); }
  bool is_scalar() const { return present() && yaml_->IsScalar(); }
  std::size_t size() const { return is_list() ? yaml_->size() : 0; }
  std::vector<Node> items() const;                            // a list's elements
  std::vector<std::pair<std::string, Node>> entries() const;  // a mapping's keys, in file order
  std::string scalar() const { return is_scalar() ? yaml_->Scalar() : std::string(); }

  // ---- Problems --------------------------------------------------------------------------------
  // Records "<file>: <path> = <value>: <why>"; returns false, for `return node.problem(...)`.
  bool problem(const std::string& why) const;

  // ---- Shapes ----------------------------------------------------------------------------------
  // A mapping with only these keys: true when it is one (each other key is a problem, "unknown
  // key; did you mean 'x'? expected one of: ...", the suggestion when one is a few edits away);
  // false when absent (no problem) or not a mapping (a problem).
  bool map_of(const std::set<std::string>& keys) const;
  // As map_of, but absence is a problem too ("required section").
  bool required_map_of(const std::set<std::string>& keys) const;
  // A problem "required" when absent; true when present.
  bool require() const;

  // ---- Values: nullopt when absent (no problem) or bad (a problem) ----------------------------
  std::optional<double> length() const;  // mm, unit from the key
  std::optional<double> angle() const;   // rad, unit from the key
  // A quantity whose bare number is in `default_unit`.
  std::optional<double> quantity(units::Dimension dim, std::string_view default_unit) const;
  std::optional<double> number() const;  // a finite plain number
  std::optional<int> integer(int lo, int hi) const;
  std::optional<std::string> text() const;
  std::optional<bool> flag() const;  // true or false
  // A list of exactly `n` lengths (mm), angles (rad) or plain numbers; a problem "expected a
  // list of <n> lengths" (angles, numbers) when it is not one.
  std::optional<Eigen::VectorXd> lengths(int n) const;
  std::optional<Eigen::VectorXd> angles(int n) const;
  std::optional<Eigen::VectorXd> numbers(int n) const;

  // ---- With a fallback: returned (and logged as the default) when absent, or when bad --------
  double length(double fallback) const;
  double angle(double fallback) const;
  double number(double fallback) const;
  int integer(int lo, int hi, int fallback) const;
  std::string text(const std::string& fallback) const;
  bool flag(bool fallback) const;
  Eigen::VectorXd lengths(int n, const Eigen::VectorXd& fallback) const;

  // ---- Required: a problem "required" when absent ---------------------------------------------
  std::optional<double> required_length() const;
  std::optional<std::string> required_text() const;

 private:
  std::string child_path(const std::string& key) const;
  // A list of exactly `n` values, each read by `read`; `what` names them in the problem.
  std::optional<Eigen::VectorXd> list_of(int n, std::optional<double> (Node::*read)() const,
                                         const char* what) const;
  void log(const std::string& value) const;
  void log_default(const std::string& value) const;

  // Shared, so that copying or assigning a Node rebinds the cursor (yaml-cpp's own assignment
  // copies the content of one node into the other).
  std::shared_ptr<const YAML::Node> yaml_;
  std::string file_;
  Diagnostics* diagnostics_;
  std::string path_;
  std::string unit_key_;  // the key whose suffix names the unit (a list element: its list's)
};

// Reads a YAML file into a Node at its root; a missing file or bad YAML is a problem of the file
// and gives an absent Node.
Node load_file(const std::string& path, Diagnostics& diagnostics);
// Parses YAML text as if it were the file `file`; bad YAML is a problem of the file.
Node parse_text(std::string_view text, const std::string& file, Diagnostics& diagnostics);

// The sections, each read from its own mapping (paths are named from the file's root).
FixtureConfig read_fixture(const Node& node);
GlobalCheckConfig read_global_check(const Node& node);
CalendarConfig read_calendar(const Node& node);
solver::ErrorBudgetConfig read_budget(const Node& budget);
sim::SimulatorConfig read_simulator(const Node& node, const MachineConfig& machine);

// The unit a bare number of `key` is in, by the key's suffix: lengths `_in`, `_um`, else mm;
// angles `_deg`, `_arcsec`, `_urad`, else rad.
std::string_view length_unit_of(std::string_view key);
std::string_view angle_unit_of(std::string_view key);
// True when `key` ends in `suffix` and is longer than it.
bool key_ends_with(std::string_view key, std::string_view suffix);

// An id of a machine or fixture: letters, digits, '-', '_' and '.', not empty.
bool valid_id(const std::string& id);

// Formats a number for messages and the resolved listing (%.10g).
std::string format_number(double v);

}  // namespace ncqual::config
