# Provides LIGGGHTS_BUILD_SRC: a patched copy of LIGGGHTS-PUBLIC 3.8.0's src/
# inside the build tree.
#
# Source, in order of preference:
#   LIGGGHTS_SOURCE_DIR  a user's tree (copied, never modified)
#   LIGGGHTS_TARBALL     a local copy of Debian's orig tarball (sha256 checked)
#   apt-get source       Debian's source package, downloaded into the build tree
#                        (needs a deb-src entry: tools/install_deps.sh adds one)

set(LIGGGHTS_DEBIAN_TARBALL_NAME "liggghts_3.8.0+repack1.orig.tar.xz")
set(LIGGGHTS_DEBIAN_TARBALL_SHA256
    "c18721d9a870c5170f03b91e4f1ffe13335c66ed1f0ff2c64ebd3be91c37867a")
# Our patches to LIGGGHTS' own sources, applied in this order (doc/liggghts_quirks.md):
#   gcc12           upstream 3.8.0 does not compile with GCC 12 as is
#   error-one-flush Error::one writes its message to the log too and flushes
#                   before MPI_Abort, so that an ERROR reaches a file or pipe
#   triclinic-lamda-box  the fractional box is 1 long, as in LAMMPS (3.8.0 has
#                   0): a tilted box wraps grains through its periodic sides
#                   and sets up its ghost exchanges without dividing by zero
set(LIGGGHTS_PATCHES
    "${CMAKE_CURRENT_LIST_DIR}/liggghts-3.8.0-gcc12.patch"
    "${CMAKE_CURRENT_LIST_DIR}/liggghts-3.8.0-error-one-flush.patch"
    "${CMAKE_CURRENT_LIST_DIR}/liggghts-3.8.0-triclinic-lamda-box.patch")

set(LIGGGHTS_WORK_DIR "${CMAKE_BINARY_DIR}/liggghts")
set(LIGGGHTS_BUILD_SRC "${LIGGGHTS_WORK_DIR}/src")

function(silokit_fetch_debian_tarball out_path)
  set(download_dir "${CMAKE_BINARY_DIR}/download")
  set(tarball "${download_dir}/${LIGGGHTS_DEBIAN_TARBALL_NAME}")
  if(LIGGGHTS_TARBALL)
    set(tarball "${LIGGGHTS_TARBALL}")
  elseif(NOT EXISTS "${tarball}")
    file(MAKE_DIRECTORY "${download_dir}")
    message(STATUS "silokit: apt-get source --download-only --tar-only liggghts")
    execute_process(
      COMMAND apt-get source --download-only --tar-only liggghts
      WORKING_DIRECTORY "${download_dir}"
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0 OR NOT EXISTS "${tarball}")
      message(FATAL_ERROR
        "silokit: could not get Debian's liggghts source package:\n${err}\n"
        "Run tools/install_deps.sh (it adds the deb-src entry), or pass "
        "-DLIGGGHTS_SOURCE_DIR=<tree> or -DLIGGGHTS_TARBALL=<file>.")
    endif()
  endif()
  file(SHA256 "${tarball}" sum)
  if(NOT sum STREQUAL LIGGGHTS_DEBIAN_TARBALL_SHA256)
    message(FATAL_ERROR "silokit: ${tarball} has sha256 ${sum}, "
                        "expected ${LIGGGHTS_DEBIAN_TARBALL_SHA256}")
  endif()
  set(${out_path} "${tarball}" PARENT_SCOPE)
endfunction()

# The copy is redone only when its origin or one of our patches changes
# (an edited patch re-runs this configure step at the next build).
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${LIGGGHTS_PATCHES})
set(patch_sum "")
foreach(patch IN LISTS LIGGGHTS_PATCHES)
  file(SHA256 "${patch}" sum)
  string(APPEND patch_sum " ${sum}")
endforeach()
if(LIGGGHTS_SOURCE_DIR)
  get_filename_component(origin "${LIGGGHTS_SOURCE_DIR}" ABSOLUTE)
  if(NOT EXISTS "${origin}/src/lammps.cpp")
    message(FATAL_ERROR "silokit: LIGGGHTS_SOURCE_DIR=${origin} has no src/lammps.cpp")
  endif()
  set(stamp_text "tree ${origin} patch ${patch_sum}")
else()
  set(stamp_text "debian ${LIGGGHTS_DEBIAN_TARBALL_SHA256} patch ${patch_sum}")
endif()

set(stamp "${LIGGGHTS_WORK_DIR}/.silokit-source-stamp")
set(old_stamp_text "")
if(EXISTS "${stamp}")
  file(READ "${stamp}" old_stamp_text)
endif()

if(NOT old_stamp_text STREQUAL stamp_text)
  file(REMOVE_RECURSE "${LIGGGHTS_WORK_DIR}")
  file(MAKE_DIRECTORY "${LIGGGHTS_WORK_DIR}")
  if(LIGGGHTS_SOURCE_DIR)
    message(STATUS "silokit: copying ${origin}/src")
    file(COPY "${origin}/src" DESTINATION "${LIGGGHTS_WORK_DIR}"
         PATTERN ".git" EXCLUDE PATTERN "Obj_*" EXCLUDE)
  else()
    silokit_fetch_debian_tarball(tarball)
    message(STATUS "silokit: extracting ${tarball}")
    set(unpack_dir "${CMAKE_BINARY_DIR}/unpack")
    file(REMOVE_RECURSE "${unpack_dir}")
    file(MAKE_DIRECTORY "${unpack_dir}")
    execute_process(COMMAND ${CMAKE_COMMAND} -E tar xf "${tarball}"
                    WORKING_DIRECTORY "${unpack_dir}" RESULT_VARIABLE rc)
    file(GLOB unpacked_src "${unpack_dir}/*/src")
    if(NOT rc EQUAL 0 OR NOT unpacked_src)
      message(FATAL_ERROR "silokit: could not unpack ${tarball}")
    endif()
    file(RENAME "${unpacked_src}" "${LIGGGHTS_BUILD_SRC}")
    file(REMOVE_RECURSE "${unpack_dir}")
  endif()
  foreach(patch IN LISTS LIGGGHTS_PATCHES)
    message(STATUS "silokit: applying ${patch}")
    execute_process(COMMAND patch -p1 --forward --batch -i "${patch}"
                    WORKING_DIRECTORY "${LIGGGHTS_WORK_DIR}"
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "silokit: ${patch} does not apply to this tree:\n${out}${err}")
    endif()
  endforeach()
  file(WRITE "${stamp}" "${stamp_text}")
endif()
