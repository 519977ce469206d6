# mdbrief_export_include_folder(<target> [INTERFACE])
# Exports the current source folder to the targets that link <target> under its own name, so
# that "trainer/x.hpp" resolves for the trainer's users and nowhere else: the build tree gets
# include_roots/<name>/, holding only a symbolic link <name> -> the source folder, and that
# folder becomes <target>'s public (or, for an INTERFACE library, interface) include directory.
# (Exporting the repository root instead would let any target include any folder.)
function(mdbrief_export_include_folder target)
  get_filename_component(name "${CMAKE_CURRENT_SOURCE_DIR}" NAME)
  set(root "${PROJECT_BINARY_DIR}/include_roots/${name}")
  file(MAKE_DIRECTORY "${root}")
  file(CREATE_LINK "${CMAKE_CURRENT_SOURCE_DIR}" "${root}/${name}" SYMBOLIC)
  if(ARGV1 STREQUAL "INTERFACE")
    target_include_directories(${target} INTERFACE $<BUILD_INTERFACE:${root}>)
  else()
    target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${root}>)
  endif()
endfunction()
