# Steps shared by the consumer tests' ctest drivers (run_consumer_test.cmake,
# run_pkgconfig_test.cmake).

# Runs a command; a failure stops the test, naming the step.
function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(rc)
    message(FATAL_ERROR "${what} failed (${rc})")
  endif()
endfunction()

# A fresh WORK_DIR with the build tree's library component installed under WORK_DIR/prefix.
function(install_library_to_scratch_prefix)
  file(REMOVE_RECURSE ${WORK_DIR})
  execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --component library --prefix ${WORK_DIR}/prefix
                  RESULT_VARIABLE rc OUTPUT_QUIET)
  if(rc)
    message(FATAL_ERROR "install failed (${rc})")
  endif()
endfunction()
