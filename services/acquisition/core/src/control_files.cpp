// SPDX-License-Identifier: Apache-2.0
#include "ncqual/acquisition/control_files.hpp"

#include "ncqual/common/text.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace ncqual::acquisition {
namespace fs = std::filesystem;

namespace {

std::int64_t seconds_to_ns(double s) { return static_cast<std::int64_t>(s * 1e9); }

std::string format_seconds(double s) {
  std::ostringstream out;
  out << s << " s";
  return out.str();
}

// `text` up to and including its last line end: a control may be writing the line after it.
std::string complete_lines(const std::string& text) {
  const std::size_t end = text.rfind('\n');
  return end == std::string::npos ? std::string() : text.substr(0, end + 1);
}

// Moves `from` into `folder` (copy and remove across file systems); "" or why not.
std::string move_into(const std::string& from, const std::string& folder) {
  std::error_code ec;
  if (!fs::exists(from, ec)) return "";
  fs::create_directories(folder, ec);
  if (ec) return "cannot create " + folder + ": " + ec.message();
  const fs::path to = fs::path(folder) / fs::path(from).filename();
  fs::rename(from, to, ec);
  if (!ec) return "";
  ec.clear();
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  if (!ec) fs::remove(from, ec);
  return ec ? "cannot move " + from + " to " + folder + ": " + ec.message() : "";
}

}  // namespace

ControlFilesInstruments::ControlFilesInstruments(const MachineConfig& machine, const Clock& clock,
                                                 std::string version)
    : machine_(machine), clock_(clock), version_(std::move(version)) {}

std::optional<MeasurementSet> ControlFilesInstruments::measure(const CheckRequest& request,
                                                               std::int64_t time_ns) {
  const InstrumentConfig& cfg = machine_.instrument;
  Running r;
  r.request = request;
  r.program_path =
      (fs::path(cfg.outbox) / probing::program_file_name(request.request_id, cfg.dialect)).string();
  r.results_path =
      (fs::path(cfg.inbox) / probing::results_file_name(request.request_id, cfg.dialect)).string();
  std::string text;
  try {
    text = probing::write_program(request, machine_, cfg.dialect, version_);
    r.program = probing::read_program(text, r.program_path);
  } catch (const std::invalid_argument& e) {
    // No touch plan: a tracker check, a machine without the section the kind needs, a bad
    // parameter (write_program's refusal).
    return unmeasured(
        request, time_ns,
        std::string("the control-files driver cannot hand this check to the control: ") + e.what());
  } catch (const std::exception& e) {
    return unmeasured(request, time_ns, std::string("no probing program: ") + e.what());
  }
  std::string why;
  if (!write_file_atomically(r.program_path, text, &why)) {
    return unmeasured(request, time_ns,
                      "the probing program could not be handed to the control: " + r.program_path +
                          ": " + why + " (instrument.outbox of " + machine_.source_path + ")");
  }
  r.deadline_ns = clock_.now_ns() + seconds_to_ns(cfg.timeout_s);
  spdlog::info("{} {}: program of {} touches written to {}; waiting up to {} s for {}",
               request.machine_id, request.request_id, r.program.touches.size(), r.program_path,
               cfg.timeout_s, r.results_path);
  running_[request.request_id] = std::move(r);
  return std::nullopt;
}

std::optional<MeasurementSet> ControlFilesInstruments::collect(const Running& r,
                                                               std::int64_t now_ns) const {
  const bool late = now_ns >= r.deadline_ns;
  std::error_code ec;
  if (!fs::exists(r.results_path, ec)) {
    if (!late) return std::nullopt;
    return unmeasured(r.request, now_ns,
                      "no results from the control after " +
                          format_seconds(machine_.instrument.timeout_s) + ": " + r.results_path +
                          " was not written (program " + r.program_path + ")");
  }
  std::string why;
  const auto whole = read_text_file(r.results_path, &why);
  if (!whole) {
    if (!late) return std::nullopt;  // a share may refuse a file being written
    return unmeasured(r.request, now_ns, r.results_path + ": " + why);
  }
  try {
    const probing::TouchLog log =
        probing::read_touch_log(complete_lines(*whole), r.results_path, r.program.dialect);
    if (log.touches.size() < r.program.touches.size() && !late) return std::nullopt;
    // Complete, or late: the log's own refusal says what is missing.
    return probing::measurement_set_from_log(r.program, log, r.results_path, machine_, now_ns);
  } catch (const probing::ProgramError& e) {
    std::string error = e.what();
    if (late) {
      error += " (after " + format_seconds(machine_.instrument.timeout_s) +
               "; the control may have stopped at an alarm)";
    }
    return unmeasured(r.request, now_ns, error);
  }
}

std::vector<MeasurementSet> ControlFilesInstruments::poll() {
  std::vector<MeasurementSet> done;
  const std::int64_t now = clock_.now_ns();
  for (auto it = running_.begin(); it != running_.end();) {
    auto set = collect(it->second, now);
    if (!set) {
      ++it;
      continue;
    }
    archive(it->second);
    done.push_back(std::move(*set));
    it = running_.erase(it);
  }
  return done;
}

void ControlFilesInstruments::archive(const Running& r) const {
  for (const std::string& file : {r.program_path, r.results_path}) {
    if (const std::string why = move_into(file, machine_.instrument.archive); !why.empty()) {
      spdlog::warn("{} {}: {}", r.request.machine_id, r.request.request_id, why);
    }
  }
}

std::string ControlFilesInstruments::apply(const Correction& correction) {
  if (correction.target.rfind("fixture:", 0) != 0) return "";  // a work offset is the control's
  std::string name = correction.target;
  for (char& ch : name) {
    if (ch == ':' || ch == '/') ch = '-';
  }
  std::ostringstream text;
  text << "# zero offsets for " << correction.target << " of machine " << machine_.machine_id
       << ", in mm, written by " << version_ << "\n";
  char value[64];
  for (const auto& o : correction.offsets) {
    std::snprintf(value, sizeof value, "%.6f", o.value);
    text << o.name << ' ' << value << '\n';
  }
  const std::string path =
      (fs::path(machine_.instrument.outbox) / (name + "-zero-offsets.txt")).string();
  std::string why;
  if (!write_file_atomically(path, text.str(), &why)) {
    return "zero offsets for " + correction.target + " not written: " + path + ": " + why;
  }
  spdlog::info("{}: zero offsets for {} written to {} for the fixture's control",
               machine_.machine_id, correction.target, path);
  return "";
}

}  // namespace ncqual::acquisition
