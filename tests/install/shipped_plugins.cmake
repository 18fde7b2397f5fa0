# SPDX-License-Identifier: MIT
#
# The shipped plugin directory holds the shipped models only (ctest: install.shipped_plugins):
#   1. build/plugins holds exactly one library per folder of plugins/ except the template;
#   2. no plugin built for the tests (anywhere else in the build) has a shipped model's name;
#   3. build/talus, with TALUS_PLUGIN_PATH unset, offers a user exactly the shipped models when
#      a script names an unknown one.
#
# cmake -DBUILD_DIR=<talus build> -DSOURCE_DIR=<talus source> -DTALUS=<talus> -P shipped_plugins.cmake
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/install_support.cmake)
talus_require_args(shipped_plugins.cmake BUILD_DIR SOURCE_DIR TALUS)

talus_shipped_models(shipped "${SOURCE_DIR}")
file(GLOB built_files "${BUILD_DIR}/plugins/libtalus_*.so")
talus_plugin_stems(built ${built_files})
if(NOT built STREQUAL shipped)
  message(FATAL_ERROR "build/plugins holds ${built}; the shipped models are ${shipped}")
endif()

talus_test_plugins(test_plugins "${BUILD_DIR}")
if(NOT "null" IN_LIST test_plugins OR NOT "liar" IN_LIST test_plugins)
  message(FATAL_ERROR "the test plugins null and liar were not found in ${BUILD_DIR} "
                      "(found: ${test_plugins})")
endif()
foreach(t ${test_plugins})
  if(t IN_LIST shipped)
    message(FATAL_ERROR "a test plugin is named like the shipped model '${t}'")
  endif()
endforeach()

# What a user sees: the unknown-model message of the build tree's talus.
string(RANDOM LENGTH 8 ALPHABET "abcdefghijklmnopqrstuvwxyz" suffix)
set(script "${CMAKE_CURRENT_BINARY_DIR}/unknown_model_${suffix}.lua")
file(WRITE "${script}" "talus.model{}:contact_model('zz_not_a_model', {})\n")
execute_process(COMMAND "${CMAKE_COMMAND}" -E env --unset=TALUS_PLUGIN_PATH "${TALUS}" run "${script}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
file(REMOVE "${script}")
string(REGEX MATCH "models that can be loaded: ([^;)]*)" offered "${out}")
string(REPLACE ", " ";" offered "${CMAKE_MATCH_1}")
if(rc EQUAL 0 OR NOT offered STREQUAL shipped)
  message(FATAL_ERROR "talus offers the models '${offered}'; the shipped ones are '${shipped}' "
                      "(exit ${rc}):\n${out}")
endif()
list(LENGTH shipped n)
list(LENGTH test_plugins nt)
message(STATUS "shipped plugin directory: ${n} models (${shipped}); ${nt} test plugins kept out")
