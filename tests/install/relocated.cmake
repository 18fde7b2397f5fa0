# SPDX-License-Identifier: MIT
#
# An installed Talus moves (ctest: install.relocated):
#   1. install the build into a temporary prefix (cmake --install, as getting-started says);
#   2. move that prefix elsewhere, so that the directory it was installed to is gone, and check
#      that no installed binary holds a path of the source or build tree;
#   3. run the moved bin/talus, with TALUS_PLUGIN_PATH and TALUS_LUA_PATH unset, on
#      installed.lua, which requires every installed Lua library module (found by listing the
#      installed lib directory) and checks it comes from the moved tree, runs a ball at rest on
#      a wall with the shipped `linear` model loaded from the moved tree, and checks that the
#      models it offers are the shipped ones.
# The scratch directory is removed at the end, also when a step fails (-DKEEP=ON keeps it).
#
# cmake -DBUILD_DIR=<talus build> -DSOURCE_DIR=<talus source> [-DCONFIG=<config>]
#       -P relocated.cmake
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/install_support.cmake)
talus_require_args(relocated.cmake BUILD_DIR SOURCE_DIR)

talus_scratch(tmp relocated)
talus_run("${tmp}" "cmake --install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}"
          --prefix "${tmp}/installed" --config "${CONFIG}")
set(prefix "${tmp}/moved/talus")
file(MAKE_DIRECTORY "${tmp}/moved")
file(RENAME "${tmp}/installed" "${prefix}")
if(EXISTS "${tmp}/installed" OR NOT EXISTS "${prefix}/bin/talus")
  talus_fail("${tmp}" "the install did not move to ${prefix}")
endif()

# No installed binary holds a path of the trees it was built from (a path fixed at configure
# time would be searched, or loaded from, wherever the install goes).
file(GLOB_RECURSE binaries "${prefix}/bin/*" "${prefix}/*.so")
foreach(b ${binaries})
  foreach(tree "${SOURCE_DIR}" "${BUILD_DIR}")
    string(REGEX REPLACE "([][+.*()^$?|\\])" "\\\\\\1" tree_re "${tree}")
    file(STRINGS "${b}" hits REGEX "${tree_re}")
    if(hits)
      talus_fail("${tmp}" "${b} holds the path ${tree}: ${hits}")
    endif()
  endforeach()
endforeach()

# Every installed library module: lib/a.lua -> a, lib/a/init.lua -> a, lib/a/b.lua -> a.b.
# An editor's definition file (LuaLS, first line "---@meta") is not a module: it is not loaded.
set(libdir "${prefix}/share/talus/scripts/lib")
file(GLOB_RECURSE lua_files RELATIVE "${libdir}" "${libdir}/*.lua")
set(modules)
foreach(f ${lua_files})
  file(STRINGS "${libdir}/${f}" first LIMIT_COUNT 1)
  if(first MATCHES "^---@meta")
    continue()
  endif()
  string(REGEX REPLACE "\\.lua$" "" m "${f}")
  string(REGEX REPLACE "/init$" "" m "${m}")
  string(REPLACE "/" "." m "${m}")
  list(APPEND modules ${m})
endforeach()
list(SORT modules)

# The shipped models, as the installed plugin directory must hold them.
talus_shipped_models(shipped "${SOURCE_DIR}")
file(GLOB_RECURSE installed_plugins "${prefix}/libtalus_*.so")
talus_plugin_stems(installed "${installed_plugins}")
if(NOT installed STREQUAL shipped)
  talus_fail("${tmp}" "installed plugins: ${installed}; shipped models (the folders of "
                     "plugins/ but the template): ${shipped}. A model in plugins/ is offered by "
                     "build/talus and must be installed as plugins/linear/CMakeLists.txt does.")
endif()
string(REPLACE ";" ", " shipped_text "${shipped}")

# The script runs from the scratch directory (its own directory is first on package.path).
file(COPY "${CMAKE_CURRENT_LIST_DIR}/installed.lua" DESTINATION "${tmp}")
talus_run("${tmp}" "the moved talus"
          "${CMAKE_COMMAND}" -E env --unset=TALUS_PLUGIN_PATH --unset=TALUS_LUA_PATH
          "${prefix}/bin/talus" run "${tmp}/installed.lua" "${prefix}" "${SOURCE_DIR}"
          "${BUILD_DIR}" "${shipped_text}" ${modules})
message(STATUS "${run_output}")
if(NOT KEEP)
  file(REMOVE_RECURSE "${tmp}")
endif()
