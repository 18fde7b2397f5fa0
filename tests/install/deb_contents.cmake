# SPDX-License-Identifier: MIT
#
# The Debian package (ctest: install.deb_contents):
#   1. build it from the build tree (cpack -G DEB, into a scratch directory);
#   2. list it (dpkg-deb -c) and check that it holds /usr/bin/talus, exactly the shipped models
#      in the plugin directory, every Lua library module, every example, the plotting tools,
#      the plugin SDK (contact_model.hpp, the sdk/ headers, talusConfig.cmake and its
#      companions), the documentation pages and the copyright file;
#   3. check that it holds no test plugin, no test header and nothing of the build or test trees;
#   4. check its Depends: the package of every shared library the binaries need themselves
#      (readelf's NEEDED, located with ldd, owned per dpkg -S), among them liblua5.4-0 and
#      libbox2d2 on Debian 12.
# cpack runs the build's preinstall step first (a make that finds everything up to date after
# a build), then installs into its staging directory, strips and calls dpkg-shlibdeps.
#
# cmake -DBUILD_DIR=<talus build> -DSOURCE_DIR=<talus source> -DLIBDIR=<CMAKE_INSTALL_LIBDIR>
#       [-DCONFIG=<config>] [-DKEEP=ON] -P deb_contents.cmake
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/install_support.cmake)
talus_require_args(deb_contents.cmake BUILD_DIR SOURCE_DIR LIBDIR)
get_filename_component(cmake_dir "${CMAKE_COMMAND}" DIRECTORY)
find_program(CPACK cpack HINTS "${cmake_dir}" REQUIRED)
find_program(DPKG_DEB dpkg-deb REQUIRED)

# 1. The package.
talus_scratch(tmp deb)
talus_run("${tmp}" "cpack -G DEB" "${CPACK}" -G DEB -C "${CONFIG}" --config
          "${BUILD_DIR}/CPackConfig.cmake" -B "${tmp}")
file(GLOB debs "${tmp}/talus_*.deb")
list(LENGTH debs n)
if(NOT n EQUAL 1)
  talus_fail("${tmp}" "cpack made ${n} packages named talus_*.deb in ${tmp}:\n${run_output}")
endif()

# 2. Its files, as paths without the leading "." (/usr/bin/talus).
talus_run("${tmp}" "dpkg-deb -c" "${DPKG_DEB}" -c "${debs}")
string(REGEX REPLACE "\n$" "" listing "${run_output}")
string(REPLACE "\n" ";" lines "${listing}")
set(files)
foreach(line ${lines})
  string(REGEX MATCH " \\./([^ ]*[^/])( -> .*)?$" _ "${line}")
  if(CMAKE_MATCH_1)
    list(APPEND files "/${CMAKE_MATCH_1}")
  endif()
endforeach()

set(expected /usr/bin/talus /usr/include/talus/contact_model.hpp
    /usr/${LIBDIR}/cmake/talus/talusConfig.cmake
    /usr/${LIBDIR}/cmake/talus/talusConfigVersion.cmake
    /usr/${LIBDIR}/cmake/talus/talusTargets.cmake /usr/${LIBDIR}/cmake/talus/TalusPlugin.cmake
    /usr/share/doc/talus/copyright /usr/share/doc/talus/README.md
    /usr/share/talus/scripts/plot_history.py /usr/share/talus/scripts/plot_rockfall.py
    /usr/share/talus/scripts/plot_calibration.py
    /usr/share/talus/plugin-template/CMakeLists.txt /usr/share/talus/plugin-template/null_model.cpp
    /usr/share/talus/plugin-template/README.md)
talus_shipped_models(shipped "${SOURCE_DIR}")
foreach(m ${shipped})
  list(APPEND expected "/usr/${LIBDIR}/talus/plugins/libtalus_${m}.so")
endforeach()
file(GLOB sdk RELATIVE "${SOURCE_DIR}/core/include" "${SOURCE_DIR}/core/include/talus/sdk/*.hpp")
file(GLOB_RECURSE lua RELATIVE "${SOURCE_DIR}/scripts" "${SOURCE_DIR}/scripts/lib/*.lua")
file(GLOB examples RELATIVE "${SOURCE_DIR}/scripts" "${SOURCE_DIR}/scripts/examples/*.lua")
file(GLOB_RECURSE docs RELATIVE "${SOURCE_DIR}/docs" "${SOURCE_DIR}/docs/*.md")
foreach(f ${sdk})
  list(APPEND expected "/usr/include/${f}")
endforeach()
foreach(f ${lua} ${examples})
  list(APPEND expected "/usr/share/talus/scripts/${f}")
endforeach()
foreach(f ${docs})
  list(APPEND expected "/usr/share/doc/talus/${f}")
endforeach()
talus_missing(missing files ${expected})
if(missing)
  string(REPLACE ";" "\n  " missing "${missing}")
  talus_fail("${tmp}" "the package lacks:\n  ${missing}\nIt holds:\n${listing}")
endif()

# The plugin directory: the shipped models, nothing else.
set(plugins)
foreach(f ${files})
  if(f MATCHES "^/usr/${LIBDIR}/talus/plugins/")
    list(APPEND plugins "${f}")
  endif()
endforeach()
talus_plugin_stems(packaged ${plugins})
if(NOT packaged STREQUAL shipped)
  talus_fail("${tmp}" "the package's plugin directory holds ${packaged}; shipped: ${shipped}")
endif()

