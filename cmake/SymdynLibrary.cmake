# symdyn_add_library(<part> <source>...)
#
# The static library of one part of symdyn (src/<part>): target symdyn_<part>,
# named symdyn::<part> in the build tree, through add_subdirectory and once
# installed. It carries everything a consumer needs to compile against it: the
# include path (<symdyn/<part>/<file>.hpp>) and C++20.
function(symdyn_add_library part)
  set(target symdyn_${part})
  add_library(${target} STATIC ${ARGN})
  add_library(symdyn::${part} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${part})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${SYMDYN_INCLUDE_DIR}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${target} PUBLIC cxx_std_20)
  symdyn_set_compile_options(${target})
endfunction()
