# Overlays src_plugin/ onto LIGGGHTS_BUILD_SRC and (re)generates LIGGGHTS'
# style headers with its own Make.sh.
#
# Each plugin file is copied with configure_file(COPYONLY), so editing one
# re-runs this step at the next build; adding or removing one is seen through
# the CONFIGURE_DEPENDS glob. Make.sh only rewrites a style header whose
# content changes, so a rebuild recompiles what really depends on the edit.

set(SILOKIT_PLUGIN_DIR "${CMAKE_SOURCE_DIR}/src_plugin")
file(GLOB plugin_files CONFIGURE_DEPENDS
     "${SILOKIT_PLUGIN_DIR}/*.h" "${SILOKIT_PLUGIN_DIR}/*.cpp"
     "${SILOKIT_PLUGIN_DIR}/*.whitelist")

# Remove files a previous overlay put there that src_plugin/ no longer has.
set(manifest "${LIGGGHTS_WORK_DIR}/.silokit-plugin-manifest")
if(EXISTS "${manifest}")
  file(STRINGS "${manifest}" previous_names)
  foreach(name IN LISTS previous_names)
    if(NOT EXISTS "${SILOKIT_PLUGIN_DIR}/${name}")
      file(REMOVE "${LIGGGHTS_BUILD_SRC}/${name}")
    endif()
  endforeach()
endif()

set(names "")
foreach(path IN LISTS plugin_files)
  get_filename_component(name "${path}" NAME)
  configure_file("${path}" "${LIGGGHTS_BUILD_SRC}/${name}" COPYONLY)
  string(APPEND names "${name}\n")
endforeach()
file(WRITE "${manifest}" "${names}")

# Only the contact-model combinations in style_contact_model_user.whitelist
# are compiled: an empty base whitelist stops Make.sh from generating its
# default list of several hundred combinations.
file(WRITE "${LIGGGHTS_BUILD_SRC}/style_contact_model.whitelist" "")

# Make.sh stamps version_liggghts.h with the date and the user's name each
# time it runs; we put a stable text in its place, so that the build output
# is reproducible (ccache then serves universe.cpp, its only user). The
# header is set aside while Make.sh runs and put back, with its old time,
# when our text is unchanged: a reconfigure (tools/build.sh runs one every
# time) then recompiles nothing, where a rewritten header would recompile
# universe.cpp and, with PGO, train again and recompile everything.
set(version_header "${LIGGGHTS_BUILD_SRC}/version_liggghts.h")
set(version_kept "${LIGGGHTS_WORK_DIR}/.silokit-version_liggghts.h")
if(EXISTS "${version_header}")
  file(RENAME "${version_header}" "${version_kept}")
endif()

foreach(what style models)
  execute_process(COMMAND sh Make.sh ${what}
                  WORKING_DIRECTORY "${LIGGGHTS_BUILD_SRC}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "silokit: 'sh Make.sh ${what}' failed:\n${out}${err}")
  endif()
endforeach()

file(READ "${LIGGGHTS_BUILD_SRC}/version_liggghts.txt" liggghts_version)
file(READ "${LIGGGHTS_BUILD_SRC}/version_liggghts_branch.txt" liggghts_branch)
string(STRIP "${liggghts_version}" liggghts_version)
string(STRIP "${liggghts_branch}" liggghts_branch)
set(version_text "#define LIGGGHTS_VERSION \"${liggghts_branch} ${liggghts_version}, with silokit styles\"\n")
set(kept_text "")
if(EXISTS "${version_kept}")
  file(READ "${version_kept}" kept_text)
endif()
if(kept_text STREQUAL version_text)
  file(RENAME "${version_kept}" "${version_header}")
else()
  file(REMOVE "${version_kept}")
  file(WRITE "${version_header}" "${version_text}")
endif()