# 3. Nothing of the tests: no test plugin anywhere, no header of tests/, no Catch2, no file of
#    the build or the test trees.
talus_test_plugins(test_plugins "${BUILD_DIR}")
file(GLOB_RECURSE test_headers RELATIVE "${SOURCE_DIR}" "${SOURCE_DIR}/tests/*.hpp"
     "${SOURCE_DIR}/tests/*.h")
set(test_header_names)
foreach(h ${test_headers})
  get_filename_component(name "${h}" NAME)
  list(APPEND test_header_names "${name}")
endforeach()
set(stray)
foreach(f ${files})
  get_filename_component(name "${f}" NAME)
  string(REGEX REPLACE "^libtalus_(.*)\\.so$" "\\1" stem "${name}")
  if((name MATCHES "^libtalus_.*\\.so$" AND stem IN_LIST test_plugins)
     OR (name MATCHES "\\.h(pp)?$" AND (name IN_LIST test_header_names OR f MATCHES "catch"))
     OR f MATCHES "/(tests?|test_plugins|CMakeFiles|_CPack_Packages)/")
    list(APPEND stray "${f}")
  endif()
endforeach()
if(stray)
  string(REPLACE ";" "\n  " stray "${stray}")
  talus_fail("${tmp}" "the package holds files of the tests:\n  ${stray}")
endif()

# 4. Depends: the package of every shared library that talus and the plugins need.
talus_run("${tmp}" "dpkg-deb -f" "${DPKG_DEB}" -f "${debs}" Depends)
string(STRIP "${run_output}" depends)
set(needed_packages)
set(resolved_sonames)
foreach(binary "${BUILD_DIR}/talus" ${plugins})
  if(binary MATCHES "^/usr/")
    string(REGEX REPLACE "^/usr/${LIBDIR}/talus/plugins/" "${BUILD_DIR}/plugins/" binary "${binary}")
  endif()
  # The libraries it needs itself (NEEDED), found where the loader finds them (ldd).
  talus_run("${tmp}" "readelf -d ${binary}" readelf -d "${binary}")
  string(REGEX MATCHALL "\\(NEEDED\\)[^[]*\\[[^]]+\\]" needed "${run_output}")
  talus_run("${tmp}" "ldd ${binary}" ldd "${binary}")
  set(ldd_output "${run_output}")
  foreach(n ${needed})
    string(REGEX REPLACE ".*\\[([^]]+)\\]$" "\\1" soname "${n}")
    if(soname IN_LIST resolved_sonames)
      continue()  # every plugin needs the same few libraries: ask dpkg once
    endif()
    list(APPEND resolved_sonames "${soname}")
    # "libx.so.1 => /lib/.../libx.so.1 (0x...)", or the loader's own "/lib64/ld-linux...".
    string(FIND "${ldd_output}" "${soname} => " at)
    string(FIND "${ldd_output}" "/${soname} (" loader_at)
    if(at GREATER_EQUAL 0)
      string(SUBSTRING "${ldd_output}" ${at} -1 rest)
      string(REGEX MATCH "=> (/[^ \n]+)" _ "${rest}")
      set(l "${CMAKE_MATCH_1}")
    elseif(loader_at GREATER_EQUAL 0)
      string(SUBSTRING "${ldd_output}" 0 ${loader_at} before)
      string(REGEX MATCH "[ \t]([^ \t\n]*)$" _ "${before}")
      set(l "${CMAKE_MATCH_1}/${soname}")
    else()
      talus_fail("${tmp}" "ldd does not resolve ${soname}, which ${binary} needs:\n${ldd_output}")
    endif()
    file(REAL_PATH "${l}" real)
    # dpkg may know the file by its link name or its real name, under /lib or /usr/lib.
    set(owner)
    foreach(candidate "${l}" "${real}")
      string(REGEX REPLACE "^/lib" "/usr/lib" usr_candidate "${candidate}")
      foreach(p "${candidate}" "${usr_candidate}")
        if(NOT owner)
          execute_process(COMMAND dpkg -S "${p}" RESULT_VARIABLE rc OUTPUT_VARIABLE o ERROR_QUIET)
          if(rc EQUAL 0)
            string(REGEX REPLACE "[:,].*" "" owner "${o}")
          endif()
        endif()
      endforeach()
    endforeach()
    if(NOT owner)
      talus_fail("${tmp}" "no Debian package holds ${l} (${soname}, needed by ${binary})")
    endif()
    list(APPEND needed_packages "${owner}")
  endforeach()
endforeach()
list(REMOVE_DUPLICATES needed_packages)
# The look-up above must have worked (else the check below passes on nothing): Lua and Box2D
# are linked dynamically on Debian 12.
foreach(required liblua5.4-0 libbox2d2)
  if(NOT required IN_LIST needed_packages)
    talus_fail("${tmp}" "talus does not seem to link ${required}'s library; needs: ${needed_packages}")
  endif()
endforeach()
# "libc6 (>= 2.34), liblua5.4-0 (>= 5.4.0), ..." -> the package names (alternatives included).
string(REGEX REPLACE " *\\([^)]*\\)" "" depends_names "${depends}")
string(REGEX REPLACE " *[,|] *" ";" depends_names "${depends_names}")
talus_missing(undeclared depends_names ${needed_packages})
if(undeclared)
  talus_fail("${tmp}" "Depends (${depends}) lacks ${undeclared}")
endif()

list(LENGTH files nf)
file(SIZE "${debs}" bytes)
message(STATUS "${debs}: ${nf} files, ${bytes} bytes; Depends: ${depends}")
if(NOT KEEP)
  file(REMOVE_RECURSE "${tmp}")
endif()
