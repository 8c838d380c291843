// SPDX-License-Identifier: Apache-2.0
// The DDS domain ids of the multi-process tests, allocated here and nowhere else.
//
// ctest runs tests in parallel (-j2 and more), and two tests on one domain would hear each
// other's samples: every test that joins DDS has its own id, and Plant takes only a TestDomain,
// never a number. The ids must be unique and within 170-232 (the demo draws from 100-169, a
// plant's default is below 100, and 232 is the highest domain id Fast DDS's default port mapping
// allows). A new test adds one enumerator here, and one case in domain_id() below.
//
// Tests that write a plant file only for commands that never join DDS (budget, uncertainty,
// config check, status) need no id.
#pragma once

#include <stdexcept>

namespace ncqual::testing {

namespace detail {
// In an enumerator's initializer: an id outside 170-232 does not compile.
constexpr int test_domain(int id) {
  return id >= 170 && id <= 232 ? id : throw std::logic_error("DDS test domains are 170-232");
}
}  // namespace detail

enum class TestDomain : int {
  EndToEnd = detail::test_domain(201),           // EndToEnd.CheckThreeOfTwoMachines...
  OperatorCheck = detail::test_domain(202),      // EndToEnd.OperatorCheckGoesThrough...
  HistorianRestart = detail::test_domain(203),   // HistorianRestart.*
  BadInput = detail::test_domain(204),           // BadInput.*
  FixtureLoop = detail::test_domain(205),        // FixtureLoop.*
  Import = detail::test_domain(206),             // Import.*
  CalendarReference = detail::test_domain(207),  // Calendar.SchedulerKilled...: the undisturbed run
  CalendarSchedulerKill = detail::test_domain(208),  // Calendar.SchedulerKilled...: the killed one
  Fleet = detail::test_domain(209),                  // Fleet.TwentyMachinesThreeWeeks...
  FleetArguments = detail::test_domain(210),         // Fleet.AcquisitionRefusesABadMachineList...
  FleetSchedulerPerMachine = detail::test_domain(211),    // Fleet.OneSchedulerPerMachine...
  CalendarAcquisitionRestart = detail::test_domain(212),  // Calendar.RestartedAcquisition...
  DefaultQos = detail::test_domain(213),                  // BadInput.APlantWhoseQosProfiles...
  Conflict = detail::test_domain(214),                    // Conflict.*
  CampaignReference = detail::test_domain(215),           // FaultCampaign.*: the undisturbed run
  CampaignKill = detail::test_domain(216),                // FaultCampaign.*: the disturbed one
  StorageFaults = detail::test_domain(217),               // StorageFaults.*
  NetworkReference = detail::test_domain(218),  // FaultCampaign.ALossy...: the undisturbed run
  NetworkImpaired = detail::test_domain(219),   // FaultCampaign.ALossy...: the impaired one
  AckBench = detail::test_domain(220),          // ncqual_ack_bench (tests/bench), its smoke run
  ImportLarge = detail::test_domain(221),       // Import.ALargeCircle...
  // ncqual_import_bench (tests/bench), its smoke run
  ImportBench = detail::test_domain(222),
  // StorageFaults.ADamagedFile...
  StorageDamaged = detail::test_domain(223),
  // ControlFiles.*: the control-files driver with a stand-in control
  ControlFiles = detail::test_domain(224),
  // LinuxCnc.*: a daily check on LinuxCNC through the control-files driver
  LinuxCnc = detail::test_domain(225),
  // PlantNetwork.*: hosts in network namespaces, discovery through a discovery server
  PlantNetwork = detail::test_domain(226),
  // SecurePlant.*: DDS Security with ncqual-pki's identities and permissions
  SecurePlant = detail::test_domain(227),
  // Cyclone.*: ncqual-cyclone-peer, a reader and writer built with Cyclone DDS, against the plant
  Cyclone = detail::test_domain(228),
  // ServiceManager.*: a service's notifications to systemd (sd_notify)
  ServiceManager = detail::test_domain(229),
  // ncqual_secure_bench (tests/bench), its smoke run: the open plant and the secured one
  SecureBenchOpen = detail::test_domain(230),
  SecureBenchSecured = detail::test_domain(231),
  // PlantNetwork.ASecuredPlantOfHosts...: the namespaces' hosts, secured, discovering by peers
  PlantNetworkSecured = detail::test_domain(232),
  // Recordings.*: the live plant recorded, and the plant its recording is replayed into
  RecordingLive = detail::test_domain(170),
  RecordingReplay = detail::test_domain(171),
  // CommittedRecordings.*: each committed recording replayed into a historian and a solver
  RecordingCommittedDrift = detail::test_domain(172),
  RecordingCommitted = detail::test_domain(173),
  // ncqual_recording_bench (tests/bench), its smoke run
  RecordingBench = detail::test_domain(174),
  // McapInteropRecordings.FoxgloveReadsWhatTheLiveRecorderWrote: a replay recorded live
  RecordingInterop = detail::test_domain(175),
  // TrendWarnings.*: a machine drifting on the simulated clock, the historian running its watch
  TrendWarnings = detail::test_domain(176),
  // Permissions.*: every role, topic and partition against Fast DDS's own permission checks
  Permissions = detail::test_domain(177),
  // SecurePlant.AnAcquisitionIdentityCannotMeasureAnotherMachine: the attack of issue 35
  SecureAttack = detail::test_domain(178),
  // Conflict.AConflictingMeasurementHoldsTheMachine...: the scheduler holds on a conflict
  ConflictHold = detail::test_domain(179),
  // WireContract.*: a service of the previous wire contract in a plant of the current one
  WireContract = detail::test_domain(180),
};

// The id as an int. The switch is the check that no two ids are equal: two case labels with the
// same value do not compile, and -Wswitch names an enumerator that is missing here.
constexpr int domain_id(TestDomain domain) {
  switch (domain) {
    case TestDomain::EndToEnd:
    case TestDomain::OperatorCheck:
    case TestDomain::HistorianRestart:
    case TestDomain::BadInput:
    case TestDomain::FixtureLoop:
    case TestDomain::Import:
    case TestDomain::CalendarReference:
    case TestDomain::CalendarSchedulerKill:
    case TestDomain::Fleet:
    case TestDomain::FleetArguments:
    case TestDomain::FleetSchedulerPerMachine:
    case TestDomain::CalendarAcquisitionRestart:
    case TestDomain::DefaultQos:
    case TestDomain::Conflict:
    case TestDomain::CampaignReference:
    case TestDomain::CampaignKill:
    case TestDomain::StorageFaults:
    case TestDomain::NetworkReference:
    case TestDomain::NetworkImpaired:
    case TestDomain::AckBench:
    case TestDomain::ImportLarge:
    case TestDomain::ImportBench:
    case TestDomain::StorageDamaged:
    case TestDomain::ControlFiles:
    case TestDomain::LinuxCnc:
    case TestDomain::PlantNetwork:
    case TestDomain::SecurePlant:
    case TestDomain::Cyclone:
    case TestDomain::ServiceManager:
    case TestDomain::SecureBenchOpen:
    case TestDomain::SecureBenchSecured:
    case TestDomain::PlantNetworkSecured:
    case TestDomain::RecordingLive:
    case TestDomain::RecordingReplay:
    case TestDomain::RecordingCommittedDrift:
    case TestDomain::RecordingCommitted:
    case TestDomain::RecordingBench:
    case TestDomain::RecordingInterop:
    case TestDomain::TrendWarnings:
    case TestDomain::Permissions:
    case TestDomain::SecureAttack:
    case TestDomain::ConflictHold:
    case TestDomain::WireContract: break;
  }
  return static_cast<int>(domain);
}

}  // namespace ncqual::testing
