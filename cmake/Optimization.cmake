# Link-time and profile-guided optimisation of the liggghts target (GCC).
#
# Why: our plain -O2 build runs the same instructions as Debian's liggghts
# but about 8 % slower (code layout, doc/accuracy_cost_rolling.md). LTO lets
# GCC inline across LIGGGHTS' many small translation units; PGO lays out and
# inlines hot code by measured branch counts. Neither changes floating-point
# semantics (no -ffast-math, no -march): the trajectories stay the same.
#
#   SILOKIT_LTO=ON   compile with -flto, optimise the whole program at link
#   SILOKIT_PGO=ON   three steps inside this build tree:
#                      1. target liggghts_instrumented (pgo/liggghts): the same
#                         sources compiled with -fprofile-generate
#                      2. tools/pgo_train.sh runs small variants of our scene
#                         decks with it -> pgo/raw/*.gcda, renamed for the
#                         liggghts target into pgo/profile/ (cmake/PgoProfile.cmake)
#                      3. liggghts compiled with -fprofile-use
#   Both targets compile the very same source files (LIGGGHTS_BUILD_SRC):
#   GCC checks a profile against each function's source file and lines, so
#   a profile made in another tree or from another copy of the sources is
#   refused (-Werror=coverage-mismatch).
#
# Expects: target liggghts, function silokit_liggghts_executable,
# SILOKIT_OPTIMIZATION_FLAGS, SILOKIT_FUNCTION_OPTIONS.

# On by default with GCC (doc/accuracy_cost_rolling.md, "Speed": the two
# together are the fastest build measured); another compiler builds without.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  set(optimise_default ON)
else()
  set(optimise_default OFF)
endif()
option(SILOKIT_LTO "Link-time optimisation (GCC -flto)" ${optimise_default})
set(SILOKIT_LTO_JOBS "auto" CACHE STRING
    "Parallel jobs of the LTO link (-flto=N); auto: make's jobserver, else all cores")
option(SILOKIT_PGO "Profile-guided optimisation: instrumented build, training run on our scene decks (tools/pgo_train.sh), then -fprofile-use" ${optimise_default})

if((SILOKIT_LTO OR SILOKIT_PGO) AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  message(FATAL_ERROR "silokit: SILOKIT_LTO and SILOKIT_PGO use GCC's options; "
                      "this is ${CMAKE_CXX_COMPILER_ID}: configure with -DSILOKIT_LTO=OFF -DSILOKIT_PGO=OFF")
endif()

if(SILOKIT_LTO)
  # The optimisation flags go to the link too: the whole-program step
  # compiles the code again and should do it as the compile step would.
  target_compile_options(liggghts PRIVATE -flto=${SILOKIT_LTO_JOBS} -fno-fat-lto-objects)
  target_link_options(liggghts PRIVATE -flto=${SILOKIT_LTO_JOBS} ${SILOKIT_OPTIMIZATION_FLAGS})
  # the functions left scalar or rolled (CMakeLists.txt): the link compiles them
  target_link_options(liggghts PRIVATE ${SILOKIT_FUNCTION_OPTIONS})
  message(STATUS "silokit: link-time optimisation on (-flto=${SILOKIT_LTO_JOBS})")
endif()

if(NOT SILOKIT_PGO)
  return()
endif()

set(pgo_dir "${CMAKE_BINARY_DIR}/pgo")
# The instrumented build needs no LTO: the profile is read per translation
# unit, before any link-time step. -fprofile-prefix-path: the profile's
# file names are the object paths relative to this tree, not absolute.
silokit_liggghts_executable(liggghts_instrumented "${pgo_dir}")
target_compile_options(liggghts_instrumented PRIVATE
  "-fprofile-generate=${pgo_dir}/raw" "-fprofile-prefix-path=${CMAKE_BINARY_DIR}")
target_link_options(liggghts_instrumented PRIVATE "-fprofile-generate=${pgo_dir}/raw")

# Training, then the profile for the liggghts target. profile.h holds the
# profile's checksum and is included (empty otherwise) by every liggghts
# source: a new profile recompiles them, an unchanged one (the training is
# deterministic) does not, and ccache sees the profile in the source.
add_custom_command(
  OUTPUT "${pgo_dir}/profile.stamp"
  BYPRODUCTS "${pgo_dir}/profile.h"
  COMMAND "${CMAKE_COMMAND}" -E rm -rf "${pgo_dir}/raw" "${pgo_dir}/training"
  COMMAND bash "${CMAKE_SOURCE_DIR}/tools/pgo_train.sh"
          "$<TARGET_FILE:liggghts_instrumented>" "${pgo_dir}/training"
  COMMAND "${CMAKE_COMMAND}" -DRAW=${pgo_dir}/raw -DPROFILE=${pgo_dir}/profile
          -DHEADER=${pgo_dir}/profile.h
          -DFROM=liggghts_instrumented.dir -DTO=liggghts.dir
          -P "${CMAKE_CURRENT_LIST_DIR}/PgoProfile.cmake"
  COMMAND "${CMAKE_COMMAND}" -E touch "${pgo_dir}/profile.stamp"
  DEPENDS liggghts_instrumented "${CMAKE_SOURCE_DIR}/tools/pgo_train.sh"
          "${CMAKE_CURRENT_LIST_DIR}/PgoProfile.cmake"
  COMMENT "silokit: PGO training run (tools/pgo_train.sh)"
  VERBATIM)
add_custom_target(pgo_profile DEPENDS "${pgo_dir}/profile.stamp")
add_dependencies(liggghts pgo_profile)

# -fprofile-partial-training: code the training did not run (styles and
# models our scene decks do not use) is optimised as without PGO, not for
# size, so that a user's deck that uses it is not slowed down.
# -Wno-missing-profile: sources the training never entered have no .gcda.
target_compile_options(liggghts PRIVATE
  "-fprofile-use=${pgo_dir}/profile" "-fprofile-prefix-path=${CMAKE_BINARY_DIR}"
  -fprofile-partial-training -Wno-missing-profile
  "SHELL:-include ${pgo_dir}/profile.h")
message(STATUS "silokit: profile-guided optimisation on: ${pgo_dir}/liggghts instrumented, "
               "trained by tools/pgo_train.sh")
