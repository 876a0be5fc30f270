# docs/architecture.md names a file for every step it describes; this checks
# that each path it quotes (`core/...`, `lab/...`, `cmake/...`, ...) exists,
# so the page cannot drift from the tree unnoticed.
#
#   cmake -DSYROF_SOURCE_DIR=<repo> -P tests/architecture/docs_paths_test.cmake
cmake_minimum_required(VERSION 3.25)

file(READ ${SYROF_SOURCE_DIR}/docs/architecture.md text)
string(REGEX MATCHALL "`(core|queries|lab|cli|cmake|tests|firmware|sim_dds|grader|docs)/[^` ]+`" quoted "${text}")
list(REMOVE_DUPLICATES quoted)
set(missing "")
set(count 0)
foreach(item IN LISTS quoted)
  string(REGEX REPLACE "^`|`$" "" path "${item}")
  # A path may end in "/" (a folder) or name a file.
  if(NOT EXISTS ${SYROF_SOURCE_DIR}/${path})
    list(APPEND missing ${path})
  endif()
  math(EXPR count "${count} + 1")
endforeach()
if(count LESS 10)
  message(FATAL_ERROR "docs/architecture.md quotes only ${count} paths: is the page there?")
endif()
if(missing)
  string(REPLACE ";" "\n  " listed "${missing}")
  message(FATAL_ERROR "docs/architecture.md names paths that do not exist:\n  ${listed}")
endif()
message("docs/architecture.md: all ${count} quoted paths exist")
