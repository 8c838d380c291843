// SPDX-License-Identifier: Apache-2.0
// A part's CMM report judged, and the work offset that would have centred it.
//
// Gu & Agapiou (J. Manufacturing Systems 2018, "Global offset compensation") use the CMM
// measurements of machined parts to find the work offsets that minimise the part's errors: a
// least-squares fit, weighted by each feature's tolerance, of offset variables to the measured
// deviations, with the CMM frame on the part's origin. This is the fit's three-axis core: the
// part displaced rigidly by t and turned by a small rotation w about the report's origin moves a
// feature at nominal p by t + w x p, and
//     minimise sum_i ((d_i - e_k(i) . (t + w x p_i)) / h_i)^2
// over the X, Y and Z characteristics i (d_i actual - nominal, k(i) the axis, h_i the half-width
// of the tolerance band: a tight feature pulls harder). The rotary-head offset variables of the
// paper (the tool and table axes' offsets) are not fitted here.
//
// The rotation is fitted when at least three features have their X, Y and Z nominals and they
// span a plane (the normal matrix then has full rank); otherwise only the translation, from every
// X, Y and Z characteristic. A characteristic without a tolerance band gets the weight of the
// tightest band in the report (all weights 1 when none has one).
//
// A direction that only one characteristic constrains (a part with one Z point) is fitted all the
// same, but the fit says so (PartOffsetFit::warnings): its displacement is that one feature's
// deviation, which cannot tell the part's offset from the feature's own error.
#pragma once

#include "ncqual/solver/instrument_files.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace ncqual::solver {

struct InspectedCharacteristic {
  CmmCharacteristic characteristic;
  double deviation_mm = 0;                 // actual - nominal
  std::optional<bool> in_tolerance;        // none without a band
  std::optional<double> after_offset_mm;   // deviation less the fitted offset's share (X, Y, Z
                                           // characteristics used by the fit)
  std::optional<bool> in_tolerance_after;  // that deviation against the band
};

struct PartOffsetFit {
  // The part's best-fit displacement: the features sit at nominal + t + w x p. The work offset
  // correction that centres the next part is its opposite (-t, and -w where the control turns
  // its work offset, e.g. G68).
  Eigen::Vector3d translation_mm = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> rotation_rad;  // about the report's X, Y, Z; none: not fitted
  std::vector<bool> axis_resolved = {false, false, false};  // an X, Y, Z characteristic was used
  int characteristics = 0;                                  // used
  int out_of_tolerance_after = 0;                           // of those judged
  double max_abs_after_mm = 0;        // the largest remaining deviation of those used
  std::vector<std::string> left_out;  // "PNT7: only X of its position" (rotation fits)
  // Characteristics used along X, Y and Z (the rows of the fit's design matrix per direction).
  std::vector<int> constraining = {0, 0, 0};
  // A direction constrained by one characteristic alone: its displacement is that feature's own
  // deviation, with nothing to check it against ("Z: 1 characteristic (PNT1) ...").
  std::vector<std::string> warnings;
};

struct PartInspection {
  std::vector<InspectedCharacteristic> characteristics;
  int judged = 0, out_of_tolerance = 0;
  std::optional<bool> pass;          // none when no characteristic has a band
  std::optional<PartOffsetFit> fit;  // none without an X, Y or Z characteristic
};

PartInspection inspect_part(const CmmReport& report);

}  // namespace ncqual::solver
