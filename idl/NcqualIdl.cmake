# SPDX-License-Identifier: Apache-2.0
# ncqual_idl_generate(TARGET <name> FILES <a.idl> ...)
#
# Turns IDL files into a static library target whose sources fastddsgen writes into the build
# tree at build time (never into the source tree, never committed), the way Cyclone DDS's
# idlc_generate does. Consumers link <name> and include "<file>.h" / "<file>PubSubTypes.h", and
# call register<file>Types() from "<file>TypeObject.h" once before creating topics.
find_program(FASTDDSGEN_EXECUTABLE fastddsgen REQUIRED)

function(ncqual_idl_generate)
  cmake_parse_arguments(ARG "" "TARGET" "FILES" ${ARGN})
  if(NOT ARG_TARGET OR NOT ARG_FILES)
    message(FATAL_ERROR "ncqual_idl_generate: TARGET and FILES are required")
  endif()
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/${ARG_TARGET}_gen)
  file(MAKE_DIRECTORY ${out_dir})
  set(sources "")
  foreach(idl ${ARG_FILES})
    get_filename_component(idl_abs ${idl} ABSOLUTE)
    get_filename_component(idl_dir ${idl_abs} DIRECTORY)
    get_filename_component(stem ${idl_abs} NAME_WE)
    # -typeobject: TypeObjects let Fast DDS evaluate content filters (per-machine readers) and
    # let other DDS implementations discover our types (plant integration). The generated
    # constructors' own registration calls are taken out (strip_registration.cmake: they made a
    # large measurement set cost minutes to convert).
    set(generated
      ${out_dir}/${stem}.h ${out_dir}/${stem}.cxx
      ${out_dir}/${stem}PubSubTypes.h ${out_dir}/${stem}PubSubTypes.cxx
      ${out_dir}/${stem}TypeObject.h ${out_dir}/${stem}TypeObject.cxx)
    add_custom_command(
      OUTPUT ${generated}
      COMMAND ${FASTDDSGEN_EXECUTABLE} -typeobject -replace -d ${out_dir} -I ${idl_dir} ${idl_abs}
      COMMAND ${CMAKE_COMMAND} -DFILE=${out_dir}/${stem}.cxx -DSTEM=${stem}
              -P ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/strip_registration.cmake
      DEPENDS ${idl_abs} ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/strip_registration.cmake
      COMMENT "fastddsgen ${stem}.idl"
      VERBATIM)
    list(APPEND sources ${out_dir}/${stem}.cxx ${out_dir}/${stem}PubSubTypes.cxx
      ${out_dir}/${stem}TypeObject.cxx)
  endforeach()
  add_library(${ARG_TARGET} STATIC ${sources})
  # Generated code is not ours to warn about.
  target_compile_options(${ARG_TARGET} PRIVATE -w)
  target_include_directories(${ARG_TARGET} PUBLIC ${out_dir})
  target_link_libraries(${ARG_TARGET} PUBLIC fastcdr fastrtps)
  set_target_properties(${ARG_TARGET} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()
