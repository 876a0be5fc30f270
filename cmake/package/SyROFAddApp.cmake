# syrof_add_app(NAME SOURCE...): a SyROF app as the shared library
# lib<NAME>.so in the project's build folder, built against SyROF::app
# (every include folder of syrof/app.h, and libsyrof_app). Part of SyROF's
# CMake package (SyROFConfig.cmake includes it).
function(syrof_add_app name)
  if(NOT ARGN)
    message(FATAL_ERROR "syrof_add_app(${name}): name the app's source files, e.g. syrof_add_app(${name} app.c)")
  endif()
  add_library(${name} SHARED ${ARGN})
  target_link_libraries(${name} PRIVATE SyROF::app m)
  # C11 and C++20 at least; warnings a student should see.
  set_target_properties(${name} PROPERTIES C_STANDARD 11 CXX_STANDARD 20 CXX_STANDARD_REQUIRED ON)
  target_compile_options(${name} PRIVATE -Wall -Wextra)
endfunction()
