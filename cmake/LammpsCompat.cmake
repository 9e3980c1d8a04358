# Which LAMMPS calls the tree at LAMMPS_PLUGIN_SRC offers, for
# src_plugin/lammps/lammps_compat.h: each newer call is compiled against the
# tree's headers, and its macro is defined on the plugin when it compiles.
# LAMMPS 20220106 (ours) has none of them; 4Feb2025 (Debian 13's) has all
# four. LAMMPS has no version macro to test, and the calls changed in
# different releases, hence one check per call.
#
#   silokit_lammps_compat(<target>)

include(CheckCXXSourceCompiles)

function(silokit_lammps_compat target)
  # the results are cached: forget them when the tree, or its version, changes
  set(version_text "")
  if(EXISTS "${LAMMPS_PLUGIN_SRC}/version.h")
    file(READ "${LAMMPS_PLUGIN_SRC}/version.h" version_text)
  endif()
  string(SHA256 tree_key "${LAMMPS_PLUGIN_SRC}\n${version_text}")
  set(checks SILOKIT_LAMMPS_HEADERS SILOKIT_LAMMPS_ADD_REQUEST SILOKIT_LAMMPS_GET_FIX_BY_STYLE
             SILOKIT_LAMMPS_GET_REGION_BY_ID SILOKIT_LAMMPS_HISTORY_TYPES)
  if(NOT "${SILOKIT_LAMMPS_COMPAT_KEY}" STREQUAL "${tree_key}")
    foreach(check IN LISTS checks)
      unset(${check} CACHE)
    endforeach()
    set(SILOKIT_LAMMPS_COMPAT_KEY "${tree_key}" CACHE INTERNAL "tree the LAMMPS API checks ran on")
  endif()

  # as the plugin compiles: headers only, C++17 (newer lmptype.h needs it)
  set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
  set(CMAKE_CXX_STANDARD 17)
  set(CMAKE_CXX_STANDARD_REQUIRED ON)
  set(CMAKE_CXX_EXTENSIONS OFF)
  set(CMAKE_REQUIRED_INCLUDES "${LAMMPS_PLUGIN_SRC}" ${MPI_CXX_INCLUDE_DIRS})
  set(CMAKE_REQUIRED_DEFINITIONS -DLAMMPS_SMALLBIG -DOMPI_SKIP_MPICXX -DMPICH_SKIP_MPICXX)

  # the baseline: without it a failed check below could mean unreadable
  # headers instead of an older LAMMPS
  check_cxx_source_compiles([[
#include "pair.h"
int main() { return 0; }
]] SILOKIT_LAMMPS_HEADERS)
  if(NOT SILOKIT_LAMMPS_HEADERS)
    message(FATAL_ERROR "silokit: cannot compile against the LAMMPS headers in "
                        "${LAMMPS_PLUGIN_SRC}; see CMakeFiles/CMakeError.log")
  endif()

  check_cxx_source_compiles([[
#include "neighbor.h"
#include "pair.h"
void request(LAMMPS_NS::Neighbor *neighbor, LAMMPS_NS::Pair *pair)
{
  neighbor->add_request(pair, LAMMPS_NS::NeighConst::REQ_SIZE | LAMMPS_NS::NeighConst::REQ_HISTORY);
}
int main() { return 0; }
]] SILOKIT_LAMMPS_ADD_REQUEST)

  check_cxx_source_compiles([[
#include "fix.h"
#include "modify.h"
bool has_gravity(LAMMPS_NS::Modify *modify)
{
  return !modify->get_fix_by_style("^gravity").empty();
}
int main() { return 0; }
]] SILOKIT_LAMMPS_GET_FIX_BY_STYLE)

  check_cxx_source_compiles([[
#include "domain.h"
#include "region.h"
LAMMPS_NS::Region *region(LAMMPS_NS::Domain *domain) { return domain->get_region_by_id("outlet"); }
int main() { return 0; }
]] SILOKIT_LAMMPS_GET_REGION_BY_ID)

  # `override` makes a parameter list the host does not declare an error
  check_cxx_source_compiles([[
#include "pair.h"
struct TypedHistory : LAMMPS_NS::Pair {
  void transfer_history(double *, double *, int, int) override;
};
int main() { return 0; }
]] SILOKIT_LAMMPS_HISTORY_TYPES)

  foreach(check IN LISTS checks)
    if(NOT check STREQUAL "SILOKIT_LAMMPS_HEADERS" AND ${check})
      target_compile_definitions(${target} PRIVATE ${check})
    endif()
  endforeach()
endfunction()
