# SPDX-License-Identifier: Apache-2.0
# cmake -DFILE=<stem>.cxx -DSTEM=<stem> -P strip_registration.cmake
#
# fastddsgen 2.x (Debian 12) makes every generated constructor call register<stem>Types(), which
# adds all TypeObjects to the factory again, with no once-flag: about 0.1 ms per constructed
# struct, so converting a measurement set of 1,000,000 tracker points took minutes. The calls are
# taken out of the generated source here; ncqual::dds::Participant registers the types once,
# before any topic exists (dds/src/participant.cpp).
file(READ ${FILE} text)
string(REPLACE "    // Just to register all known types\n    register${STEM}Types();\n"
               "    // (types registered once by ncqual::dds::Participant: idl/strip_registration.cmake)\n"
               stripped "${text}")
if(stripped STREQUAL text)
  message(FATAL_ERROR "strip_registration: no register${STEM}Types() call found in ${FILE}: "
                      "has fastddsgen's output changed?")
endif()
file(WRITE ${FILE} "${stripped}")
