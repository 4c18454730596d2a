# cmake -DINPUT=<file> -DOUTPUT=<file.cpp> -DNAME=<identifier> -P EmbedText.cmake
#
# Writes a C++ source defining `const char* const NAME[]`: the text of INPUT in
# raw string chunks (each under the 65 536 characters ISO C++ promises for a
# literal), ending with nullptr. Used to build the HTML viewer's script into
# the runtime, so that a written HTML file needs nothing else.
file(READ "${INPUT}" text)
string(FIND "${text}" ")embedded\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw string delimiter )embedded\"")
endif()
string(LENGTH "${text}" length)
set(chunk 30000)
file(WRITE "${OUTPUT}" "// Generated from ${INPUT} at build time. Do not edit.\n"
                       "namespace symdyn::runtime::detail {\nextern const char* const ${NAME}[];\n"
                       "const char* const ${NAME}[] = {\n")
set(offset 0)
while(offset LESS length)
  string(SUBSTRING "${text}" ${offset} ${chunk} piece)
  file(APPEND "${OUTPUT}" "R\"embedded(${piece})embedded\",\n")
  math(EXPR offset "${offset} + ${chunk}")
endwhile()
file(APPEND "${OUTPUT}" "nullptr};\n}  // namespace symdyn::runtime::detail\n")
