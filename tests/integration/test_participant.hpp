// SPDX-License-Identifier: Apache-2.0
// A test's own DDS participant in a harness plant: on the plant's domain, with its QoS profiles
// and network (so a test on a discovery-server or peers plant joins the way the services do),
// and on a plant NCQUAL_TEST_SECURITY secured as a rig (Plant::test_identity).
#pragma once

#include "harness.hpp"

#include "ncqual/common/config.hpp"
#include "ncqual/dds/participant.hpp"

#include <string>

namespace ncqual::testing {

// Call after the plant file is written (Plant::write_plant and friends).
inline dds::ParticipantOptions test_participant(const Plant& plant, std::string name = "test") {
  dds::ParticipantOptions o = dds::participant_options(load_plant_config(plant.plant_file()),
                                                       plant.domain(), std::move(name));
  if (const std::string id = plant.test_identity(); !id.empty()) o.security.identity = id;
  return o;
}

}  // namespace ncqual::testing
