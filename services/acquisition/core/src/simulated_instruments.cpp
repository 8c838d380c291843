// SPDX-License-Identifier: Apache-2.0
#include "ncqual/acquisition/instruments.hpp"

#include "ncqual/acquisition/control_files.hpp"

#include "ncqual/common/check_kinds.hpp"

#include <spdlog/spdlog.h>

#include <stdexcept>

namespace ncqual::acquisition {

MeasurementSet unmeasured(const CheckRequest& request, std::int64_t time_ns,
                          const std::string& error) {
  MeasurementSet set = measurement_set_for(request, time_ns);
  set.error = error;
  return set;
}

std::unique_ptr<Instruments> make_instruments(const MachineConfig& machine, const Clock& clock,
                                              const std::string& version) {
  switch (machine.instrument.driver) {
    case InstrumentDriver::ControlFiles:
      spdlog::info(
          "{}: measured by its control ({}): programs to {}, results from {}, archived in {}, "
          "timeout {} s",
          machine.machine_id, to_string(machine.instrument.dialect), machine.instrument.outbox,
          machine.instrument.inbox, machine.instrument.archive, machine.instrument.timeout_s);
      return std::make_unique<ControlFilesInstruments>(machine, clock, version);
    case InstrumentDriver::Simulator: break;
  }
  return std::make_unique<SimulatedInstruments>(machine);
}

SimulatedInstruments::SimulatedInstruments(const MachineConfig& machine)
    : machine_(machine), simulator_(machine_, machine_.simulator) {
  if (machine_.fixture) fixture_ = sim::FixtureSimulator::for_machine(machine_, machine_.simulator);
  if (machine_.global_check) tracker_.emplace(machine_, machine_.simulator);
}

std::optional<MeasurementSet> SimulatedInstruments::measure(const CheckRequest& request,
                                                            std::int64_t time_ns) {
  MeasurementSet set = simulate(request, time_ns);
  set.origin = origin();  // also a set that says why it could not be simulated
  return set;
}

MeasurementSet SimulatedInstruments::simulate(const CheckRequest& request, std::int64_t time_ns) {
  switch (check_kind_info(request.kind).instrument) {
    case Instrument::FixtureProbe:
      if (!fixture_) {
        return unmeasured(request, time_ns,
                          "machine '" + machine_.machine_id + "' has no fixture: section to probe");
      }
      return sim::perform_fixture_check(simulator_, *fixture_, request, time_ns);
    case Instrument::LaserTracker:
      if (!tracker_) {
        return unmeasured(request, time_ns,
                          "machine '" + machine_.machine_id +
                              "' has no global_check: section for the laser tracker");
      }
      return tracker_->perform(request, time_ns);
    case Instrument::TouchProbe: break;
  }
  return simulator_.perform(request, time_ns);
}

std::string SimulatedInstruments::apply(const Correction& correction) {
  if (correction.target.rfind("fixture:", 0) != 0) return "";
  if (!fixture_) {
    return "zero offsets for " + correction.target + " but machine '" + machine_.machine_id +
           "' has no fixture";
  }
  try {
    fixture_->apply_zero_offsets(correction);
  } catch (const std::invalid_argument& e) {
    return std::string("zero offsets refused: ") + e.what();
  }
  return "";
}

}  // namespace ncqual::acquisition
