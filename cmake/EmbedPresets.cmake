# Generates a C++ source holding every examples/*.toml preset as a string, so the presets are
# built into the binary (input/presets.h). Run at configure time; re-run when a preset changes.
file(GLOB _presets "${FLEXROD_SOURCE}/examples/*.toml")
set(_out "// Generated from examples/*.toml by cmake/EmbedPresets.cmake. Do not edit.\n")
string(APPEND _out "#include \"input/presets.h\"\nnamespace flexrod {\nconst std::vector<Preset>& Presets() {\n")
string(APPEND _out "  static const std::vector<Preset> presets = {\n")
foreach(_p IN LISTS _presets)
  get_filename_component(_name "${_p}" NAME_WE)
  file(READ "${_p}" _text)
  string(APPEND _out "    {\"${_name}\", R\"flexrod_preset(${_text})flexrod_preset\"},\n")
endforeach()
string(APPEND _out "  };\n  return presets;\n}\n}  // namespace flexrod\n")
file(WRITE "${FLEXROD_OUTPUT}.new" "${_out}")
file(COPY_FILE "${FLEXROD_OUTPUT}.new" "${FLEXROD_OUTPUT}" ONLY_IF_DIFFERENT)
