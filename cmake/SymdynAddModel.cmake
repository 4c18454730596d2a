# symdyn_add_model(<target> <model.cpp> [MODEL <name>] [VARIANT <v>]
#                  [PARTIALS numeric|symbolic] [NO_SIMPLIFY] [NO_EOM]
#                  [DERIVATIVES | DYNAMICS_DERIVATIVES] [REACTIONS] [PART_SIZE n]
#                  [DYNAMICS auto|mass-matrix|recursive] [ONLY <entry point>...]
#                  [SOURCES n] [PYTHON] [SIM_MODULE])
#
# Builds the model's generator (the model file linked with symdyn's generator
# main; one per model file, shared by every variant), runs it at build time
# whenever the model or the generator changes, and makes <target> a static
# library of the emitted code. MODEL chooses among the models of a file that
# registers several (chain.cpp: chain_2 ... chain_64). Link it into a simulation:
#
#   symdyn_add_model(double_pendulum_absolute double_pendulum.cpp VARIANT absolute)
#   target_link_libraries(my_simulation PRIVATE double_pendulum_absolute symdyn::runtime)
#
# The emitted header is <target>.hpp; the struct inside is symdyn_generated::<target>.
# ONLY emits those entry points alone (generator --only), to call directly.
# DERIVATIVES also emits the exact derivatives of the equations of motion and of
# the kinematics force elements read (generator --derivatives), which the runtime
# then uses wherever it needs a Jacobian (implicit integrators, statics,
# linearization and modes, control); DYNAMICS_DERIVATIVES those of the equations
# of motion alone (--dynamics-derivatives: they grow as nq², the kinematics' as
# nbody·nq²), the force elements at body points then differenced.
# REACTIONS also emits joint_reactions (generator --reactions): the force and
# moment every body's joint transmits, which the runtime then reports.
# Every target with equations of motion (no NO_EOM, no ONLY) is appended to the global
# property SYMDYN_MODELS, in the order added: tests/simulation checks each of
# them (emitted against assembled equations) without being told.
# SOURCES spreads the emitted definitions over up to n source files (generator
# --sources), which make or ninja compile in parallel (default
# SYMDYN_EMITTED_CODE_SOURCES); a small model fills the first alone.
# PYTHON also builds the Python module <target> (cmake/SymdynPython.cmake).
#
# The emitted code is compiled optimized whatever the project's build type (the
# flags of "Compiling the emitted code" below); an -O of the project's own
# CMAKE_CXX_FLAGS stays.
include(${CMAKE_CURRENT_LIST_DIR}/SymdynPython.cmake)

# ---- Compiling the emitted code -------------------------------------------
# The emitted code is long straight-line functions, whose compilation takes
# most of a model's build: these flags, after the build type's (in every
# build type), skip the passes of -O2 that cost compile time there and win
# no instruction (bench/results/build_loop.md). Set SYMDYN_EMITTED_CODE_FLAGS
# to change them, or to "" for the build type's flags alone; an optimization
# level in CMAKE_CXX_FLAGS is the user's choice and is kept.
# (Variables, not cache entries, so that a new default reaches every build;
# -D sets them.) Defaulted where a model is added, not only here: a project
# that adds symdyn with add_subdirectory sees none of symdyn's variables.
macro(symdyn_emitted_code_defaults)
  if(NOT DEFINED SYMDYN_EMITTED_CODE_FLAGS)
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      set(SYMDYN_EMITTED_CODE_FLAGS "-O2 -fno-tree-slp-vectorize -fno-schedule-insns2 -fno-tree-dse -fno-gcse -fno-tree-pre -fno-tree-vrp -fno-code-hoisting -fno-expensive-optimizations -fno-tree-fre -fno-dse -fno-tree-dce -fno-ipa-pure-const -fno-ipa-reference -fno-ipa-modref -fno-rerun-cse-after-loop")
    else()  # the passes above are GCC's: clang refuses most of their names
      set(SYMDYN_EMITTED_CODE_FLAGS "-O2")
    endif()
  endif()
  # The most source files of one model, compiled in parallel (SOURCES).
  if(NOT DEFINED SYMDYN_EMITTED_CODE_SOURCES)
    set(SYMDYN_EMITTED_CODE_SOURCES 4)
  endif()
endmacro()
symdyn_emitted_code_defaults()

# The emitted source files of <target> spread over <count>: <target>.cpp, then
# <target>.2.cpp ... <target>.<count>.cpp, the flags above on each (for every
# target compiling them: the library, the Python and the symdyn-sim module).
function(symdyn_emitted_sources var out_dir target count)
  symdyn_emitted_code_defaults()
  if(NOT count MATCHES "^[1-9][0-9]*$")
    message(FATAL_ERROR "${target}: SOURCES '${count}' is not a number of files (1 or more)")
  endif()
  set(files ${out_dir}/${target}.cpp)
  if(count GREATER 1)
    foreach(i RANGE 2 ${count})
      list(APPEND files ${out_dir}/${target}.${i}.cpp)
    endforeach()
  endif()
  if(NOT CMAKE_CXX_FLAGS MATCHES "(^| )-O")
    separate_arguments(flags UNIX_COMMAND "${SYMDYN_EMITTED_CODE_FLAGS}")
    set_source_files_properties(${files} PROPERTIES COMPILE_OPTIONS "${flags}")
  endif()
  set(${var} ${files} PARENT_SCOPE)
