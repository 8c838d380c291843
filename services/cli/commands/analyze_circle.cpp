// SPDX-License-Identifier: Apache-2.0
// `ncqual analyze circle`: a circular test (ballbar, grid encoder, tracker) evaluated per
// ISO 230-4, printed as a table or as its --json document.
#include "analyze.hpp"

#include "ncqual/common/csv.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/common/units.hpp"
#include "ncqual/solver/circular_test.hpp"
#include "ncqual/solver/instrument_files.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::cli::analysis {
namespace {

using units::kPi;

using nlohmann::json;

std::string fixed(double v, int decimals) { return fmt::format("{:.{}f}", v, decimals); }
std::string fixed(const std::optional<double>& v, int decimals) {
  return v ? fixed(*v, decimals) : "-";
}

// The --json document of circle (names: the comment at the top of analyze.cpp).
struct HarmonicsDocument {
  double a0 = 0, a1 = 0, b1 = 0, a2 = 0, b2 = 0, residual_rms = 0;
};
struct ReferenceDocument {
  std::string centre, radius;  // "nominal" or "lsc"
  Eigen::Vector2d centre_mm = Eigen::Vector2d::Zero();
  double radius_mm = 0;
};
struct ArcDocument {
  bool full_circle = true;
  double from_deg = 0, span_deg = 360;
};
struct PathDocument {
  int points = 0;
  Eigen::Vector2d lsc_centre_mm = Eigen::Vector2d::Zero();
  double lsc_radius_mm = 0, lsc_rms_mm = 0, G_mm = 0, F_max_mm = 0, F_min_mm = 0;
  ReferenceDocument F_reference;
  double max_gap_deg = 0;
  std::optional<double> scale_mismatch_um_per_m, squareness_urad;
  std::optional<HarmonicsDocument> harmonics_mm;
  ArcDocument arc;
  double shape_noise_gain = 1;
};
struct DirectionsDocument {
  std::optional<PathDocument> ccw, cw;
};
struct CircleDocument {
  std::string standard = "ISO 230-4";
  std::string file;
  std::string unit = "mm";
  std::string plane, layout;
  std::size_t points = 0;
  Eigen::Vector2d lsc_centre_mm = Eigen::Vector2d::Zero();
  double lsc_radius_mm = 0, G_mm = 0;
  std::optional<double> G_b_mm, H_mm;
  double F_max_mm = 0, F_min_mm = 0;
  ReferenceDocument F_reference;
  std::optional<double> scale_mismatch_um_per_m, squareness_urad;
  std::optional<HarmonicsDocument> harmonics_mm;
  DirectionsDocument directions;
  ArcDocument arc;
  double shape_noise_gain = 1;
  std::optional<double> H_overlap_deg;
  std::vector<std::string> warnings;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(HarmonicsDocument, a0, a1, b1, a2, b2, residual_rms)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ReferenceDocument, centre, radius, centre_mm, radius_mm)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ArcDocument, full_circle, from_deg, span_deg)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(PathDocument, points, lsc_centre_mm, lsc_radius_mm, lsc_rms_mm,
                                   G_mm, F_max_mm, F_min_mm, F_reference, max_gap_deg,
                                   scale_mismatch_um_per_m, squareness_urad, harmonics_mm, arc,
                                   shape_noise_gain)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DirectionsDocument, ccw, cw)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CircleDocument, standard, file, unit, plane, layout, points,
                                   lsc_centre_mm, lsc_radius_mm, G_mm, G_b_mm, H_mm, F_max_mm,
                                   F_min_mm, F_reference, scale_mismatch_um_per_m, squareness_urad,
                                   harmonics_mm, directions, arc, shape_noise_gain, H_overlap_deg,
                                   warnings)

std::optional<HarmonicsDocument> harmonics_document(
    const std::optional<solver::RadialHarmonics>& h) {
  if (!h) return std::nullopt;
  return HarmonicsDocument{h->a0_mm, h->a1_mm, h->b1_mm, h->a2_mm, h->b2_mm, h->residual_rms_mm};
}

ArcDocument arc_document(const solver::CircularArc& a) {
  return {a.full_circle, a.from_rad * 180.0 / kPi, a.span_rad * 180.0 / kPi};
}

ReferenceDocument reference_document(const solver::RadialReference& ref) {
  return {ref.nominal_centre ? "nominal" : "lsc", ref.nominal_radius ? "nominal" : "lsc",
          ref.centre_mm, ref.radius_mm};
}

