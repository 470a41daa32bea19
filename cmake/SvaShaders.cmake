# sva_add_shaders(TARGET SOURCES...): compiles each compute shader to SPIR-V in
# the build tree (never the source tree) and embeds it as a uint32_t array
# (sva_spirv_embed, after decorating every float operation NoContraction: see
# shaders/tools/spirv_embed.cpp) as sva_spv_<name> in <build>/generated/spv/<name>.h.
# TARGET is an INTERFACE library whose users include "spv/<name>.h"; the
# shaders include the shared headers of shaders/include.
function(sva_add_shaders target)
  set(spv_dir ${CMAKE_CURRENT_BINARY_DIR}/generated)
  set(headers)
  foreach(src ${ARGN})
    get_filename_component(name ${src} NAME_WE)
    set(out ${spv_dir}/spv/${name}.h)
    set(spv ${spv_dir}/spv/${name}.spv)
    add_custom_command(
      OUTPUT ${spv}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${spv_dir}/spv
      COMMAND ${SVA_GLSLANG} -V --target-env vulkan1.2 -I${PROJECT_SOURCE_DIR}/shaders/include
              --depfile ${spv}.d -o ${spv} ${src}
      DEPENDS ${src}
      DEPFILE ${spv}.d
      COMMENT "GLSL -> SPIR-V ${name}.comp"
      VERBATIM)
    add_custom_command(
      OUTPUT ${out}
      COMMAND sva_spirv_embed ${spv} ${out} sva_spv_${name}
      DEPENDS ${spv} sva_spirv_embed
      COMMENT "SPIR-V -> ${name}.h (NoContraction everywhere)"
      VERBATIM)
    list(APPEND headers ${out})
  endforeach()
  add_custom_target(${target}_spirv DEPENDS ${headers})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_spirv)
  target_include_directories(${target} INTERFACE
    $<BUILD_INTERFACE:${spv_dir}>
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/shaders/include>)
endfunction()
