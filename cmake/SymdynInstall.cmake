# What `cmake --install` puts under the prefix for a project to use symdyn
# (docs/install.md): the headers as <symdyn/<part>/<file>.hpp> (not those of
# a part's detail/ folder, its internals), the static
# libraries as the exported targets symdyn::<part>, symdyn_add_model, and the
# package configuration that find_package(symdyn) reads; and the programs in
# bin/ with their man pages: symdyn-generate (a model file's generator),
# symdyn-urdf (with urdfdom), symdyn-sim and its Python package symdyn (with
# the reference models).
include(CMakePackageConfigHelpers)
include(SymdynManPages)

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
  ${CMAKE_CURRENT_LIST_DIR}/SymdynAddUrdfModel.cmake
  ${CMAKE_CURRENT_LIST_DIR}/SymdynPython.cmake
  ${CMAKE_CURRENT_LIST_DIR}/SymdynCompileOptions.cmake
  DESTINATION ${symdyn_cmake_dir})
# The Python binding code, compiled by the consuming project for its PYTHON models.
install(FILES ${PROJECT_SOURCE_DIR}/src/python/model_module.cpp DESTINATION ${symdyn_cmake_dir}/python)
# symdyn-generate finds the CMake package from where it is installed.
file(RELATIVE_PATH SYMDYN_CMAKE_DIR_FROM_BIN /prefix/${CMAKE_INSTALL_BINDIR} /prefix/${symdyn_cmake_dir})
set(SYMDYN_GENERATE ${PROJECT_BINARY_DIR}/bin/symdyn-generate)
configure_file(${PROJECT_SOURCE_DIR}/src/codegen/symdyn-generate.in ${SYMDYN_GENERATE} @ONLY
  FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
# The project symdyn-generate builds a model file's generator with.
install(FILES ${CMAKE_CURRENT_LIST_DIR}/generate/CMakeLists.txt DESTINATION ${symdyn_cmake_dir}/generate)

# The programs, each with its man page.
install(PROGRAMS ${SYMDYN_GENERATE} DESTINATION ${CMAKE_INSTALL_BINDIR})
symdyn_man_page(symdyn-generate ${SYMDYN_GENERATE} "builds and runs the generator of a symdyn model file"
  DEPENDS ${SYMDYN_GENERATE})
if(TARGET symdyn-urdf)
  install(TARGETS symdyn-urdf RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  symdyn_man_page(symdyn-urdf $<TARGET_FILE:symdyn-urdf> "emits the C++ of a robot described in URDF"
    DEPENDS symdyn-urdf)
endif()
if(TARGET symdyn-sim)
  install(TARGETS symdyn-sim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  symdyn_man_page(symdyn-sim $<TARGET_FILE:symdyn-sim> "runs scenarios and sweeps of symdyn models"
    DEPENDS symdyn-sim)
  # The sweeps' package, with the _build.py that finds the installed symdyn-sim.
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/apps/sim/python/symdyn/ DESTINATION ${SYMDYN_INSTALL_PYTHONDIR}/symdyn
    FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
  install(FILES ${SYMDYN_INSTALLED_BUILD_PY} DESTINATION ${SYMDYN_INSTALL_PYTHONDIR}/symdyn)
endif()
