# The programs' man pages, written at build time by help2man from each
# program's --help, with the sections of docs/man/<program>.h2m (examples, see
# also), installed in share/man/man1 by cmake/SymdynInstall.cmake.
#   symdyn_man_page(<program> <command> <one-line description> [DEPENDS <target>...])
# Building symdyn itself needs help2man (scripts/lib/setup.sh installs it);
# built along by a project, symdyn installs no man page when it is missing.
if(SYMDYN_BUILD_TESTS)
  find_program(SYMDYN_HELP2MAN help2man REQUIRED)
else()
  find_program(SYMDYN_HELP2MAN help2man)
endif()

function(symdyn_man_page program command description)
  cmake_parse_arguments(ARG "" "" "DEPENDS" ${ARGN})
  if(NOT SYMDYN_HELP2MAN)
    message(STATUS "symdyn: help2man not found, no man page of ${program} (apt-get install help2man)")
    return()
  endif()
  set(page ${PROJECT_BINARY_DIR}/man/${program}.1)
  set(sections ${PROJECT_SOURCE_DIR}/docs/man/${program}.h2m)
  add_custom_command(OUTPUT ${page}
    COMMAND ${SYMDYN_HELP2MAN} --no-info --locale=C.UTF-8 --section=1 --name=${description}
      --version-string=${PROJECT_VERSION} --source=symdyn --include=${sections}
      --output=${page} ${command}
    DEPENDS ${ARG_DEPENDS} ${sections}
    COMMENT "symdyn: man page of ${program}"
    VERBATIM)
  add_custom_target(${program}_man_page ALL DEPENDS ${page})
  install(FILES ${page} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endfunction()
