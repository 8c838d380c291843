#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# The wrist of ncqual's LinuxCNC test machine, a userspace HAL component (probe.hal loads it): from
# the A, C and W positions it gives the offset of the true stylus ball centre from the axes' X, Y,
# Z (the wrist pivot), as ncqual's kinematics define it (ncqual/common/kinematics.hpp), written
# here again on its own:
#   offset = Rz(c + dc) Rx(a + da) (ox, oy, -(L + w))
# with the true probe's stylus offset (ox, oy) and length L and the wrist's angle errors da, dc
# (radians), given on the command line in that order. The probing moves happen with A, C and W
# standing still, so the offset the real-time comparators read is exact while they look; it is
# refreshed every millisecond.
import math
import signal
import sys
import time

import hal

ox, oy, length, da, dc = (float(v) for v in sys.argv[1:6])

component = hal.component("ncqual-wrist")
for pin in ("a-deg", "c-deg", "w-mm"):
    component.newpin(pin, hal.HAL_FLOAT, hal.HAL_IN)
for pin in ("off-x", "off-y", "off-z"):
    component.newpin(pin, hal.HAL_FLOAT, hal.HAL_OUT)
component.ready()
signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))

try:
    while True:
        a = math.radians(component["a-deg"]) + da
        c = math.radians(component["c-deg"]) + dc
        z = -(length + component["w-mm"])
        # Rx(a): about X; then Rz(c): about Z.
        y1 = oy * math.cos(a) - z * math.sin(a)
        z1 = oy * math.sin(a) + z * math.cos(a)
        component["off-x"] = ox * math.cos(c) - y1 * math.sin(c)
        component["off-y"] = ox * math.sin(c) + y1 * math.cos(c)
        component["off-z"] = z1
        time.sleep(0.001)
except KeyboardInterrupt:
    pass
