# symdyn_add_model(<target> <model.cpp> [MODEL <name>] [VARIANT <v>]
#                  [PARTIALS numeric|symbolic] [NO_SIMPLIFY] [NO_EOM] [PART_SIZE n]
#                  [PYTHON])
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
# Every target with equations of motion (no NO_EOM) is appended to the global
# property SYMDYN_MODELS, in the order added: tests/simulation checks each of
# them (emitted against assembled equations) without being told.
# PYTHON also builds the Python module <target> (cmake/SymdynPython.cmake).
include(${CMAKE_CURRENT_LIST_DIR}/SymdynPython.cmake)

function(symdyn_add_model target model_source)
  cmake_parse_arguments(ARG "NO_SIMPLIFY;NO_EOM;PYTHON" "MODEL;VARIANT;PARTIALS;PART_SIZE" "" ${ARGN})
  get_filename_component(model_name ${model_source} NAME_WE)
  get_filename_component(model_path ${model_source} ABSOLUTE)
  set(generator symdyn_generator_${model_name})
  if(NOT TARGET ${generator})
    add_executable(${generator} ${model_path})
    target_link_libraries(${generator} PRIVATE symdyn::generator_main)
    symdyn_set_compile_options(${generator})
  endif()
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
  if(DEFINED ARG_PART_SIZE)
    list(APPEND flags --part-size ${ARG_PART_SIZE} --split-above 0)
  endif()
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/generated/${target})
  add_custom_command(
    OUTPUT ${out_dir}/${target}.hpp ${out_dir}/${target}.cpp
    COMMAND ${generator} --out ${out_dir} ${flags}
    DEPENDS ${generator}
    COMMENT "symdyn: generating ${target} from ${model_name}"
    VERBATIM)
  add_library(${target} STATIC ${out_dir}/${target}.cpp ${out_dir}/${target}.hpp)
  target_include_directories(${target} PUBLIC ${out_dir})
  symdyn_set_compile_options(${target})
  if(NOT ARG_NO_EOM)
    set_property(GLOBAL APPEND PROPERTY SYMDYN_MODELS ${target})
  endif()
  if(ARG_PYTHON)
    symdyn_python_module(${target})
  endif()
endfunction()
