// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze iso230-2`: a linear axis's positioning run (laser interferometer) evaluated per
// ISO 230-2:2014, printed as a table or as its --json document.
#include "analyze.hpp"

#include "ncqual/common/csv.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/solver/instrument_files.hpp"
#include "ncqual/solver/iso230_2.hpp"

#include <fmt/format.h>

#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::cli::analysis {
namespace {

using nlohmann::json;

// The --json document of iso230-2 (names: the comment at the top of analyze.cpp).
struct DirectionDocument {
  int n = 0;
  double mean = 0, s = 0, R = 0, min = 0, max = 0;
};
struct TargetDocument {
  double target_mm = 0;
  std::optional<DirectionDocument> up, down;
  std::optional<double> B, R, mean;
};
struct Iso230_2Document {
  std::string standard = "ISO 230-2:2014";
  std::string file;
  std::string unit = "mm";
  std::size_t targets = 0;
  int cycles = 0;
  std::vector<std::string> directions;
  std::optional<double> A, A_up, A_down, E, E_up, E_down, M, R, R_up, R_down, B, B_mean;
  std::vector<TargetDocument> per_target;
  std::vector<std::string> warnings;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DirectionDocument, n, mean, s, R, min, max)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TargetDocument, target_mm, up, down, B, R, mean)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Iso230_2Document, standard, file, unit, targets, cycles,
                                   directions, A, A_up, A_down, E, E_up, E_down, M, R, R_up, R_down,
                                   B, B_mean, per_target, warnings)

std::optional<DirectionDocument> direction_document(
    const std::optional<solver::DirectionFigures>& d) {
  if (!d) return std::nullopt;
  return DirectionDocument{d->cycles, d->mean_mm, d->s_mm, d->R_mm, d->min_mm, d->max_mm};
}

Iso230_2Document document_of(const solver::Iso230_2Result& r, const std::string& file) {
  Iso230_2Document d;
  d.file = file;
  d.targets = r.targets.size();
  d.cycles = r.cycles;
  if (r.has_up) d.directions.emplace_back("up");
  if (r.has_down) d.directions.emplace_back("down");
  d.A = r.A_mm, d.A_up = r.A_up_mm, d.A_down = r.A_down_mm;
  d.E = r.E_mm, d.E_up = r.E_up_mm, d.E_down = r.E_down_mm;
  d.M = r.M_mm;
  d.R = r.R_mm, d.R_up = r.R_up_mm, d.R_down = r.R_down_mm;
  d.B = r.B_mm, d.B_mean = r.B_mean_mm;
  for (const auto& t : r.targets) {
    d.per_target.push_back({t.target_mm, direction_document(t.up), direction_document(t.down),
                            t.B_mm, t.R_mm, t.mean_mm});
  }
  d.warnings = solver::iso230_2_conformance(r);
  return d;
}

void print_iso230_2(const solver::Iso230_2Result& r, const std::string& file) {
  const std::string dirs = r.has_up && r.has_down ? "both directions"
                           : r.has_up             ? "up (+) only"
                                                  : "down (-) only";
  fmt::print("ISO 230-2:2014 positioning test: {}\n", file);
  fmt::print("  {} targets ({} .. {} mm), {} cycles, {}\n\n", r.targets.size(),
             mm(r.targets.front().target_mm), mm(r.targets.back().target_mm), r.cycles, dirs);
  fmt::print("Axis (mm)            bidirectional       up (+)     down (-)\n");
  auto axis_row = [](const char* name, const std::optional<double>& both,
                     const std::optional<double>& up, const std::optional<double>& down) {
    fmt::print("  {:<20}{:>12}{:>13}{:>13}\n", name, mm(both), mm(up), mm(down));
  };
  axis_row("A  accuracy", r.A_mm, r.A_up_mm, r.A_down_mm);
  axis_row("E  systematic dev.", r.E_mm, r.E_up_mm, r.E_down_mm);
  axis_row("R  repeatability", r.R_mm, r.R_up_mm, r.R_down_mm);
  axis_row("M  range of mean x_i", r.M_mm, std::nullopt, std::nullopt);
  axis_row("B  reversal", r.B_mm, std::nullopt, std::nullopt);
  axis_row("B_mean mean reversal", r.B_mean_mm, std::nullopt, std::nullopt);

  fmt::print(
      "\nPer target (mm): mean = mean deviation, s = standard uncertainty, R = 4 s;\n"
      "  B_i = reversal, R_i = bidirectional repeatability, x_i = mean bidirectional "
      "deviation\n");
  const std::vector<std::pair<std::string, std::size_t>> cols{
      {"target", 12}, {"n↑", 4}, {"mean↑", 9}, {"s↑", 8},  {"R↑", 8},  {"n↓", 4},
      {"mean↓", 9},   {"s↓", 8}, {"R↓", 8},    {"B_i", 9}, {"R_i", 8}, {"x_i", 9}};
  std::string header = " ";
  // The arrows are 3 bytes and one column wide: fmt pads by columns.
  for (const auto& [name, width] : cols) header += fmt::format("{:>{}}", name, width);
  fmt::print("{}\n", header);
  for (const auto& t : r.targets) {
    std::string line = fmt::format(" {:>12}", mm(t.target_mm));
    for (const auto* d : {&t.up, &t.down}) {
      line += *d ? fmt::format("{:>4}{:>9}{:>8}{:>8}", (*d)->cycles, mm((*d)->mean_mm),
                               mm((*d)->s_mm), mm((*d)->R_mm))
                 : fmt::format("{:>4}{:>9}{:>8}{:>8}", "-", "-", "-", "-");
    }
    line += fmt::format("{:>9}{:>8}{:>9}", mm(t.B_mm), mm(t.R_mm), mm(t.mean_mm));
    fmt::print("{}\n", line);
  }
  const std::vector<std::string> warnings = solver::iso230_2_conformance(r);
  fmt::print("\nConformance to ISO 230-2:2014: {}\n",
             warnings.empty() ? "the test plan conforms" : "the figures above are given, but");
  for (const auto& w : warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace

int run_iso230_2(const Options& o) {
  const std::string& file = o.file;
  const solver::Iso230_2File data = solver::read_iso230_2_csv(read_csv_file(file));
  const solver::Iso230_2Result r = solver::evaluate_iso230_2(data.readings);
  if (o.json) {
    std::cout << json(document_of(r, file)).dump(2) << "\n";
  } else {
    print_iso230_2(r, file);
  }
  return kExitOk;
}

}  // namespace ncqual::cli::analysis
