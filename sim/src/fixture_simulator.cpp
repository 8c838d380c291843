// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/fixture_simulator.hpp"

#include "ncqual/sim/contact.hpp"
#include "ncqual/probing/plan.hpp"
#include "ncqual/sim/request_random.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <vector>

namespace ncqual::sim {
namespace {

using probing::FixtureMove;
using probing::FixturePlan;
// Contact points computed in machine coordinates (~1e3 mm) carry rounding of ~1e-13 mm.
constexpr double kOnFaceTolMm = 1e-9;

std::string format_number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

// ---- The touch on the true block --------------------------------------------------------------

// Whether the contact point lies on the real face of the block whose top-face centre is p.
bool on_face(const FixtureConfig& f, const Eigen::Vector3d& p, PogoFace face,
             const Eigen::Vector3d& point) {
  const double h = f.block_half_size_mm() + kOnFaceTolMm;
  const Eigen::Vector3d d = point - p;
  const bool in_height = d.z() <= kOnFaceTolMm && d.z() >= -f.block_height_mm - kOnFaceTolMm;
  switch (face) {
    case PogoFace::Top: return std::abs(d.x()) <= h && std::abs(d.y()) <= h;
    case PogoFace::XMinus:
    case PogoFace::XPlus: return std::abs(d.y()) <= h && in_height;
    default: return std::abs(d.x()) <= h && in_height;
  }
}

// Runs one move on the true machine (MachineSimulator::execute) against the face it is meant to
// touch on the true block of its pogo (top-face centre p): the plane through p + face offset
// with outward normal n, where the contact point must lie on the block's real face. The probe
// deflects at once when the ball starts closer to that plane than its radius.
std::optional<Touch> execute_on_block(const MachineSimulator& machine, const FixtureConfig& f,
                                      const Eigen::Vector3d& p, const FixtureMove& fm,
                                      double noise_mm, std::string* why) {
  const Eigen::Vector3d n = outward_normal(fm.face);
  const Eigen::Vector3d plane_point = p + face_offset(f, fm.face);
  const auto meets_face = [&](const BallMove& ball) -> std::optional<Contact> {
    const auto s = ball_meets_plane(ball, plane_point, n);
    if (!s || *s > ball.travel_mm) return std::nullopt;
    const Eigen::Vector3d centre = ball.centre_at(*s);
    const Eigen::Vector3d point = centre - ball.ball_radius_mm * n;
    if (!on_face(f, p, fm.face, point)) return std::nullopt;
    return Contact{*s, fm.move.feature, centre, point};
  };
  const auto beyond_face = [&](const Eigen::Vector3d& centre, double radius) {
    return (centre - plane_point).dot(n) < radius;
  };
  return machine.execute(fm.move, noise_mm, meets_face, beyond_face,
                         "the pogo's reference block, beyond the face probed", why);
}

}  // namespace

// ---- FixtureSimulator -------------------------------------------------------------------------

FixtureSimulator::FixtureSimulator(FixtureConfig fixture, FixtureErrors errors,
                                   std::optional<SimulatorDrift> drift)
    : fixture_(std::move(fixture)), errors_(std::move(errors)), drift_(std::move(drift)) {}

FixtureSimulator FixtureSimulator::at(std::int64_t now_ns) const {
  FixtureSimulator frozen(fixture_, fixture_errors_at(errors_, drift_, now_ns));
  frozen.zero_offsets_ = zero_offsets_;
  return frozen;
}

FixtureSimulator FixtureSimulator::for_machine(const MachineConfig& machine,
                                               const SimulatorConfig& config) {
  if (!machine.fixture) {
    throw ConfigError(machine.source_path + ": machine '" + machine.machine_id +
                      "' has no `fixture:` section to simulate");
  }
  return FixtureSimulator(*machine.fixture, config.fixture, config.drift);
}

void FixtureSimulator::apply_zero_offsets(const Correction& correction) {
  const std::string target = "fixture:" + fixture_.fixture_id;
  if (correction.target != target) {
    throw std::invalid_argument("Correction.target = '" + correction.target +
                                "': this fixture's control unit takes '" + target + "'");
  }
  std::map<std::string, Eigen::Vector3d> updated = zero_offsets_;
  for (std::size_t i = 0; i < correction.offsets.size(); ++i) {
    const NamedValue& offset = correction.offsets[i];
    const std::string field = "Correction.offsets[" + std::to_string(i) + "]";
    const auto name = parse_zero_offset_name(offset.name);
    if (!name) {
      throw std::invalid_argument(field + ".name = '" + offset.name +
                                  "': expected '<pogo>.dx', '.dy' or '.dz', e.g. 'C2R3.dx'");
    }
    if (!fixture_has_pogo(fixture_, name->id)) {
      throw std::invalid_argument(field + ".name = '" + offset.name + "': fixture '" +
                                  fixture_.fixture_id + "' has no pogo " + name->pogo);
    }
    if (offset.unit != "mm") {
      throw std::invalid_argument(field + ".unit = '" + offset.unit + "' ('" + offset.name +
                                  "'): zero offsets are in 'mm'");
    }
    if (!std::isfinite(offset.value)) {
      throw std::invalid_argument(field + ".value = " + format_number(offset.value) + " ('" +
                                  offset.name + "') is not finite");
    }
    auto it = updated.try_emplace(name->pogo, Eigen::Vector3d::Zero()).first;
    it->second[name->axis] += offset.value;
  }
  zero_offsets_ = std::move(updated);
}

void FixtureSimulator::clear_zero_offsets() { zero_offsets_.clear(); }

Eigen::Vector3d FixtureSimulator::zero_offset_mm(const std::string& pogo) const {
  const auto it = zero_offsets_.find(pogo);
  return it == zero_offsets_.end() ? Eigen::Vector3d::Zero() : it->second;
}

Eigen::Vector3d FixtureSimulator::actuator_command_mm(const PogoPlacement& placement) const {
  return placement.commanded_mm - zero_offset_mm(placement.pogo);
}

Eigen::Vector3d FixtureSimulator::true_reference_point_mm(const PogoPlacement& placement) const {
  // p = origin + sum_j (a_j + e_j(a_j)) d_j + pogo_offset
  const Eigen::Vector3d a = actuator_command_mm(placement);
  const FixtureAxisErrors* axes[] = {&errors_.column_x, &errors_.pogo_y, &errors_.pogo_z};
  Eigen::Vector3d p = fixture_.origin_mm;
  for (int j = 0; j < 3; ++j) p += (a[j] + axes[j]->error_mm(a[j])) * axes[j]->direction(j);
  const auto it = errors_.pogo_offsets_mm.find(placement.pogo);
  if (it != errors_.pogo_offsets_mm.end()) p += it->second;
  return p;
}

Eigen::Vector3d FixtureSimulator::true_delta_mm(const PogoPlacement& placement) const {
  return true_reference_point_mm(placement) - fixture_.to_machine(placement.commanded_mm);
}

// ---- The check --------------------------------------------------------------------------------

MeasurementSet perform_fixture_check(const MachineSimulator& machine,
                                     const FixtureSimulator& fixture, const CheckRequest& request,
                                     std::int64_t time_ns) {
  // A drifting truth: measure on both frozen at the measurement time (no drift there).
  if (machine.config().drift || fixture.drift()) {
    return perform_fixture_check(machine.at(time_ns), fixture.at(time_ns), request, time_ns);
  }
  MeasurementSet set = measurement_set_for(request, time_ns);
  set.origin = DataOrigin::Simulated;
  set.instrument = "touch_probe";
  set.frame = "machine";

  if (request.machine_id != machine.machine().machine_id) {
    set.error = "the request is for machine '" + request.machine_id +
                "' but this simulator is machine '" + machine.machine().machine_id + "'";
    return set;
  }
  const FixturePlan program = probing::fixture_plan(fixture.fixture(), machine.machine().probe,
                                                    machine.machine().probing, request);
  if (!program.error.empty()) {
    set.error = program.error;
    return set;
  }

  // Where each placed pogo truly is: the deterministic errors, then the wear scatter.
  const std::uint64_t seed = machine.config().seed;
  NormalSource wear(request_seed(seed, request.request_id + "/fixture_wear"));
  const double wear_sigma = fixture.ground_truth().wear_sigma_mm;
  std::vector<Eigen::Vector3d> true_points;
  true_points.reserve(program.placements.size());
  for (const PogoPlacement& placement : program.placements) {
    Eigen::Vector3d scatter;
    for (int j = 0; j < 3; ++j) scatter[j] = wear_sigma * wear.next();
    true_points.push_back(fixture.true_reference_point_mm(placement) + scatter);
  }

  NormalSource noise(request_seed(seed, request.request_id));
  const double sigma = machine.config().trigger_noise_sigma_mm;
  std::vector<std::string> alarms;
  for (std::size_t i = 0; i < program.moves.size(); ++i) {
    const FixtureMove& fm = program.moves[i];
    // One deviate per move, drawn whether or not it triggers.
    const double noise_mm = sigma * noise.next();
    std::string why;
    if (auto touch = execute_on_block(machine, fixture.fixture(), true_points[fm.placement], fm,
                                      noise_mm, &why)) {
      set.touches.push_back(std::move(*touch));
    } else {
      alarms.push_back("move " + std::to_string(i) + " ('" + fm.move.feature + "'): " + why);
    }
  }
  for (std::size_t i = 0; i < alarms.size(); ++i) {
    set.error += (i ? "; " : "probe alarm: ") + alarms[i];
  }
  return set;
}

}  // namespace ncqual::sim
