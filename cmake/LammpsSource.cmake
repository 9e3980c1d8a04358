# Provides LAMMPS_PLUGIN_SRC: the src/ directory of the LAMMPS tree our plugin
# compiles against, and LAMMPS_BUILD_TREE: the unpacked tree that
# cmake/LammpsHost.cmake builds (empty with LAMMPS_SOURCE_DIR: that LAMMPS is
# the user's, already built).
#
# Source, in order of preference:
#   LAMMPS_SOURCE_DIR  a user's LAMMPS tree with the PLUGIN package (read only,
#                      never modified; LAMMPS is not built, only our plugin)
#   LAMMPS_TARBALL     a local copy of Debian's orig tarball (sha256 checked)
#   apt-get source     Debian 12's source package, downloaded into the build
#                      tree (needs a deb-src entry: tools/install_deps.sh adds one)
#
# Debian 12's lammps 20220106.git7586adbb6a+ds1-2 is LAMMPS' stable release of
# 29 Sep 2021, update 2 (doc/lammps_host.md, section 1). Debian's patches
# touch nothing we build: the orig tarball is used alone, as for LIGGGHTS.

set(LAMMPS_DEBIAN_TARBALL_NAME "lammps_20220106.git7586adbb6a+ds1.orig.tar.xz")
set(LAMMPS_DEBIAN_TARBALL_SHA256
    "65146c615ad24d8b8bc64f4e05e86226a7f1fdb45c0b5ea9416562b9f3863082")

set(LAMMPS_WORK_DIR "${CMAKE_BINARY_DIR}/lammps")
set(LAMMPS_BUILD_TREE "")

if(LAMMPS_SOURCE_DIR)
  get_filename_component(origin "${LAMMPS_SOURCE_DIR}" ABSOLUTE)
  if(NOT EXISTS "${origin}/src/lammps.cpp")
    message(FATAL_ERROR "silokit: LAMMPS_SOURCE_DIR=${origin} has no src/lammps.cpp")
  endif()
  if(NOT EXISTS "${origin}/src/lammpsplugin.h")
    message(FATAL_ERROR
      "silokit: LAMMPS_SOURCE_DIR=${origin} has no src/lammpsplugin.h: this LAMMPS "
      "predates the PLUGIN package (2021), so it cannot load silokit_lammps.so")
  endif()
  set(LAMMPS_PLUGIN_SRC "${origin}/src")
  message(STATUS "silokit: LAMMPS plugin against ${LAMMPS_PLUGIN_SRC} (LAMMPS itself not built)")
  return()
endif()

function(silokit_fetch_lammps_tarball out_path)
  set(download_dir "${CMAKE_BINARY_DIR}/download")
  set(tarball "${download_dir}/${LAMMPS_DEBIAN_TARBALL_NAME}")
  if(LAMMPS_TARBALL)
    set(tarball "${LAMMPS_TARBALL}")
  elseif(NOT EXISTS "${tarball}")
    file(MAKE_DIRECTORY "${download_dir}")
    message(STATUS "silokit: apt-get source --download-only --tar-only lammps (80 MB)")
    execute_process(
      COMMAND apt-get source --download-only --tar-only lammps
      WORKING_DIRECTORY "${download_dir}"
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT EXISTS "${tarball}")
      message(FATAL_ERROR
        "silokit: could not get Debian's lammps source package:\n${err}\n"
        "Run tools/install_deps.sh (it adds the deb-src entry), or pass "
        "-DLAMMPS_SOURCE_DIR=<tree> or -DLAMMPS_TARBALL=<file>, "
        "or -DSILOKIT_LAMMPS=OFF to build without LAMMPS.")
    endif()
  endif()
  file(SHA256 "${tarball}" sum)
  if(NOT sum STREQUAL LAMMPS_DEBIAN_TARBALL_SHA256)
    message(FATAL_ERROR "silokit: ${tarball} has sha256 ${sum}, "
                        "expected ${LAMMPS_DEBIAN_TARBALL_SHA256}")
  endif()
  set(${out_path} "${tarball}" PARENT_SCOPE)
endfunction()

set(LAMMPS_BUILD_TREE "${LAMMPS_WORK_DIR}/src-tree")
set(LAMMPS_PLUGIN_SRC "${LAMMPS_BUILD_TREE}/src")

# Unpacked once: the stamp names the tarball's sum, so only another LAMMPS
# version unpacks again (the build is then redone from scratch).
set(stamp_text "debian ${LAMMPS_DEBIAN_TARBALL_SHA256}")
set(stamp "${LAMMPS_WORK_DIR}/.silokit-source-stamp")
set(old_stamp_text "")
if(EXISTS "${stamp}")
  file(READ "${stamp}" old_stamp_text)
endif()

if(NOT old_stamp_text STREQUAL stamp_text)
  file(REMOVE_RECURSE "${LAMMPS_WORK_DIR}")
  file(MAKE_DIRECTORY "${LAMMPS_WORK_DIR}")
  silokit_fetch_lammps_tarball(tarball)
  # Only cmake/ and src/ (71 MB of the 342 MB: no examples, potentials,
  # docs or bundled libraries, which the GRANULAR + PLUGIN build does not
  # read). GNU tar's --wildcards; cmake -E tar has no pattern filter.
  find_program(SILOKIT_TAR tar REQUIRED)
  message(STATUS "silokit: extracting cmake/ and src/ of ${tarball}")
  set(unpack_dir "${LAMMPS_WORK_DIR}/unpack")
  file(MAKE_DIRECTORY "${unpack_dir}")
  execute_process(COMMAND "${SILOKIT_TAR}" xJf "${tarball}" --wildcards "*/cmake/*" "*/src/*"
                  WORKING_DIRECTORY "${unpack_dir}" RESULT_VARIABLE rc ERROR_VARIABLE err)
  file(GLOB unpacked "${unpack_dir}/*")
  list(LENGTH unpacked count)
  if(NOT rc EQUAL 0 OR NOT count EQUAL 1 OR NOT EXISTS "${unpacked}/src/lammpsplugin.h")
    message(FATAL_ERROR "silokit: could not unpack ${tarball}:\n${err}")
  endif()
  file(RENAME "${unpacked}" "${LAMMPS_BUILD_TREE}")
  file(REMOVE_RECURSE "${unpack_dir}")
  file(WRITE "${stamp}" "${stamp_text}")
endif()