std::optional<PathDocument> path_document(const std::optional<solver::CircularPathFigures>& p) {
  if (!p) return std::nullopt;
  return PathDocument{p->point_count,
                      p->lsc_centre_mm,
                      p->lsc_radius_mm,
                      p->lsc_rms_mm,
                      p->G_mm,
                      p->F_max_mm,
                      p->F_min_mm,
                      reference_document(p->F_reference),
                      p->max_gap_rad * 180.0 / kPi,
                      p->scale_mismatch_um_per_m,
                      p->squareness_urad,
                      harmonics_document(p->harmonics),
                      arc_document(p->arc),
                      p->shape_noise_gain};
}

CircleDocument document_of(const solver::CircularTestResult& r, const solver::CircleFile& data,
                           const std::string& file) {
  CircleDocument d;
  d.file = file;
  d.plane = solver::to_string(r.plane);
  d.layout = data.deviations ? "deviations" : data.polar ? "polar" : "coordinates";
  d.points = data.input.points.size();
  d.lsc_centre_mm = r.lsc_centre_mm;
  d.lsc_radius_mm = r.lsc_radius_mm;
  d.G_mm = r.G_mm;
  d.G_b_mm = r.G_b_mm;
  d.H_mm = r.H_mm;
  d.F_max_mm = r.F_max_mm;
  d.F_min_mm = r.F_min_mm;
  d.F_reference = reference_document(r.F_reference);
  d.scale_mismatch_um_per_m = r.scale_mismatch_um_per_m;
  d.squareness_urad = r.squareness_urad;
  d.harmonics_mm = harmonics_document(r.harmonics);
  d.directions = {path_document(r.ccw), path_document(r.cw)};
  d.arc = arc_document(r.arc);
  d.shape_noise_gain = r.shape_noise_gain;
  if (r.H_mm) d.H_overlap_deg = r.H_overlap_rad * 180.0 / kPi;
  d.warnings = solver::iso230_4_conformance(r);
  return d;
}

std::string reference_text(const solver::RadialReference& ref) {
  return (ref.nominal_centre ? "nominal centre (" : "LSC centre (") + mm(ref.centre_mm.x()) + ", " +
         mm(ref.centre_mm.y()) + ") mm, " +
         (ref.nominal_radius ? "nominal radius R0 " : "LSC radius ") + mm(ref.radius_mm) + " mm";
}

