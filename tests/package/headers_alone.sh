#!/usr/bin/env bash
# The public/internal line, checked on installed symdyn: no internal header
# (a part's detail/) is installed or included by an installed one, each part's
# umbrella header includes every public header of its part, and every
# installed header compiles on its own, included first and twice.
#   headers_alone.sh <symdyn build dir> <work dir> [cmake option]...
set -euo pipefail
symdyn_build=$1 work=$2
shift 2
fail() { echo "error: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work/project/sources"
cmake --install "$symdyn_build" --prefix "$work/prefix" >/dev/null || fail "cmake --install failed"
include=$work/prefix/include
[ -d "$include/symdyn" ] || fail "no headers installed under $include/symdyn"
cd "$include"

internal=$(find symdyn -path '*/detail/*')
[ -z "$internal" ] || fail "internal headers installed: $internal"
including=$(grep -lE '^#include <symdyn/([a-z_]+/)?detail/' -r symdyn || true)
[ -z "$including" ] || fail "installed headers that include an internal one: $including"

# The umbrella of each part; model.hpp is the model part's builder, so its umbrella is all.hpp.
declare -A umbrella=([symbolic]=symbolic.hpp [model]=all.hpp [codegen]=codegen.hpp [runtime]=runtime.hpp)
# Not under an umbrella: URDF import is a library of its own (symdyn::urdf).
not_umbrella=symdyn/model/urdf.hpp
for part in "${!umbrella[@]}"; do
  file=symdyn/$part/${umbrella[$part]}
  [ -f "$file" ] || fail "the umbrella header $file is not installed"
  for header in symdyn/"$part"/*.hpp; do
    [ "$header" = "$file" ] || [ "$header" = "$not_umbrella" ] ||
      grep -qx "#include <$header>" "$file" || fail "$file does not include <$header>"
  done
done

# One source per header, the header included twice (its include guard works).
headers=$(find symdyn -name '*.hpp' | sort)
python_headers=""
for header in $headers; do
  source=$work/project/sources/$(echo "$header" | tr '/.' '__').cpp
  printf '#include <%s>\n#include <%s>\n' "$header" "$header" >"$source"
  case $header in symdyn/python/*) python_headers+=" $source" ;; esac
done
echo "== $(echo "$headers" | wc -w) installed headers, each compiled alone"

cat >"$work/project/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.25)
project(symdyn_headers LANGUAGES CXX)
find_package(symdyn 0.1 REQUIRED)
file(GLOB sources ${PROJECT_SOURCE_DIR}/sources/*.cpp)
file(GLOB python_sources ${PROJECT_SOURCE_DIR}/sources/symdyn_python_*.cpp)
list(REMOVE_ITEM sources ${python_sources})
add_library(headers OBJECT ${sources})
target_link_libraries(headers PRIVATE symdyn::codegen symdyn::generator_main symdyn::runtime)
symdyn_set_compile_options(headers)
# The Python binding's header needs pybind11 and Python's headers, as a PYTHON model does.
if(python_sources AND SYMDYN_PYTHON)
  set(Python3_EXECUTABLE ${SYMDYN_PYTHON_EXECUTABLE})
  find_package(Python3 REQUIRED COMPONENTS Interpreter Development.Module)
  set(PYBIND11_NOPYTHON ON)
  find_package(pybind11 CONFIG REQUIRED)
  add_library(python_headers OBJECT ${python_sources})
  target_link_libraries(python_headers PRIVATE symdyn::runtime pybind11::headers Python3::Module)
  symdyn_set_compile_options(python_headers)
endif()
CMAKE
cmake -S "$work/project" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" "$@" \
  >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; fail "configuring the headers' project failed"; }
cmake --build "$work/build" || fail "an installed header does not compile on its own (above)"
