# Writes OUT (a .cpp) holding every formats/profiles/*.json as text, sorted by name, for
# builtin_profile() (src/pipeline/profile.h). Run at build time: cmake -DDIR=… -DOUT=… -P this file.
file(GLOB _profiles "${DIR}/*.json")
list(SORT _profiles)
set(_body "")
foreach(_p ${_profiles})
  get_filename_component(_name "${_p}" NAME_WE)
  file(READ "${_p}" _text)
  string(APPEND _body "    {\"${_name}\", R\"ahdjson(${_text})ahdjson\"},\n")
endforeach()
list(LENGTH _profiles _n)
file(WRITE "${OUT}.new" "// Generated from formats/profiles by cmake/embed_profiles.cmake: do not edit.\n#include \"pipeline/builtin_profiles.h\"\n\nnamespace ahd {\n\nconst BuiltinProfileText kBuiltinProfiles[] = {\n${_body}};\nconst size_t kBuiltinProfileCount = ${_n};\n\n}  // namespace ahd\n")
file(COPY_FILE "${OUT}.new" "${OUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT}.new")
