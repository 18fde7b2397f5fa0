# SPDX-License-Identifier: MIT
# Helpers of the install tests (included by relocated.cmake, shipped_plugins.cmake and
# deb_contents.cmake).

# talus_require_args(<script> <VAR>...): every -D<VAR>=... given, else a usage error. Also
# defaults CONFIG to Release and makes BUILD_DIR and SOURCE_DIR real paths when given.
macro(talus_require_args script)
  foreach(var ${ARGN})
    if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
      message(FATAL_ERROR "${script}: -D${var}=... is required")
    endif()
  endforeach()
  if(NOT CONFIG)
    set(CONFIG Release)
  endif()
  foreach(var BUILD_DIR SOURCE_DIR)
    if(DEFINED ${var})
      file(REAL_PATH "${${var}}" ${var})
    endif()
  endforeach()
endmacro()

# talus_missing(<var> <list variable> <item>...): the items not in the list, in order.
function(talus_missing var list)
  set(out)
  foreach(item ${ARGN})
    if(NOT item IN_LIST ${list})
      list(APPEND out "${item}")
    endif()
  endforeach()
  set(${var} ${out} PARENT_SCOPE)
endfunction()

# talus_scratch(<var> <name>): a new empty directory outside the source and build trees (under
# TMPDIR or /tmp), so that a path inside it can never be mistaken for one of theirs.
function(talus_scratch var name)
  set(base "$ENV{TMPDIR}")
  if(NOT base)
    set(base /tmp)
  endif()
  string(RANDOM LENGTH 8 ALPHABET "abcdefghijklmnopqrstuvwxyz0123456789" suffix)
  file(REAL_PATH "${base}" base)
  set(dir "${base}/talus-${name}-${suffix}")
  file(REMOVE_RECURSE "${dir}")
  file(MAKE_DIRECTORY "${dir}")
  set(${var} "${dir}" PARENT_SCOPE)
endfunction()

# talus_run(<scratch> <what> <command...>): runs a command; on failure prints its output, removes
# the scratch directory (unless -DKEEP=ON) and fails the test. Sets run_output.
function(talus_run scratch what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    if(NOT KEEP)
      file(REMOVE_RECURSE "${scratch}")
    endif()
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

# talus_fail(<scratch> <message>): removes the scratch directory and fails the test.
function(talus_fail scratch msg)
  if(NOT KEEP)
    file(REMOVE_RECURSE "${scratch}")
  endif()
  message(FATAL_ERROR "${msg}")
endfunction()

# talus_shipped_models(<var> <source dir>): the models Talus ships, one per folder of plugins/
# (plugins/CMakeLists.txt), except the template, which is a starting point for a model of one's
# own and is built for tests only. Sorted.
function(talus_shipped_models var source_dir)
  file(GLOB dirs LIST_DIRECTORIES true RELATIVE "${source_dir}/plugins" "${source_dir}/plugins/*")
  set(models)
  foreach(d ${dirs})
    if(EXISTS "${source_dir}/plugins/${d}/CMakeLists.txt" AND NOT d STREQUAL "template")
      list(APPEND models ${d})
    endif()
  endforeach()
  list(SORT models)
  set(${var} ${models} PARENT_SCOPE)
endfunction()

# talus_plugin_stems(<var> <files...>): libtalus_<stem>.so -> <stem>, sorted.
function(talus_plugin_stems var)
  set(stems)
  foreach(f ${ARGN})
    get_filename_component(n "${f}" NAME)
    string(REGEX REPLACE "^libtalus_(.*)\\.so$" "\\1" n "${n}")
    list(APPEND stems ${n})
  endforeach()
  list(SORT stems)
  set(${var} ${stems} PARENT_SCOPE)
endfunction()

# talus_test_plugins(<var> <build dir>): the stems of every plugin library built outside the
# shipped plugin directory (the template's null, liar, the ABI tests' libraries, ...).
function(talus_test_plugins var build_dir)
  file(GLOB_RECURSE all "${build_dir}/libtalus_*.so")
  set(tests)
  foreach(f ${all})
    string(FIND "${f}" "${build_dir}/plugins/" at)
    if(NOT at EQUAL 0 AND NOT f MATCHES "/_CPack_Packages/")
      list(APPEND tests "${f}")
    endif()
  endforeach()
  talus_plugin_stems(stems ${tests})
  list(REMOVE_DUPLICATES stems)
  set(${var} ${stems} PARENT_SCOPE)
endfunction()