void print_circle(const solver::CircularTestResult& r, const solver::CircleFile& data,
                  const std::string& file) {
  const std::string plane(solver::to_string(r.plane));
  const std::string u(1, plane[0]), v(1, plane[1]);
  fmt::print("ISO 230-4 circular test: {}\n", file);
  fmt::print("  plane {} (u = {}, v = {}), {} points ({}), directions:{}{}\n", plane, u, v,
             data.input.points.size(),
             data.deviations ? "angle, radial deviation"
             : data.polar    ? "angle, radius"
                             : "coordinates",
             r.ccw ? " ccw" : "", r.cw ? " cw" : "");
  if (!r.arc.full_circle) {
    fmt::print(
        "  a partial arc of {} deg, from {} deg counter-clockwise (angles from +{} towards +{})\n",
        fixed(r.arc.span_rad * 180.0 / kPi, 1),
        // 359.97 deg is 0.0, not 360.0
        fixed(std::fmod(std::round(r.arc.from_rad * 1800.0 / kPi) / 10.0, 360.0), 1), u, v);
  }
  fmt::print("  least-squares circle of all points: centre ({}, {}) = ({}, {}) mm, radius {} mm\n",
             u, v, mm(r.lsc_centre_mm.x()), mm(r.lsc_centre_mm.y()), mm(r.lsc_radius_mm));
  fmt::print("  F measured from the {}\n\n", reference_text(r.F_reference));

  auto path_value = [](const std::optional<solver::CircularPathFigures>& p, auto get) {
    return p ? get(*p) : std::string("-");
  };
  fmt::print("{:34}{:>12}{:>12}{:>12}\n", "", "ccw", "cw", "both");
  auto row = [&](const char* name, const std::string& ccw, const std::string& cw,
                 const std::string& both) {
    // The names are padded in bytes, as they always were (the degree sign is two).
    fmt::print("  {:<32}{:>12}{:>12}{:>12}\n", fmt::bytes(name), ccw, cw, both);
  };
  using P = solver::CircularPathFigures;
  row("points", path_value(r.ccw, [](const P& p) { return std::to_string(p.point_count); }),
      path_value(r.cw, [](const P& p) { return std::to_string(p.point_count); }),
      std::to_string(data.input.points.size()));
  row("LSC radius (mm)", path_value(r.ccw, [](const P& p) { return mm(p.lsc_radius_mm); }),
      path_value(r.cw, [](const P& p) { return mm(p.lsc_radius_mm); }), mm(r.lsc_radius_mm));
  row("G  circular deviation (mm)", path_value(r.ccw, [](const P& p) { return mm(p.G_mm); }),
      path_value(r.cw, [](const P& p) { return mm(p.G_mm); }), "-");
  row("G(b) bidirectional (mm)", "-", "-", mm(r.G_b_mm));
  row("H  circular hysteresis (mm)", "-", "-", mm(r.H_mm));
  row("F_max radial deviation (mm)", path_value(r.ccw, [](const P& p) { return mm(p.F_max_mm); }),
      path_value(r.cw, [](const P& p) { return mm(p.F_max_mm); }), mm(r.F_max_mm));
  row("F_min radial deviation (mm)", path_value(r.ccw, [](const P& p) { return mm(p.F_min_mm); }),
      path_value(r.cw, [](const P& p) { return mm(p.F_min_mm); }), mm(r.F_min_mm));
  row("scale mismatch u - v (um/m)",
      path_value(r.ccw, [](const P& p) { return fixed(p.scale_mismatch_um_per_m, 1); }),
      path_value(r.cw, [](const P& p) { return fixed(p.scale_mismatch_um_per_m, 1); }),
      fixed(r.scale_mismatch_um_per_m, 1));
  row("squareness (urad, >0: over 90°)",
      path_value(r.ccw, [](const P& p) { return fixed(p.squareness_urad, 1); }),
      path_value(r.cw, [](const P& p) { return fixed(p.squareness_urad, 1); }),
      fixed(r.squareness_urad, 1));
  const auto arc_text = [](const solver::CircularArc& a) {
    return a.full_circle ? std::string("360") : fixed(a.span_rad * 180.0 / kPi, 1);
  };
  row("arc measured (deg)", path_value(r.ccw, [&](const P& p) { return arc_text(p.arc); }),
      path_value(r.cw, [&](const P& p) { return arc_text(p.arc); }), arc_text(r.arc));
  row("largest angular gap (deg)",
      path_value(r.ccw, [](const P& p) { return fixed(p.max_gap_rad * 180.0 / kPi, 1); }),
      path_value(r.cw, [](const P& p) { return fixed(p.max_gap_rad * 180.0 / kPi, 1); }), "-");
  if (r.ccw && r.cw) {
    fmt::print(
        "\n  The scale mismatch and squareness of one direction include its reversal "
        "errors;\n  those of both directions together cancel them.\n");
  }
  const std::vector<std::string> warnings = solver::iso230_4_conformance(r);
  fmt::print("\nConformance to ISO 230-4: {}\n",
             warnings.empty() ? "the test conforms" : "the figures above are given, but");
  for (const auto& w : warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace

int run_circle(const Options& o) {
  const std::string& file = o.file;
  const std::optional<solver::Plane> plane = plane_option(o.plane);
  const std::optional<double> nominal_radius = o.nominal_radius_mm;
  if (nominal_radius && !(std::isfinite(*nominal_radius) && *nominal_radius > 0)) {
    throw UsageError(
        fmt::format("--nominal-radius-mm {}: expected a radius > 0 (mm)", *nominal_radius));
  }
  std::optional<Eigen::Vector2d> centre;
  if (o.centre_mm) {
    const auto [u, v] = centre_option(*o.centre_mm);
    centre = Eigen::Vector2d(u, v);
  }

  solver::CircleFile data = solver::read_circle_csv(read_csv_file(file), plane, nominal_radius);
  data.input.nominal_centre_mm = centre;
  const solver::CircularTestResult r = solver::evaluate_circular_test(data.input);
  if (o.json) {
    std::cout << json(document_of(r, data, file)).dump(2) << "\n";
  } else {
    print_circle(r, data, file);
  }
  return kExitOk;
}

void circle_options(CLI::App* circle, Options& o) {
  circle
      ->add_option("--plane", o.plane,
                   "the plane (needed for angle_deg,radius_mm and u_mm,v_mm files)")
      ->type_name("XY|YZ|XZ");
  circle
      ->add_option(
          "--nominal-radius-mm", o.nominal_radius_mm,
          "F about this radius (default: the file's '# Radius:', else the least-squares circle's)")
      ->type_name("R");
  circle
      ->add_option("--centre-mm", o.centre_mm,
                   "F about this centre in the plane's u, v (default: the least-squares one)")
      ->type_name("U,V");
}

}  // namespace ncqual::cli::analysis
