# SPDX-License-Identifier: MIT
# The Debian package: `cpack -G DEB` in a build tree gives talus_<version>_<arch>.deb
# (docs/getting-started.md, "The Debian package"). It holds what `cmake --install` installs,
# under /usr: bin/talus; the shipped contact models in lib/talus/plugins; the Lua libraries,
# examples and plotting tools in share/talus/scripts; the plugin SDK (include/talus and
# lib/cmake/talus, for find_package(talus)); the documentation in share/doc/talus. talus finds
# its plugins and Lua libraries relative to its executable, so the same files work under any
# prefix. Depends are read off the binaries by dpkg-shlibdeps (dpkg-dev).
# tests/install/deb_contents.cmake checks the package's file list and its Depends.

# The documentation: docs/ (with its figures), the README, and the licence as Debian's
# copyright file.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME copyright)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME talus)
set(CPACK_PACKAGE_VENDOR "The Talus developers")
set(CPACK_PACKAGE_CONTACT "The Talus developers <dev@talus.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_DESCRIPTION
    "Balls, clumps, walls and contacts cycled in PFC's order, contact models as shared-library
plugins with PFC's user-defined-model interface, runs driven by Lua 5.4 scripts, and energy
traced per named group. Ships the talus command, the contact models (linear, hertz, hysdamp,
power, ng, rrlinear, cbond, pbond, fjoint), the rockfall and material Lua libraries, examples,
the plugin SDK (headers and a CMake package) and the documentation.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The plotting tools are Python (matplotlib); building a plugin against the SDK needs a compiler
# and CMake; mpirun runs talus.map across machines.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-matplotlib")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "cmake, g++, openmpi-bin")
include(CPack)
