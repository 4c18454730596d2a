# cmake -DDOC=<markdown> -DQUOTED=<file> -P doc_quotes_file.cmake
# Fails unless the document quotes the file whole, so that the CMakeLists.txt
# docs/install.md shows is the one the package tests build.
file(READ ${DOC} doc)
file(READ ${QUOTED} quoted)
string(FIND "${doc}" "${quoted}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${DOC} does not quote ${QUOTED} as it is: copy the file into it again")
endif()
