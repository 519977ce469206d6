# ctest driver: install the library component of the build tree to a scratch prefix, build the consumer against it, run it.
# Expects -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... and optional -DCONSUMER_FLAGS=...
include(${CMAKE_CURRENT_LIST_DIR}/consumer_steps.cmake)
install_library_to_scratch_prefix()
run_step("configuring the consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build -DCMAKE_BUILD_TYPE=Release
         -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
         "-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_FLAGS}")
run_step("building the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run_step("the consumer" ${WORK_DIR}/build/consumer)
