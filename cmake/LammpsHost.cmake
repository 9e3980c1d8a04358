# LAMMPS as a second host (doc/lammps_host.md, section 3):
#   build/bin/lmp, build/lib/liblammps.so*   LAMMPS with PLUGIN and GRANULAR,
#                                            from Debian 12's source package
#   build/lib/silokit_lammps.so              our LAMMPS styles, one plugin that
#                                            a deck loads with `plugin load`
# With LAMMPS_SOURCE_DIR only the plugin is built, against that tree.

set(LAMMPS_SOURCE_DIR "" CACHE PATH
    "An existing LAMMPS tree with the PLUGIN package (holding src/lammpsplugin.h), already built; only our plugin is compiled against it. Empty: build Debian's LAMMPS")
set(LAMMPS_TARBALL "" CACHE FILEPATH
    "A local copy of Debian's lammps_20220106.git7586adbb6a+ds1.orig.tar.xz; empty: download it with apt-get source")

include(${CMAKE_CURRENT_LIST_DIR}/LammpsSource.cmake)   # -> LAMMPS_PLUGIN_SRC, LAMMPS_BUILD_TREE

if(LAMMPS_BUILD_TREE)
  include(ExternalProject)

  # An ExternalProject, not add_subdirectory: LAMMPS' CMake sets global
  # options of its own (BUILD_SHARED_LIBS, CMAKE_BUILD_TYPE, ...) that would
  # leak into ours. Its make runs under our make's jobserver, so one
  # `cmake --build build -j2` schedules LIGGGHTS' and LAMMPS' compiles alike.
  set(lammps_launcher "")
  if(CCACHE_PROGRAM)
    # base_dir: relative paths, so that another build directory on this
    # machine hits the same cache entries
    set(lammps_launcher
        "-DCMAKE_CXX_COMPILER_LAUNCHER:STRING=${CMAKE_COMMAND};-E;env;CCACHE_BASEDIR=${CMAKE_BINARY_DIR};${CCACHE_PROGRAM}"
        "-DCMAKE_C_COMPILER_LAUNCHER:STRING=${CMAKE_COMMAND};-E;env;CCACHE_BASEDIR=${CMAKE_BINARY_DIR};${CCACHE_PROGRAM}")
  endif()
  set(lammps_binary_dir "${LAMMPS_WORK_DIR}/build")
  # liblammps.so.0 is the file (SOVERSION 0), liblammps.so a link to it
  ExternalProject_Add(lammps
    SOURCE_DIR "${LAMMPS_BUILD_TREE}/cmake"
    BINARY_DIR "${lammps_binary_dir}"
    STAMP_DIR "${LAMMPS_WORK_DIR}/stamp"
    TMP_DIR "${LAMMPS_WORK_DIR}/tmp"
    DOWNLOAD_COMMAND ""
    UPDATE_COMMAND ""
    CMAKE_CACHE_ARGS
      -DCMAKE_C_COMPILER:FILEPATH=${CMAKE_C_COMPILER}
      -DCMAKE_CXX_COMPILER:FILEPATH=${CMAKE_CXX_COMPILER}
      -DCMAKE_BUILD_TYPE:STRING=Release
      -DPKG_PLUGIN:BOOL=ON
      -DPKG_GRANULAR:BOOL=ON
      -DBUILD_SHARED_LIBS:BOOL=ON
      -DBUILD_MPI:BOOL=ON
      -DBUILD_OMP:BOOL=OFF
      -DLAMMPS_SIZES:STRING=smallbig
      -DWITH_JPEG:BOOL=OFF
      -DWITH_PNG:BOOL=OFF
      -DWITH_FFMPEG:BOOL=OFF
      -DWITH_GZIP:BOOL=ON
      # the binaries are copied out of LAMMPS' build tree (its install step
      # would want the potentials, docs and Python module we do not unpack):
      # link them with their final run path, so that build/bin/lmp finds
      # build/lib/liblammps.so.0 wherever the tree is, and `plugin load
      # silokit_lammps.so` finds build/lib/silokit_lammps.so by its bare name
      -DCMAKE_BUILD_WITH_INSTALL_RPATH:BOOL=ON
      -DCMAKE_INSTALL_RPATH:STRING=$ORIGIN/../lib
      ${lammps_launcher}
    BUILD_ALWAYS ON
    INSTALL_COMMAND
      ${CMAKE_COMMAND} -E make_directory "${CMAKE_BINARY_DIR}/bin" "${CMAKE_BINARY_DIR}/lib"
      COMMAND ${CMAKE_COMMAND} -E copy_if_different "${lammps_binary_dir}/lmp" "${CMAKE_BINARY_DIR}/bin/lmp"
      COMMAND ${CMAKE_COMMAND} -E copy_if_different "${lammps_binary_dir}/liblammps.so.0"
              "${CMAKE_BINARY_DIR}/lib/liblammps.so.0"
      COMMAND ${CMAKE_COMMAND} -E create_symlink liblammps.so.0 "${CMAKE_BINARY_DIR}/lib/liblammps.so"
    BUILD_BYPRODUCTS "${CMAKE_BINARY_DIR}/bin/lmp" "${CMAKE_BINARY_DIR}/lib/liblammps.so.0")
endif()

# The plugin: the adapters in src_plugin/lammps/ and the host-free core in
# src_plugin/core/, compiled in place (nothing is copied into LAMMPS' tree).
# It compiles against LAMMPS' headers only and is not linked with
# liblammps.so: the LAMMPS and fmt symbols it uses resolve at `plugin load`
# from the liblammps.so that the running lmp has loaded. So it loads only
# into the LAMMPS it was compiled against (same version, same LAMMPS_SIZES).
file(GLOB SILOKIT_LAMMPS_SOURCES CONFIGURE_DEPENDS "${CMAKE_SOURCE_DIR}/src_plugin/lammps/*.cpp")
add_library(silokit_lammps MODULE ${SILOKIT_LAMMPS_SOURCES})
target_include_directories(silokit_lammps PRIVATE
  "${CMAKE_SOURCE_DIR}/src_plugin/core" "${CMAKE_SOURCE_DIR}/src_plugin/lammps"
  "${LAMMPS_PLUGIN_SRC}")
# LAMMPS_SMALLBIG: the integer sizes of the library (its default, given
# explicitly as in LAMMPS' examples/plugins); -O3 as LAMMPS' Release build
target_compile_definitions(silokit_lammps PRIVATE LAMMPS_SMALLBIG OMPI_SKIP_MPICXX MPICH_SKIP_MPICXX)
target_compile_options(silokit_lammps PRIVATE -O3 -Wall)
target_link_libraries(silokit_lammps PRIVATE MPI::MPI_CXX)
set_target_properties(silokit_lammps PROPERTIES
  PREFIX "" LIBRARY_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/lib"
  CXX_STANDARD 17 CXX_STANDARD_REQUIRED ON CXX_EXTENSIONS OFF)
# C++17: newer LAMMPS headers need it (20220106's take it as they take 11)
include(${CMAKE_CURRENT_LIST_DIR}/LammpsCompat.cmake)
silokit_lammps_compat(silokit_lammps)
if(TARGET lammps)
  # keeps a failed LAMMPS build from hiding behind a plugin that built
  add_dependencies(silokit_lammps lammps)
  message(STATUS "silokit: building LAMMPS (${LAMMPS_DEBIAN_TARBALL_NAME}) with PLUGIN and "
                 "GRANULAR -> bin/lmp, and the plugin -> lib/silokit_lammps.so")
endif()
