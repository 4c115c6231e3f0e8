# Run in script mode: INPUTS ('|'-joined files), OUT_CPP, FUNCTION (a
# qualified name). Writes a C++ source defining
#   std::vector<std::pair<std::string, std::string>> FUNCTION()
# that returns (file name without extension, file text) for each input, in order.
string(REPLACE "|" ";" INPUTS "${INPUTS}")
set(rows "")
foreach(f ${INPUTS})
  get_filename_component(name ${f} NAME_WE)
  file(READ ${f} text)
  string(APPEND rows "      {\"${name}\", R\"vts_text(${text})vts_text\"},\n")
endforeach()
string(REGEX REPLACE "::[A-Za-z0-9_]+$" "" ns "${FUNCTION}")
string(REGEX REPLACE "^.*::" "" fn "${FUNCTION}")
file(WRITE ${OUT_CPP}.tmp "// Generated at build time.\n#include <string>\n#include <utility>\n#include <vector>\nnamespace ${ns} {\nstd::vector<std::pair<std::string, std::string>> ${fn}() {\n  return {\n${rows}  };\n}\n}\n")
file(RENAME ${OUT_CPP}.tmp ${OUT_CPP})
