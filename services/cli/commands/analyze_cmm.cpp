// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze cmm`: a CMM report of a part judged characteristic by characteristic, and the
// work offset's correction from its best fit, printed as a table or as its --json document.
#include "analyze.hpp"

#include "ncqual/common/csv.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/common/text.hpp"
#include "ncqual/solver/instrument_files.hpp"
#include "ncqual/solver/part_inspection.hpp"

#include <fmt/format.h>

#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::cli::analysis {
namespace {

using nlohmann::json;

// The --json document of cmm (names: the comment at the top of analyze.cpp).
struct CmmCharacteristicDocument {
  std::string feature, axis;
  int line = 0;
  double nominal_mm = 0, actual_mm = 0, deviation_mm = 0;
  std::optional<double> lower_mm, upper_mm;
  std::optional<bool> in_tolerance;
  std::optional<double> after_offset_mm;
  std::optional<bool> in_tolerance_after;
};
struct CmmOffsetDocument {
  Eigen::Vector3d translation_mm = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> rotation_urad;
  Eigen::Vector3d work_offset_correction_mm = Eigen::Vector3d::Zero();
  std::vector<bool> axis_resolved;
  int characteristics = 0, out_of_tolerance_after = 0;
  double max_abs_after_mm = 0;
  std::vector<std::string> left_out;
  std::vector<int> constraining;
  std::vector<std::string> warnings;
};
struct CmmDocument {
  std::string file, format, unit = "mm";
  int characteristics = 0, judged = 0, out_of_tolerance = 0;
  std::optional<std::string> verdict;
  std::vector<CmmCharacteristicDocument> per_characteristic;
  std::optional<CmmOffsetDocument> offset;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CmmCharacteristicDocument, feature, axis, line, nominal_mm,
                                   actual_mm, deviation_mm, lower_mm, upper_mm, in_tolerance,
                                   after_offset_mm, in_tolerance_after)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CmmOffsetDocument, translation_mm, rotation_urad,
                                   work_offset_correction_mm, axis_resolved, characteristics,
                                   out_of_tolerance_after, max_abs_after_mm, left_out, constraining,
                                   warnings)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CmmDocument, file, format, unit, characteristics, judged,
                                   out_of_tolerance, verdict, per_characteristic, offset)

CmmDocument document_of(const solver::PartInspection& p, const solver::CmmReport& report,
                        const std::string& file) {
  CmmDocument d;
  d.file = file;
  d.format = report.format;
  d.characteristics = static_cast<int>(p.characteristics.size());
  d.judged = p.judged;
  d.out_of_tolerance = p.out_of_tolerance;
  if (p.pass) d.verdict = *p.pass ? "PASS" : "FAIL";
  for (const auto& r : p.characteristics) {
    CmmCharacteristicDocument c;
    c.feature = r.characteristic.feature;
    c.axis = r.characteristic.axis;
    c.line = r.characteristic.line;
    c.nominal_mm = r.characteristic.nominal_mm;
    c.actual_mm = r.characteristic.actual_mm;
    c.deviation_mm = r.deviation_mm;
    c.lower_mm = r.characteristic.lower_mm;
    c.upper_mm = r.characteristic.upper_mm;
    c.in_tolerance = r.in_tolerance;
    c.after_offset_mm = r.after_offset_mm;
    c.in_tolerance_after = r.in_tolerance_after;
    d.per_characteristic.push_back(c);
  }
  if (p.fit) {
    CmmOffsetDocument o;
    o.translation_mm = p.fit->translation_mm;
    if (p.fit->rotation_rad) o.rotation_urad = Eigen::Vector3d(*p.fit->rotation_rad * 1e6);
    o.work_offset_correction_mm = -p.fit->translation_mm;
    o.axis_resolved = p.fit->axis_resolved;
    o.characteristics = p.fit->characteristics;
    o.out_of_tolerance_after = p.fit->out_of_tolerance_after;
    o.max_abs_after_mm = p.fit->max_abs_after_mm;
    o.left_out = p.fit->left_out;
    o.constraining = p.fit->constraining;
    o.warnings = p.fit->warnings;
    d.offset = o;
  }
  return d;
}

