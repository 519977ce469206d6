# ctest driver: install the library component of the build tree to a scratch prefix, then build
# the consumer with nothing but `pkg-config --cflags --libs mdbrief` and run it.
# Expects -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DCXX=... and optional -DCONSUMER_FLAGS=...
include(${CMAKE_CURRENT_LIST_DIR}/consumer_steps.cmake)
install_library_to_scratch_prefix()
file(GLOB_RECURSE pc_files ${WORK_DIR}/prefix/mdbrief.pc)
list(LENGTH pc_files count)
if(NOT count EQUAL 1)
  message(FATAL_ERROR "expected one installed mdbrief.pc, found: ${pc_files}")
endif()
get_filename_component(pc_dir ${pc_files} DIRECTORY)
set(ENV{PKG_CONFIG_PATH} ${pc_dir})
execute_process(COMMAND pkg-config --cflags --libs mdbrief OUTPUT_VARIABLE flags RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(rc)
  message(FATAL_ERROR "pkg-config --cflags --libs mdbrief failed (${rc})")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
separate_arguments(extra UNIX_COMMAND "${CONSUMER_FLAGS}")
execute_process(COMMAND ${CXX} -std=c++17 -O1 ${extra} ${SOURCE_DIR}/main.cpp -o ${WORK_DIR}/consumer ${flags}
                RESULT_VARIABLE rc)
if(rc)
  message(FATAL_ERROR "building the consumer with pkg-config's flags failed (${rc}): ${flags}")
endif()
# The README's examples load this path under the install prefix.
set(camera ${WORK_DIR}/prefix/share/mdbrief/cameras/lafida_fisheye0.yaml)
if(NOT EXISTS ${camera})
  message(FATAL_ERROR "the example cameras are not installed: no ${camera}")
endif()
run_step("the consumer" ${WORK_DIR}/consumer ${camera})
