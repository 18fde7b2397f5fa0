# SPDX-License-Identifier: MIT
#
# Out-of-tree plugin build, as a plugin author does it (ctest: abi_out_of_tree):
#   1. install the Talus build's package into a temporary prefix (cmake --install);
#   2. configure plugins/template as a project of its own against it, find_package(talus);
#   3. build it (warnings are errors);
#   4. run the host test program, which loads the resulting library through
#      PluginRegistry::load and uses it in a Model.
# The temporary directory is removed at the end, also when a step fails.
#
# cmake -DBUILD_DIR=<talus build> -DSOURCE_DIR=<talus source> -DHOST=<test_out_of_tree_host>
#       -DCXX_COMPILER=<compiler of the build> -DGENERATOR=<generator> -DWORK_DIR=<scratch parent>
#       [-DCONFIG=<config>] [-DKEEP=ON] -P out_of_tree.cmake
cmake_minimum_required(VERSION 3.16)

foreach(var BUILD_DIR SOURCE_DIR HOST CXX_COMPILER GENERATOR WORK_DIR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "out_of_tree.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT CONFIG)
  set(CONFIG Release)
endif()

string(TIMESTAMP t0 "%s")
string(RANDOM LENGTH 8 ALPHABET "abcdefghijklmnopqrstuvwxyz0123456789" suffix)
set(tmp "${WORK_DIR}/oot-${suffix}")
set(prefix "${tmp}/prefix")
set(plugin_build "${tmp}/build")
file(REMOVE_RECURSE "${tmp}")
file(MAKE_DIRECTORY "${tmp}")

# Runs one step; on failure prints its output, removes the scratch directory and stops.
function(oot_step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    if(NOT KEEP)
      file(REMOVE_RECURSE "${tmp}")
    endif()
    message(FATAL_ERROR "out-of-tree test: ${name} failed (${rc}):\n${out}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

# 1. The ABI headers and the CMake package (talusConfig.cmake, talusTargets.cmake,
#    TalusPlugin.cmake) into a prefix of its own. They are core/'s install rules, so only that
#    part of the build is installed: the rest (plugins, the CLI) need not be built for this test,
#    and a plugin that is not built yet cannot fail it.
set(install_from "${BUILD_DIR}/core")
if(NOT EXISTS "${install_from}/cmake_install.cmake")
  set(install_from "${BUILD_DIR}")
endif()
oot_step("install" "${CMAKE_COMMAND}" --install "${install_from}" --prefix "${prefix}"
         --config "${CONFIG}")
file(GLOB_RECURSE config_file "${prefix}/*/talusConfig.cmake")
if(NOT config_file)
  file(REMOVE_RECURSE "${tmp}")
  message(FATAL_ERROR "out-of-tree test: no talusConfig.cmake under ${prefix}")
endif()

# 2. The template as a separate project. The package must come from the prefix above: the user
#    package registry and the system prefixes are not searched.
oot_step("configure" "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/plugins/template" -B "${plugin_build}"
         -G "${GENERATOR}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}" "-DCMAKE_BUILD_TYPE=${CONFIG}"
         "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
         -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_CMAKE_SYSTEM_PATH=OFF
         -DCMAKE_CXX_FLAGS=-Werror)
file(STRINGS "${plugin_build}/CMakeCache.txt" found_dir REGEX "^talus_DIR:")
string(FIND "${found_dir}" "${prefix}" at)
if(at LESS 0)
  file(REMOVE_RECURSE "${tmp}")
  message(FATAL_ERROR "out-of-tree test: talus was found elsewhere (${found_dir})")
endif()

# 3. Build.
oot_step("build" "${CMAKE_COMMAND}" --build "${plugin_build}" --config "${CONFIG}")
file(GLOB_RECURSE plugin_file "${plugin_build}/libtalus_null.so")
if(NOT plugin_file)
  file(REMOVE_RECURSE "${tmp}")
  message(FATAL_ERROR "out-of-tree test: the build made no libtalus_null.so:\n${step_output}")
endif()
list(GET plugin_file 0 plugin_file)

# 4. Load and use it from a host linked against talus_core.
oot_step("host test" "${CMAKE_COMMAND}" -E env "TALUS_OOT_PLUGIN=${plugin_file}" "${HOST}")
message(STATUS "${step_output}")

if(NOT KEEP)
  file(REMOVE_RECURSE "${tmp}")
endif()
string(TIMESTAMP t1 "%s")
math(EXPR elapsed "${t1} - ${t0}")
message(STATUS "out-of-tree plugin build and load: passed in ${elapsed} s")
