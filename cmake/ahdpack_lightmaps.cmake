# ahdpack_add_lightmaps: cook lightmaps as part of a game's CMake build (docs/asset-cook.md).
#
#   ahdpack_add_lightmaps(<target>
#     INPUTS <file>...            lightmaps: canonical SH EXRs or any file of a baker's set
#     [PROFILE <name|file.json>]  output profile (default: uncompressed)
#     [OUTPUT_DIR <dir>]          default: ${CMAKE_CURRENT_BINARY_DIR}/lightmaps
#     [CONTAINER ktx2|dds]        default: ktx2
#     [CACHE <dir>]               a shared conversion cache (convert --cache)
#     [OPTIONS <convert flag>...] passed to every conversion of this call (--normals n.exr, --quality high…)
#     [ALL])                      build <target> by default
#
# One custom command per input: OUTPUT_DIR/<stem>.json (the manifest; the planes it names and
# <stem>.report.json are by-products) with DEPFILE OUTPUT_DIR/<stem>.d, which `convert --depfile`
# fills with every file the conversion read (the baker's files, .exr.import, .lmbake, meshes,
# profiles, layout presets). Ninja (or Make) then reconverts exactly the lightmaps whose inputs
# changed, in parallel. Calling it again with the same <target> adds more lightmaps to it (inputs
# with other OPTIONS); the manifests are in the target's AHDPACK_MANIFESTS property.
#
# The tool: ${AHDPACK_EXECUTABLE} when set, else the ahdpack target of this build (add_subdirectory),
# else the installed package's. Its data files (profiles, layout presets) are the ones installed
# beside it (AHD_FORMATS_DIR), so a conversion never reads a source tree.
# The depfile names the manifest and the inputs by absolute path; CMP0116 NEW makes the Ninja
# generator rewrite them to the paths build.ninja uses, whatever the caller's cmake_minimum_required
# (a function runs with the policies of where it was defined).
if(POLICY CMP0116)
  cmake_policy(SET CMP0116 NEW)
endif()
function(ahdpack_add_lightmaps target)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "ALL" "PROFILE;OUTPUT_DIR;CONTAINER;CACHE" "INPUTS;OPTIONS")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "ahdpack_add_lightmaps: unknown arguments: ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT ARG_INPUTS)
    message(FATAL_ERROR "ahdpack_add_lightmaps(${target}): INPUTS is empty")
  endif()
  if(NOT ARG_PROFILE)
    set(ARG_PROFILE uncompressed)
  endif()
  if(NOT ARG_OUTPUT_DIR)
    set(ARG_OUTPUT_DIR "${CMAKE_CURRENT_BINARY_DIR}/lightmaps")
  endif()
  if(NOT ARG_CONTAINER)
    set(ARG_CONTAINER ktx2)
  endif()
  if(NOT ARG_CONTAINER MATCHES "^(ktx2|dds)$")
    message(FATAL_ERROR "ahdpack_add_lightmaps(${target}): CONTAINER must be ktx2 or dds")
  endif()
  get_filename_component(out_dir "${ARG_OUTPUT_DIR}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_BINARY_DIR}")

  set(tool_env)
  if(AHDPACK_EXECUTABLE)
    set(tool "${AHDPACK_EXECUTABLE}")
    set(tool_dep "${AHDPACK_EXECUTABLE}")
  elseif(TARGET ahdpack)
    set(tool "$<TARGET_FILE:ahdpack>")
    set(tool_dep ahdpack)
  elseif(_AHDPACK_INSTALLED_EXECUTABLE)
    set(tool "${_AHDPACK_INSTALLED_EXECUTABLE}")
    set(tool_dep "${_AHDPACK_INSTALLED_EXECUTABLE}")
  else()
    message(FATAL_ERROR "ahdpack_add_lightmaps: no ahdpack executable (set AHDPACK_EXECUTABLE)")
  endif()
  if(_AHDPACK_INSTALLED_FORMATS AND NOT AHDPACK_EXECUTABLE AND NOT TARGET ahdpack)
    set(tool_env "${CMAKE_COMMAND}" -E env "AHD_FORMATS_DIR=${_AHDPACK_INSTALLED_FORMATS}")
  endif()
  set(profile_arg "${ARG_PROFILE}")
  if(ARG_PROFILE MATCHES "\\.json$")
    get_filename_component(profile_arg "${ARG_PROFILE}" ABSOLUTE)
  endif()
  set(cache_args)
  if(ARG_CACHE)
    get_filename_component(cache_dir "${ARG_CACHE}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_BINARY_DIR}")
    set(cache_args --cache "${cache_dir}")
  endif()

  get_property(known GLOBAL PROPERTY _AHDPACK_OUTPUTS)
  set(manifests)
  foreach(input IN LISTS ARG_INPUTS)
    get_filename_component(input_abs "${input}" ABSOLUTE)
    get_filename_component(stem "${input_abs}" NAME_WE)
    set(manifest "${out_dir}/${stem}.json")
    if(manifest IN_LIST known)
      message(FATAL_ERROR "ahdpack_add_lightmaps(${target}): ${input} would write ${manifest}, which another lightmap writes")
    endif()
    list(APPEND known "${manifest}")
    add_custom_command(
      OUTPUT "${manifest}"
      BYPRODUCTS "${out_dir}/${stem}.report.json"
      COMMAND ${tool_env} "${tool}" convert "${input_abs}" -o "${out_dir}/${stem}.${ARG_CONTAINER}" --profile "${profile_arg}"
              --depfile "${out_dir}/${stem}.d" ${cache_args} ${ARG_OPTIONS} -q
      DEPENDS "${input_abs}" ${tool_dep}
      DEPFILE "${out_dir}/${stem}.d"
      COMMENT "ahdpack: cooking ${stem}"
      VERBATIM)
    list(APPEND manifests "${manifest}")
  endforeach()
  set_property(GLOBAL PROPERTY _AHDPACK_OUTPUTS "${known}")

  set(all)
  if(ARG_ALL)
    set(all ALL)
  endif()
  if(TARGET ${target})
    # A further call for the same target: its lightmaps in a part target the first one depends on.
    get_property(n TARGET ${target} PROPERTY _AHDPACK_PARTS)
    if(NOT n)
      set(n 0)
    endif()
    math(EXPR n "${n} + 1")
    set_property(TARGET ${target} PROPERTY _AHDPACK_PARTS ${n})
    add_custom_target(${target}_part${n} DEPENDS ${manifests})
    add_dependencies(${target} ${target}_part${n})
  else()
    add_custom_target(${target} ${all} DEPENDS ${manifests})
  endif()
  set_property(TARGET ${target} APPEND PROPERTY AHDPACK_MANIFESTS ${manifests})
endfunction()
