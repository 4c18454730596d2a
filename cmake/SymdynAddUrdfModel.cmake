# symdyn_add_urdf_model(<target> <robot.urdf> [FLOATING_BASE] [GRAVITY gx gy gz]
#                       [PARTIALS numeric|symbolic] [NO_SIMPLIFY] [NO_EOM] [PART_SIZE n]
#                       [SOURCES n])
#
# The URDF counterpart of symdyn_add_model (docs/urdf.md): runs symdyn-urdf on
# the file at build time, whenever the file or the generator changes, and makes
# <target> a static library of the emitted code:
#
#   symdyn_add_urdf_model(my_arm robots/my_arm.urdf)
#   target_link_libraries(my_simulation PRIVATE my_arm symdyn::runtime)
#
# The emitted header is <target>.hpp; the struct inside is symdyn_generated::<target>.
# SOURCES and the flags of the emitted code as in symdyn_add_model. Like
# symdyn_add_model, a target with equations of motion joins the global
# property SYMDYN_MODELS (tests/simulation checks each of them).
function(symdyn_add_urdf_model target urdf_file)
  cmake_parse_arguments(ARG "FLOATING_BASE;NO_SIMPLIFY;NO_EOM" "PARTIALS;PART_SIZE;SOURCES" "GRAVITY" ${ARGN})
  get_filename_component(urdf_path ${urdf_file} ABSOLUTE)
  set(flags --urdf ${urdf_path} --basename ${target})
  if(ARG_FLOATING_BASE)
    list(APPEND flags --floating-base)
  endif()
  if(ARG_GRAVITY)
    list(APPEND flags --gravity ${ARG_GRAVITY})
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
  if(NOT ARG_SOURCES)
    symdyn_emitted_code_defaults()
    set(ARG_SOURCES ${SYMDYN_EMITTED_CODE_SOURCES})
  endif()
  list(APPEND flags --sources ${ARG_SOURCES})
  set(out_dir ${CMAKE_CURRENT_BINARY_DIR}/generated/${target})
  symdyn_emitted_sources(sources ${out_dir} ${target} ${ARG_SOURCES})
  add_custom_command(
    OUTPUT ${out_dir}/${target}.hpp ${sources}
    COMMAND symdyn-urdf --out ${out_dir} ${flags}
    DEPENDS symdyn-urdf ${urdf_path}
    COMMENT "symdyn: generating ${target} from ${urdf_file}"
    VERBATIM)
  add_library(${target} STATIC ${sources} ${out_dir}/${target}.hpp)
  set_target_properties(${target} PROPERTIES SYMDYN_EMITTED_SOURCES "${sources}")
  target_include_directories(${target} PUBLIC ${out_dir})
  symdyn_set_compile_options(${target})
  if(NOT ARG_NO_EOM)
    set_property(GLOBAL APPEND PROPERTY SYMDYN_MODELS ${target})
  endif()
endfunction()
