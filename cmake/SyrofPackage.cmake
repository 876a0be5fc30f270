# What `cmake --install` puts where, SyROF's CMake package (in the build tree
# too, so a student's project builds against a build tree without
# installing), the pkg-config file, and the Debian package (`make package`).
#
# Installed layout (prefix /usr for the .deb):
#   bin/syrof                          the command
#   libexec/syrof/syrof-app-host       the sandboxed app host (FindHostBinary looks here)
#   lib/libsyrof_app.so.1              the app platform's C functions and the queries' C API
#   include/syrof/app.h, include/syrof/queries/queries.h   the app API
#   lib/cmake/SyROF/                   SyROFConfig.cmake (target SyROF::app, syrof_add_app)
#   lib/pkgconfig/syrof-app.pc
#
# The package config is written by hand rather than by install(EXPORT):
# libsyrof_app is built from SyROF's static libraries, whose targets an
# export would drag along; a student's app needs only the .so and two
# headers. lib/, not the multiarch folder: the app host finds the library
# through its RUNPATH ($ORIGIN/../../lib), and /usr/lib is on the loader's
# default path.
include(CMakePackageConfigHelpers)

set(syrof_package_in ${PROJECT_SOURCE_DIR}/cmake/package)
set(syrof_package_out ${PROJECT_BINARY_DIR}/package)

install(TARGETS syrof RUNTIME DESTINATION bin)
install(TARGETS syrof-robot RUNTIME DESTINATION bin)  # `syrof swarm` finds it beside syrof
install(TARGETS syrof-bridge RUNTIME DESTINATION bin)  # the base station (docs/bridge.md, docs/demo-day.md)
install(TARGETS syrof-firmware-config RUNTIME DESTINATION bin)  # a robot's inputs at flash time (docs/demo-day.md)
install(TARGETS syrof-app-host RUNTIME DESTINATION libexec/syrof)
install(TARGETS syrof_app_shared LIBRARY DESTINATION lib)
install(FILES ${PROJECT_SOURCE_DIR}/core/app/include/syrof/app.h DESTINATION include/syrof)
install(FILES ${PROJECT_SOURCE_DIR}/queries/include/syrof/queries/queries.h DESTINATION include/syrof/queries)

# The assignments as students get them (share/syrof/assignments/<name>/):
# assignment.yaml, the README, the public scenarios, the public search
# tests' scenarios (search/) and the starter. Not the
# hidden scenarios, the reference or the broken variants: the package is
# what students install. `syrof grade --assignment NAME` finds these and,
# the hidden files being absent, grades the public sets only
# (docs/grading.md); instructors grade from the source tree or a Gradescope
# bundle, which carry the hidden sets.
file(GLOB syrof_assignment_folders LIST_DIRECTORIES true ${PROJECT_SOURCE_DIR}/assignments/*)
foreach(folder IN LISTS syrof_assignment_folders)
  if(EXISTS ${folder}/assignment.yaml)
    get_filename_component(name ${folder} NAME)
    install(FILES ${folder}/assignment.yaml ${folder}/README.md DESTINATION share/syrof/assignments/${name})
    set(student_folders ${folder}/scenarios ${folder}/starter)
    if(EXISTS ${folder}/search)
      list(APPEND student_folders ${folder}/search)  # the public search tests' scenarios (hidden ones live in hidden/)
    endif()
    install(DIRECTORY ${student_folders} DESTINATION share/syrof/assignments/${name} PATTERN expected.yaml EXCLUDE)
  endif()
endforeach()

write_basic_package_version_file(${PROJECT_BINARY_DIR}/SyROFConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)

# The installed config finds everything relative to itself, so the package
# works under any prefix.
set(SYROF_PACKAGE_PREFIX_CODE
    "get_filename_component(_syrof_prefix \"\${CMAKE_CURRENT_LIST_DIR}/../../..\" ABSOLUTE)")
set(SYROF_PACKAGE_LIBRARY "\${_syrof_prefix}/lib/libsyrof_app.so.1")
set(SYROF_PACKAGE_INCLUDE_DIRS "\${_syrof_prefix}/include")
set(SYROF_PACKAGE_EXECUTABLE "\${_syrof_prefix}/bin/syrof")
configure_file(${syrof_package_in}/SyROFConfig.cmake.in ${syrof_package_out}/SyROFConfig.cmake @ONLY)
install(FILES ${syrof_package_out}/SyROFConfig.cmake ${PROJECT_BINARY_DIR}/SyROFConfigVersion.cmake
              ${syrof_package_in}/SyROFAddApp.cmake
        DESTINATION lib/cmake/SyROF)
configure_file(${syrof_package_in}/syrof-app.pc.in ${syrof_package_out}/syrof-app.pc @ONLY)
install(FILES ${syrof_package_out}/syrof-app.pc DESTINATION lib/pkgconfig)

# The build tree's config: the headers from the source tree, the library
# and the command from the build tree. Written twice from one input:
# build/lib/cmake/SyROF/, where find_package looks beneath the parent of
# every PATH entry ending in /bin, so a student with build/bin on PATH (as
# `syrof` itself needs) finds SyROF with no hint, as with the installed
# package; and build/, which `syrof new` run from build/bin names in the
# project it writes (and older projects name).
set(SYROF_PACKAGE_PREFIX_CODE "")
set(SYROF_PACKAGE_LIBRARY "$<TARGET_SONAME_FILE:syrof_app_shared>")
set(SYROF_PACKAGE_INCLUDE_DIRS "${PROJECT_SOURCE_DIR}/core/app/include;${PROJECT_SOURCE_DIR}/queries/include")
set(SYROF_PACKAGE_EXECUTABLE "$<TARGET_FILE:syrof>")
configure_file(${syrof_package_in}/SyROFConfig.cmake.in ${syrof_package_out}/SyROFConfig.build.cmake.in @ONLY)
foreach(folder ${PROJECT_BINARY_DIR} ${PROJECT_BINARY_DIR}/lib/cmake/SyROF)
  file(GENERATE OUTPUT ${folder}/SyROFConfig.cmake INPUT ${syrof_package_out}/SyROFConfig.build.cmake.in)
  configure_file(${syrof_package_in}/SyROFAddApp.cmake ${folder}/SyROFAddApp.cmake COPYONLY)
endforeach()
configure_file(${PROJECT_BINARY_DIR}/SyROFConfigVersion.cmake ${PROJECT_BINARY_DIR}/lib/cmake/SyROF/SyROFConfigVersion.cmake
               COPYONLY)

# `make package`: a Debian package. dpkg-shlibdeps (dpkg-dev) works out the
# shared libraries' packages for Depends; cmake and a compiler are what a
# student needs to build an app, so they are recommended.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME syrof)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "SyROF: a teaching lab for robot swarms (simulator, app host, app API)")
set(CPACK_PACKAGE_DESCRIPTION
    "Run robot apps written in C or C++ on a simulated swarm with synchronized rounds, membership and common \
knowledge; each robot's app in its own sandboxed process. Includes the syrof command, the app API's headers, \
libsyrof_app, a CMake package and a pkg-config file.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "SyROF maintainers <syrof@localhost>")
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${PROJECT_BINARY_DIR}/lib)
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "cmake (>= 3.16), gcc, g++, pkg-config")
set(CPACK_OUTPUT_FILE_PREFIX ${PROJECT_BINARY_DIR})
# Debug information stays in the build tree: the package is for running.
set(CPACK_STRIP_FILES ON)
include(CPack)
