# The Debian package of what cmake/SymdynInstall.cmake installs, from the
# release build: `cpack -G DEB` in build/release gives symdyn_<version>_<arch>.deb.
# It depends on the -dev packages symdynConfig.cmake finds; fmt and SUNDIALS
# within the major version the static libraries were compiled against; and on
# the shared libraries its programs load (dpkg-shlibdeps: urdfdom, TinyXML).
set(SYMDYN_PACKAGE_MAINTAINER "symdyn maintainers <maintainers@symdyn.invalid>"
  CACHE STRING "Maintainer field of the Debian package")

function(symdyn_same_major_depends out package version)
  string(REGEX MATCH "^[0-9]+" major ${version})
  math(EXPR next_major "${major} + 1")
  set(${out} "${package} (>= ${version}), ${package} (<< ${next_major})" PARENT_SCOPE)
endfunction()

symdyn_same_major_depends(fmt_depends libfmt-dev ${fmt_VERSION})
symdyn_same_major_depends(sundials_depends libsundials-dev ${SUNDIALS_VERSION})

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME symdyn)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_DESCRIPTION "symdyn derives multibody kinematics and equations of motion \
symbolically from a C++ builder API and emits plain C++. This package holds the headers, the \
static libraries and the CMake package (find_package(symdyn), symdyn_add_model), and the \
programs symdyn-sim (scenarios and sweeps), symdyn-urdf (URDF robots) and symdyn-generate \
(a model file's generator), with their man pages and the Python package of sweeps.")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${SYMDYN_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libeigen3-dev (>= 3.4), ${fmt_depends}, ${sundials_depends}")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# symdyn_add_model compiles the user's model at build time: C++20 and CMake >= 3.25.
# symdyn-sim --sweep runs the Python package with python3; HDF5 tables need h5py,
# a cluster of workers Dask's distributed.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "cmake (>= 3.25), g++ (>= 12), python3")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-h5py, python3-distributed")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
include(CPack)
