// SPDX-License-Identifier: Apache-2.0
// The plants the scheduler's unit tests run on.
#pragma once

#include "ncqual/common/config.hpp"

namespace ncqual::scheduler::test_support {

// A plant of one machine, "m1", on the wall clock, with no calendar.
inline PlantConfig one_machine() {
  PlantConfig p;
  p.plant = "t";
  p.machines.resize(1);
  p.machines[0].machine_id = "m1";
  return p;
}

// The plant with its scheduler's state file at /var/lib/ncqual/scheduler.db.
inline PlantConfig with_state_database(PlantConfig p) {
  p.scheduler_state_database = "/var/lib/ncqual/scheduler.db";
  return p;
}

}  // namespace ncqual::scheduler::test_support
