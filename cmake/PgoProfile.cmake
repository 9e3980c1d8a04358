# cmake -DRAW=<dir> -DPROFILE=<dir> -DHEADER=<file> -DFROM=<a.dir> -DTO=<b.dir> -P PgoProfile.cmake
#
# After the PGO training run (cmake/Optimization.cmake): copies the counts
# the instrumented target wrote (RAW/*.gcda, named after its objects,
# CMakeFiles#<FROM>#...) to PROFILE under the names the liggghts target's
# objects look for (CMakeFiles#<TO>#...), and writes HEADER with the
# profile's checksum, only when it changed (so that an identical profile
# recompiles nothing).
file(GLOB raw_files "${RAW}/*.gcda")
if(NOT raw_files)
  message(FATAL_ERROR "silokit: the PGO training wrote no profile to ${RAW}")
endif()
list(SORT raw_files)
file(REMOVE_RECURSE "${PROFILE}")
file(MAKE_DIRECTORY "${PROFILE}")
set(sums "")
foreach(path IN LISTS raw_files)
  get_filename_component(name "${path}" NAME)
  string(REPLACE "#${FROM}#" "#${TO}#" renamed "${name}")
  if(renamed STREQUAL name)
    message(FATAL_ERROR "silokit: unexpected profile file name ${name} (no #${FROM}#)")
  endif()
  configure_file("${path}" "${PROFILE}/${renamed}" COPYONLY)
  file(SHA256 "${path}" sum)
  string(APPEND sums "${renamed} ${sum}\n")
endforeach()
string(SHA256 checksum "${sums}")
list(LENGTH raw_files count)
set(text "/* silokit PGO profile: ${count} files, sha256 ${checksum} */\n")
set(old "")
if(EXISTS "${HEADER}")
  file(READ "${HEADER}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${HEADER}" "${text}")
endif()
message(STATUS "silokit: PGO profile: ${count} files, sha256 ${checksum}")
