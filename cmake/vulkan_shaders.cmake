# Build-time SPIR-V: every shaders/<name>.comp is compiled by glslangValidator (Vulkan 1.1 target),
# validated by spirv-val, and embedded as a uint32_t array in a generated header
#   ${CMAKE_BINARY_DIR}/generated/shaders/<name>.spv.h   ->   const uint32_t k<Name>Spv[] = {...};
# (e.g. kNmsEdgeSignSpv, kHysteresisRmwSpv). No shader compiler is needed at run time.
#
#   include(cmake/vulkan_shaders.cmake)
#   ellipsekit_embed_vulkan_shaders(<target> <shader folder>...)
# embeds every *.comp file of the named folders (found again at build time, so a shader added,
# renamed or fused away needs no list edited), adds the headers to <target> (so they are generated
# before it compiles) and puts ${CMAKE_BINARY_DIR}/generated on its private include path:
# #include "shaders/nms_edge_sign.spv.h". (A .comp file named instead of a folder stands for its folder.)
# Sets ELLIPSEKIT_VULKAN_SHADER_TOOLS_FOUND in the caller's scope.
find_program(ELLIPSEKIT_GLSLANG_VALIDATOR NAMES glslangValidator glslang)
find_program(ELLIPSEKIT_SPIRV_VAL NAMES spirv-val)
if(ELLIPSEKIT_GLSLANG_VALIDATOR AND ELLIPSEKIT_SPIRV_VAL)
  set(ELLIPSEKIT_VULKAN_SHADER_TOOLS_FOUND TRUE)
else()
  set(ELLIPSEKIT_VULKAN_SHADER_TOOLS_FOUND FALSE)
endif()

function(ellipsekit_embed_vulkan_shaders target)
  if(NOT ELLIPSEKIT_VULKAN_SHADER_TOOLS_FOUND)
    message(FATAL_ERROR "Vulkan shaders need glslangValidator and spirv-val (Debian: glslang-tools, spirv-tools)")
  endif()
  set(out_dir ${CMAKE_BINARY_DIR}/generated/shaders)
  file(MAKE_DIRECTORY ${out_dir})
  set(dirs)
  foreach(arg ${ARGN})
    get_filename_component(abs ${arg} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
    if(NOT IS_DIRECTORY ${abs})
      get_filename_component(abs ${abs} DIRECTORY)
    endif()
    list(APPEND dirs ${abs})
  endforeach()
  list(REMOVE_DUPLICATES dirs)
  set(sources)
  foreach(dir ${dirs})
    file(GLOB found CONFIGURE_DEPENDS ${dir}/*.comp)
    list(APPEND sources ${found})
  endforeach()
  list(SORT sources)
  set(headers)
  foreach(abs ${sources})
    get_filename_component(name ${abs} NAME_WE)
    # snake_case -> kCamelCaseSpv
    string(REPLACE "_" ";" parts ${name})
    set(var "k")
    foreach(p ${parts})
      string(SUBSTRING ${p} 0 1 head)
      string(SUBSTRING ${p} 1 -1 tail)
      string(TOUPPER ${head} head)
      string(APPEND var "${head}${tail}")
    endforeach()
    string(APPEND var "Spv")
    # Files a shader #includes (GL_GOOGLE_include_directive) are the .glsl files beside it.
    get_filename_component(src_dir ${abs} DIRECTORY)
    file(GLOB includes CONFIGURE_DEPENDS ${src_dir}/*.glsl)
    set(spv ${out_dir}/${name}.spv)
    set(header ${out_dir}/${name}.spv.h)
    add_custom_command(
      OUTPUT ${header} ${spv}
      COMMAND ${ELLIPSEKIT_GLSLANG_VALIDATOR} -V --target-env vulkan1.1 -o ${spv} ${abs}
      COMMAND ${ELLIPSEKIT_SPIRV_VAL} --target-env vulkan1.1 ${spv}
      COMMAND ${ELLIPSEKIT_GLSLANG_VALIDATOR} -V --target-env vulkan1.1 --vn ${var} -o ${header} ${abs}
      DEPENDS ${abs} ${includes}
      COMMENT "SPIR-V ${name}.comp -> ${name}.spv.h (${var}), validated"
      VERBATIM)
    list(APPEND headers ${header})
  endforeach()
  target_sources(${target} PRIVATE ${headers})
  target_include_directories(${target} PRIVATE ${CMAKE_BINARY_DIR}/generated)
endfunction()
