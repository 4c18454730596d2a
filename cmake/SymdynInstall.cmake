# What `cmake --install` puts under the prefix for a project to use symdyn
# (docs/install.md): the headers as <symdyn/<part>/<file>.hpp> (not those of
# a part's detail/ folder, its internals), the static
# libraries as the exported targets symdyn::<part>, symdyn_add_model, and the
# package configuration that find_package(symdyn) reads.
include(CMakePackageConfigHelpers)

set(symdyn_exported_parts symbolic model codegen runtime generator_main)
set(symdyn_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/symdyn)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/symdyn
  FILES_MATCHING PATTERN "*.hpp" PATTERN "detail" EXCLUDE)

list(TRANSFORM symdyn_exported_parts PREPEND symdyn_ OUTPUT_VARIABLE symdyn_exported_targets)
install(TARGETS ${symdyn_exported_targets} EXPORT symdynTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT symdynTargets NAMESPACE symdyn:: DESTINATION ${symdyn_cmake_dir})

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/symdynConfig.cmake.in
  ${PROJECT_BINARY_DIR}/symdynConfig.cmake INSTALL_DESTINATION ${symdyn_cmake_dir})
# 0.x: a minor release may break the interface, a patch release may not.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/symdynConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES
  ${PROJECT_BINARY_DIR}/symdynConfig.cmake
  ${PROJECT_BINARY_DIR}/symdynConfigVersion.cmake
  ${CMAKE_CURRENT_LIST_DIR}/SymdynAddModel.cmake
  ${CMAKE_CURRENT_LIST_DIR}/SymdynPython.cmake
  ${CMAKE_CURRENT_LIST_DIR}/SymdynCompileOptions.cmake
  DESTINATION ${symdyn_cmake_dir})
# The Python binding code, compiled by the consuming project for its PYTHON models.
install(FILES ${PROJECT_SOURCE_DIR}/src/python/model_module.cpp DESTINATION ${symdyn_cmake_dir}/python)