std::string signed_mm(double v) { return fmt::format("{:+.4f}", v == 0 ? 0.0 : v); }

void print_cmm(const solver::PartInspection& p, const solver::CmmReport& report,
               const std::string& file) {
  std::cout << "CMM report " << file << " (" << report.format << "): " << p.characteristics.size()
            << " characteristics, " << p.judged << " with a tolerance\n";
  std::cout << fmt::format("  {:<12} {:<4} {:>11} {:>11} {:>9}  {:<19} {:<4} {:>12}\n", "feature",
                           "axis", "nominal mm", "actual mm", "dev mm", "tolerance mm", "in",
                           "after offset");
  std::vector<std::string> out;
  for (const auto& r : p.characteristics) {
    const auto& c = r.characteristic;
    const std::string band =
        c.lower_mm ? signed_mm(*c.lower_mm) + " .. " + signed_mm(*c.upper_mm) : "-";
    const std::string in = r.in_tolerance ? (*r.in_tolerance ? "yes" : "NO") : "-";
    if (r.in_tolerance && !*r.in_tolerance) out.push_back(c.feature + " " + c.axis);
    std::cout << fmt::format("  {:<12} {:<4} {:>11} {:>11} {:>9}  {:<19} {:<4} {:>12}\n", c.feature,
                             c.axis.empty() ? "-" : c.axis, mm(c.nominal_mm), mm(c.actual_mm),
                             signed_mm(r.deviation_mm), band, in,
                             r.after_offset_mm ? signed_mm(*r.after_offset_mm) : "-");
  }
  if (!p.pass) {
    std::cout << "verdict: none (the report gives no tolerances)\n";
  } else if (*p.pass) {
    std::cout << "verdict: PASS (all " << p.judged << " in tolerance)\n";
  } else {
    std::cout << "verdict: FAIL (" << p.out_of_tolerance << " of " << p.judged
              << " out of tolerance:";
    for (std::size_t k = 0; k < out.size(); ++k) std::cout << (k ? ", " : " ") << out[k];
    std::cout << ")\n";
  }
  if (!p.fit) return;
  const solver::PartOffsetFit& f = *p.fit;
  std::cout << "best-fit offset of the part (tolerance-weighted, " << f.characteristics
            << " X, Y, Z characteristics):\n";
  const char* const axes = "xyz";
  std::cout << "  displacement";
  for (int k = 0; k < 3; ++k) {
    std::cout << "  d" << axes[k] << " "
              << (f.axis_resolved[static_cast<std::size_t>(k)] ? signed_mm(f.translation_mm(k))
                                                               : "-");
  }
  std::cout << " mm (the work offset's correction is its opposite)\n";
  if (f.rotation_rad) {
    std::cout << "  rotation     "
              << fmt::format("about x {:+.1f}  y {:+.1f}  z {:+.1f} urad",
                             f.rotation_rad->x() * 1e6, f.rotation_rad->y() * 1e6,
                             f.rotation_rad->z() * 1e6)
              << " (about the report's origin)\n";
  } else {
    std::cout << "  rotation     not fitted (fewer than three features with X, Y and Z nominals "
                 "spanning a plane)\n";
  }
  for (const auto& why : f.left_out) std::cout << "  left out: " << why << "\n";
  for (const auto& w : f.warnings) std::cout << "  warning: " << w << "\n";
  std::cout << "  after it: " << f.out_of_tolerance_after
            << " out of tolerance, largest remaining deviation " << mm(f.max_abs_after_mm)
            << " mm\n";
}

}  // namespace

int run_cmm(const Options& o) {
  std::string why;
  const std::optional<std::string> text = read_text_file(o.file, &why);
  if (!text) throw CsvError(o.file, 0, 0, "cannot read: " + why);
  const solver::CmmReport report = solver::read_cmm_results(*text, o.file);
  const solver::PartInspection p = solver::inspect_part(report);
  if (o.json) {
    std::cout << json(document_of(p, report, o.file)).dump(2) << "\n";
  } else {
    print_cmm(p, report, o.file);
  }
  return p.pass && !*p.pass ? kExitFail : kExitOk;
}

}  // namespace ncqual::cli::analysis
