# SPDX-License-Identifier: MIT
# talus_add_plugin(<model> SOURCES <files...>)
# Builds libtalus_<model>.so, the file name `find` looks for when a script names the model.
# Works in the Talus tree and, through find_package(talus), out of it.
function(talus_add_plugin model)
  cmake_parse_arguments(ARG "" "OUTPUT_DIRECTORY" "SOURCES" ${ARGN})
  set(target talus_${model})
  add_library(${target} MODULE ${ARG_SOURCES})
  if(TARGET talus::plugin)
    target_link_libraries(${target} PRIVATE talus::plugin)
  else()
    target_link_libraries(${target} PRIVATE talus_plugin_abi)
  endif()
  if(TARGET talus_warnings)
    target_link_libraries(${target} PRIVATE talus_warnings)
  endif()
  set_target_properties(${target} PROPERTIES PREFIX "lib" OUTPUT_NAME talus_${model}
                        CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  if(ARG_OUTPUT_DIRECTORY)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${ARG_OUTPUT_DIRECTORY})
  elseif(DEFINED TALUS_PLUGIN_OUTPUT_DIR)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${TALUS_PLUGIN_OUTPUT_DIR})
  endif()
endfunction()
