// SPDX-License-Identifier: Apache-2.0
// Conversions between the wire types generated from idl/ncqual.idl and the domain model.
// from_wire never trusts its input: an enum out of range or a non-finite number in a header
// field is reported in `error` (naming the field and value) rather than thrown, so a service can
// answer a malformed sample (e.g. with an INVALID result) and keep running.
#pragma once

#include "ncqual.h"
#include "ncqual/common/model.hpp"

#include <string>
#include <type_traits>

namespace ncqual::dds {

msg::CheckRequest to_wire(const CheckRequest& v);
msg::CheckCommand to_wire(const CheckCommand& v);
msg::v2::MeasurementSet to_wire(const MeasurementSet& v);
msg::v2::CheckResult to_wire(const CheckResult& v);
msg::MachineStatus to_wire(const MachineStatus& v);
msg::Intervention to_wire(const Intervention& v);
msg::Compensation to_wire(const Compensation& v);
msg::Heartbeat to_wire(const Heartbeat& v);
msg::Acknowledgement to_wire(const Acknowledgement& v);
msg::Alarm to_wire(const Alarm& v);
msg::TrendWarning to_wire(const TrendWarning& v);

// Each returns the model; `error` is set (and the model holds what could be read, at least
// machine_id and the request id) when the sample is malformed.
CheckRequest from_wire(const msg::CheckRequest& w, std::string& error);
CheckCommand from_wire(const msg::CheckCommand& w, std::string& error);
MeasurementSet from_wire(const msg::v2::MeasurementSet& w, std::string& error);
CheckResult from_wire(const msg::v2::CheckResult& w, std::string& error);
MachineStatus from_wire(const msg::MachineStatus& w, std::string& error);
Intervention from_wire(const msg::Intervention& w, std::string& error);
Compensation from_wire(const msg::Compensation& w, std::string& error);
Heartbeat from_wire(const msg::Heartbeat& w, std::string& error);
Acknowledgement from_wire(const msg::Acknowledgement& w, std::string& error);
Alarm from_wire(const msg::Alarm& w, std::string& error);
TrendWarning from_wire(const msg::TrendWarning& w, std::string& error);

// Wire contract 1's layouts (docs/architecture.md, "Changing the wire contract"): read from
// services of an older version and from their recordings, with the origin Unknown; written only
// by tests and tools that stand in for such a service.
MeasurementSet from_wire(const msg::MeasurementSet& w, std::string& error);
CheckResult from_wire(const msg::CheckResult& w, std::string& error);
msg::MeasurementSet to_wire_contract1(const MeasurementSet& v);
msg::CheckResult to_wire_contract1(const CheckResult& v);

// The sample in layout `Wire`: the current one, or contract 1's (for a topic's *Contract1Topic).
template <typename Wire, typename Model>
Wire to_wire_as(const Model& v) {
  if constexpr (std::is_same_v<Wire, decltype(to_wire(v))>) {
    return to_wire(v);
  } else {
    return to_wire_contract1(v);
  }
}

}  // namespace ncqual::dds