endfunction()
# ---------------------------------------------------------------------------

# symdyn_add_generator(<out var> <model.cpp>): the model's generator, the model
# file linked with symdyn's generator main, named symdyn_generator_<file stem>;
# defined once per model file. symdyn-generate builds it the same way.
function(symdyn_add_generator out model_source)
  get_filename_component(model_name ${model_source} NAME_WE)
  get_filename_component(model_path ${model_source} ABSOLUTE)
  set(generator symdyn_generator_${model_name})
  if(NOT TARGET ${generator})
    add_executable(${generator} ${model_path})
    target_link_libraries(${generator} PRIVATE symdyn::generator_main)
    symdyn_set_compile_options(${generator})
  endif()
  set(${out} ${generator} PARENT_SCOPE)
endfunction()

function(symdyn_add_model target model_source)
  cmake_parse_arguments(ARG "NO_SIMPLIFY;NO_EOM;DERIVATIVES;DYNAMICS_DERIVATIVES;REACTIONS;PYTHON;SIM_MODULE" "MODEL;VARIANT;PARTIALS;PART_SIZE;DYNAMICS;SOURCES" "ONLY" ${ARGN})
  get_filename_component(model_name ${model_source} NAME_WE)
  symdyn_add_generator(generator ${model_source})
  set(flags --basename ${target})
  if(ARG_MODEL)
    list(APPEND flags --model ${ARG_MODEL})
  endif()
  if(ARG_VARIANT)
    list(APPEND flags --variant ${ARG_VARIANT})
  endif()
  if(ARG_PARTIALS)
    list(APPEND flags --partials ${ARG_PARTIALS})
  endif()
  if(ARG_NO_SIMPLIFY)
    list(APPEND flags --no-simplify)
  endif()
  if(ARG_NO_EOM)
    list(APPEND flags --no-eom)
  endif()
  if(ARG_DERIVATIVES)
    list(APPEND flags --derivatives)
  elseif(ARG_DYNAMICS_DERIVATIVES)
    list(APPEND flags --dynamics-derivatives)
  endif()
  if(ARG_REACTIONS)
    list(APPEND flags --reactions)
  endif()
  if(ARG_DYNAMICS)
    list(APPEND flags --dynamics ${ARG_DYNAMICS})
  endif()
  if(ARG_ONLY)
    list(JOIN ARG_ONLY "," only)
    list(APPEND flags --only ${only})
  endif()
  if(DEFINED ARG_PART_SIZE)
    list(APPEND flags --part-size ${ARG_PART_SIZE} --split-above 0)
  endif()
  if(NOT ARG_SOURCES)
    symdyn_emitted_code_defaults()
    set(ARG_SOURCES ${SYMDYN_EMITTED_CODE_SOURCES})
  endif()
  list(APPEND flags --sources ${ARG_SOURCES})
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/generated/${target})
  symdyn_emitted_sources(sources ${out_dir} ${target} ${ARG_SOURCES})
  add_custom_command(
    OUTPUT ${out_dir}/${target}.hpp ${sources}
    COMMAND ${generator} --out ${out_dir} ${flags}
    DEPENDS ${generator}
    COMMENT "symdyn: generating ${target} from ${model_name}"
    VERBATIM)
  add_library(${target} STATIC ${sources} ${out_dir}/${target}.hpp)
  set_target_properties(${target} PROPERTIES SYMDYN_EMITTED_SOURCES "${sources}")
  target_include_directories(${target} PUBLIC ${out_dir})
  symdyn_set_compile_options(${target})
  if(NOT ARG_NO_EOM AND NOT ARG_ONLY)
    set_property(GLOBAL APPEND PROPERTY SYMDYN_MODELS ${target})
  endif()
  if(ARG_PYTHON)
    symdyn_python_module(${target})
  endif()
  if(ARG_SIM_MODULE)
    symdyn_add_model_module(${target} ${out_dir})
  endif()
endfunction()

# SIM_MODULE: also <target>_module, a loadable module (<target>_module.so)
# that symdyn-sim runs from a scenario file ("model": {"module": ...}). It
# holds the emitted code, compiled position-independent, and the one entry
# point of runtime/model_module.hpp; it uses no symbol of the runtime library.
function(symdyn_add_model_module target out_dir)
  set(entry ${out_dir}/${target}_module.cpp)
  file(GENERATE OUTPUT ${entry} CONTENT
"// Generated by symdyn_add_model(${target} ... SIM_MODULE).
#include <symdyn/runtime/model_module.hpp>

#include \"${target}.hpp\"

extern \"C\" __attribute__((visibility(\"default\"))) const symdyn::runtime::ModelModule* symdyn_model_module() {
  static const symdyn::runtime::ModelModule module =
      symdyn::runtime::make_model_module<symdyn_generated::${target}>();
  return &module;
}
")
  get_target_property(sources ${target} SYMDYN_EMITTED_SOURCES)
  add_library(${target}_module MODULE ${sources} ${entry})
  set_target_properties(${target}_module PROPERTIES PREFIX "" POSITION_INDEPENDENT_CODE ON
                                                    CXX_VISIBILITY_PRESET hidden)
  target_include_directories(${target}_module PRIVATE ${out_dir})
  target_link_libraries(${target}_module PRIVATE symdyn::runtime)
  symdyn_set_compile_options(${target}_module)
endfunction()
