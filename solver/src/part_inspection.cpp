// SPDX-License-Identifier: Apache-2.0
#include "ncqual/solver/part_inspection.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

namespace ncqual::solver {
namespace {

int axis_index(const std::string& axis) {
  return axis == "X" ? 0 : axis == "Y" ? 1 : axis == "Z" ? 2 : -1;
}

bool inside(double value, const CmmCharacteristic& c) {
  return *c.lower_mm <= value && value <= *c.upper_mm;
}

// d(e_k . (w x p)) / dw: the row of the rotation's unknowns for axis k at p.
Eigen::Vector3d rotation_row(int k, const Eigen::Vector3d& p) {
  switch (k) {
    case 0: return {0, p.z(), -p.y()};
    case 1: return {-p.z(), 0, p.x()};
    default: return {p.y(), -p.x(), 0};
  }
}

}  // namespace

PartInspection inspect_part(const CmmReport& report) {
  PartInspection out;
  double tightest = std::numeric_limits<double>::infinity();
  for (const CmmCharacteristic& c : report.characteristics) {
    InspectedCharacteristic r;
    r.characteristic = c;
    r.deviation_mm = c.deviation_mm();
    if (c.lower_mm && c.upper_mm) {
      r.in_tolerance = inside(r.deviation_mm, c);
      ++out.judged;
      if (!*r.in_tolerance) ++out.out_of_tolerance;
      const double h = (*c.upper_mm - *c.lower_mm) / 2;
      if (h > 0) tightest = std::min(tightest, h);
    }
    out.characteristics.push_back(std::move(r));
  }
  if (out.judged > 0) out.pass = out.out_of_tolerance == 0;

  // The fit over the X, Y, Z characteristics.
  std::vector<std::size_t> used;
  std::map<std::string, std::array<std::optional<double>, 3>> nominal_of;  // feature -> X, Y, Z
  for (std::size_t i = 0; i < out.characteristics.size(); ++i) {
    const CmmCharacteristic& c = out.characteristics[i].characteristic;
    const int k = axis_index(c.axis);
    if (k < 0) continue;
    used.push_back(i);
    nominal_of[c.feature][static_cast<std::size_t>(k)] = c.nominal_mm;
  }
  if (used.empty()) return out;
  const auto position = [&](const std::string& feature) -> std::optional<Eigen::Vector3d> {
    const auto& n = nominal_of.at(feature);
    if (!n[0] || !n[1] || !n[2]) return std::nullopt;
    return Eigen::Vector3d(*n[0], *n[1], *n[2]);
  };
  const double fallback = std::isfinite(tightest) ? tightest : 1.0;
  const auto weight = [&](const CmmCharacteristic& c) {
    const double h = c.lower_mm && c.upper_mm && *c.upper_mm > *c.lower_mm
                         ? (*c.upper_mm - *c.lower_mm) / 2
                         : fallback;
    return 1.0 / h;  // the square root of the weight: rows are scaled by it
  };

  // With the rotation: the characteristics of features with a whole nominal position.
  std::vector<std::size_t> located;
  std::vector<std::string> partial;
  for (std::size_t i : used) {
    const std::string& f = out.characteristics[i].characteristic.feature;
    if (position(f)) {
      located.push_back(i);
    } else if (std::find(partial.begin(), partial.end(), f) == partial.end()) {
      partial.push_back(f);
    }
  }
  PartOffsetFit fit;
  if (nominal_of.size() - partial.size() >= 3) {
    Eigen::MatrixXd a(static_cast<Eigen::Index>(located.size()), 6);
    Eigen::VectorXd b(static_cast<Eigen::Index>(located.size()));
    for (std::size_t r = 0; r < located.size(); ++r) {
      const CmmCharacteristic& c = out.characteristics[located[r]].characteristic;
      const int k = axis_index(c.axis);
      const double s = weight(c);
      const auto row = static_cast<Eigen::Index>(r);
      a.row(row).setZero();
      a(row, k) = s;
      a.block<1, 3>(row, 3) = s * rotation_row(k, *position(c.feature)).transpose();
      b(row) = s * out.characteristics[located[r]].deviation_mm;
    }
    // Unknowns in mm and rad over lever arms of the part's size: scale the rotation's columns so
    // that the rank test compares like with like.
    double arm = 0;
    for (const auto& [f, n] : nominal_of) {
      if (const auto p = position(f)) arm = std::max(arm, p->norm());
    }
    if (arm > 0) {
      a.rightCols<3>() /= arm;
      Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
      qr.setThreshold(1e-9);
      if (qr.rank() == 6) {
        const Eigen::VectorXd x = qr.solve(b);
        fit.translation_mm = x.head<3>();
        fit.rotation_rad = Eigen::Vector3d(x.tail<3>() / arm);
        used = located;
        for (const std::string& f : partial) {
          fit.left_out.push_back(f + ": not all of its X, Y and Z are in the report");
        }
      }
    }
  }
  if (!fit.rotation_rad) {  // weighted means per axis
    Eigen::Vector3d sum_w = Eigen::Vector3d::Zero(), sum_wd = Eigen::Vector3d::Zero();
    for (std::size_t i : used) {
      const CmmCharacteristic& c = out.characteristics[i].characteristic;
      const auto k = static_cast<Eigen::Index>(axis_index(c.axis));
      const double w = weight(c) * weight(c);
      sum_w(k) += w;
      sum_wd(k) += w * out.characteristics[i].deviation_mm;
    }
    for (int k = 0; k < 3; ++k) {
      if (sum_w(k) > 0) fit.translation_mm(k) = sum_wd(k) / sum_w(k);
    }
  }
  for (std::size_t i : used) {
    InspectedCharacteristic& r = out.characteristics[i];
    const int k = axis_index(r.characteristic.axis);
    fit.axis_resolved[static_cast<std::size_t>(k)] = true;
    double moved = fit.translation_mm(k);
    if (fit.rotation_rad) {
      moved += rotation_row(k, *position(r.characteristic.feature)).dot(*fit.rotation_rad);
    }
    r.after_offset_mm = r.deviation_mm - moved;
    fit.max_abs_after_mm = std::max(fit.max_abs_after_mm, std::abs(*r.after_offset_mm));
    if (r.in_tolerance) {
      r.in_tolerance_after = inside(*r.after_offset_mm, r.characteristic);
      if (!*r.in_tolerance_after) ++fit.out_of_tolerance_after;
    }
  }
  fit.characteristics = static_cast<int>(used.size());
  std::array<std::string, 3> only;  // the feature of a direction's first characteristic
  for (std::size_t i : used) {
    const CmmCharacteristic& c = out.characteristics[i].characteristic;
    const auto k = static_cast<std::size_t>(axis_index(c.axis));
    if (fit.constraining[k]++ == 0) only[k] = c.feature;
  }
  for (std::size_t k = 0; k < 3; ++k) {
    if (fit.constraining[k] != 1) continue;
    const std::string axis(1, static_cast<char>('X' + k));
    fit.warnings.push_back(axis + ": 1 characteristic (" + only[k] + " " + axis +
                           ") constrains the displacement along " + axis + ": d" +
                           static_cast<char>('x' + k) +
                           " is that feature's own deviation, "
                           "not a best fit; measure more features along " +
                           axis + " before correcting the work offset with it");
  }
  out.fit = fit;
  return out;
}

}  // namespace ncqual::solver
