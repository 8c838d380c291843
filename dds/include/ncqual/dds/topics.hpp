// SPDX-License-Identifier: Apache-2.0
// The topics of ncqual: name, wire type, domain type and QoS profiles of each.
#pragma once

#include "ncqual.h"
#include "ncqualPubSubTypes.h"
#include "ncqual/dds/participant.hpp"
#include "ncqual/common/model.hpp"

namespace ncqual::dds {

// The wire contract this build writes (idl/ncqual.idl; docs/architecture.md, "Changing the wire
// contract"): a struct whose layout changes gets a new type name, in the IDL module of the
// contract that changed it, on the same topic name.
inline constexpr int kWireContract = 2;

// PER_MACHINE: the topic's samples travel in their machine's partition (machine_partition):
// written by a MachineWriters, read by an acquisition in its machines' partitions only, and
// refused by every reader when a writer in machine partitions writes another machine's.
// CONTRACT: the contract whose layout WIRE is (that of the last change of the type).
#define NCQUAL_TOPIC_OF(TRAITS, NAME, MODEL, WIRE, CONTRACT, WRITER_PROFILE, READER_PROFILE, \
                        PER_MACHINE)                                                         \
  struct TRAITS {                                                                            \
    using Model = ::ncqual::MODEL;                                                           \
    using Wire = ::ncqual::msg::WIRE;                                                        \
    using PubSub = ::ncqual::msg::WIRE##PubSubType;                                          \
    static constexpr const char* kName = NAME;                                               \
    static constexpr const char* kWriterProfile = WRITER_PROFILE;                            \
    static constexpr const char* kReaderProfile = READER_PROFILE;                            \
    static constexpr bool kPerMachine = PER_MACHINE;                                         \
    static constexpr int kContract = CONTRACT;                                               \
  }
#define NCQUAL_TOPIC(TRAITS, NAME, MODEL, WRITER_PROFILE, READER_PROFILE, PER_MACHINE) \
  NCQUAL_TOPIC_OF(TRAITS, NAME, MODEL, MODEL, 1, WRITER_PROFILE, READER_PROFILE, PER_MACHINE)

// Durable topics: a late-joining or restarted historian or solver still gets what it missed
// (TRANSIENT_LOCAL, KEEP_LAST with a deep history; storing is idempotent on the request id).
NCQUAL_TOPIC(CheckRequestTopic, "ncqual/CheckRequest", CheckRequest, profiles::kDurableWriter,
             profiles::kDurableReader, true);
NCQUAL_TOPIC_OF(MeasurementSetTopic, "ncqual/MeasurementSet", MeasurementSet, v2::MeasurementSet, 2,
                profiles::kDurableWriter, profiles::kDurableReader, true);
NCQUAL_TOPIC_OF(CheckResultTopic, "ncqual/CheckResult", CheckResult, v2::CheckResult, 2,
                profiles::kDurableWriter, profiles::kDurableReader, false);
NCQUAL_TOPIC(MachineStatusTopic, "ncqual/MachineStatus", MachineStatus, profiles::kDurableWriter,
             profiles::kDurableReader, false);
NCQUAL_TOPIC(CompensationTopic, "ncqual/Compensation", Compensation, profiles::kDurableWriter,
             profiles::kDurableReader, true);
// Operator topics: written by the short-lived command-line tool, which waits for its readers
// and their acknowledgements before it exits.
NCQUAL_TOPIC(CheckCommandTopic, "ncqual/CheckCommand", CheckCommand, profiles::kCommandWriter,
             profiles::kCommandReader, false);
NCQUAL_TOPIC(InterventionTopic, "ncqual/Intervention", Intervention, profiles::kCommandWriter,
             profiles::kCommandReader, false);
// Acknowledgements: what the historian committed and what the services took into their durable
// state. Volatile: a producer that misses one sends the sample again and is acknowledged again.
NCQUAL_TOPIC(AcknowledgementTopic, "ncqual/Acknowledgement", Acknowledgement, profiles::kAckWriter,
             profiles::kAckReader, false);
// Alarms: the latest state of each alarm (active or cleared); durable, so a monitor that joins
// late sees what was raised before it.
NCQUAL_TOPIC(AlarmTopic, "ncqual/Alarm", Alarm, profiles::kAlarmWriter, profiles::kAlarmReader,
             false);
// Trend warnings: raised, updated and ended by the historian; durable like the alarms, with
// their QoS.
NCQUAL_TOPIC(TrendWarningTopic, "ncqual/TrendWarning", TrendWarning, profiles::kAlarmWriter,
             profiles::kAlarmReader, false);
NCQUAL_TOPIC(HeartbeatTopic, "ncqual/Heartbeat", Heartbeat, profiles::kHeartbeatWriter,
             profiles::kHeartbeatReader, false);

// Contract 1's layouts of the types contract 2 changed, on the same topics: read only, by the
// historian (what an older service sends) and by a replay (what an older recording holds).
NCQUAL_TOPIC_OF(MeasurementSetContract1Topic, "ncqual/MeasurementSet", MeasurementSet,
                MeasurementSet, 1, profiles::kDurableWriter, profiles::kDurableReader, true);
NCQUAL_TOPIC_OF(CheckResultContract1Topic, "ncqual/CheckResult", CheckResult, CheckResult, 1,
                profiles::kDurableWriter, profiles::kDurableReader, false);

#undef NCQUAL_TOPIC
#undef NCQUAL_TOPIC_OF

}  // namespace ncqual::dds
