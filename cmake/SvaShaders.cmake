# sva_add_shaders(TARGET SOURCES...): compiles each compute shader to SPIR-V in
# the build tree (never the source tree) and embeds it as a uint32_t array
# (glslangValidator --vn sva_spv_<name>) in <build>/generated/spv/<name>.h.
# TARGET is an INTERFACE library whose users include "spv/<name>.h"; the
# shaders include the shared headers of shaders/include.
function(sva_add_shaders target)
  set(spv_dir ${CMAKE_CURRENT_BINARY_DIR}/generated)
  set(headers)
  foreach(src ${ARGN})
    get_filename_component(name ${src} NAME_WE)
    set(out ${spv_dir}/spv/${name}.h)
    add_custom_command(
      OUTPUT ${out}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${spv_dir}/spv
      COMMAND ${SVA_GLSLANG} -V --target-env vulkan1.2 -I${PROJECT_SOURCE_DIR}/shaders/include
              --vn sva_spv_${name} --depfile ${out}.d -o ${out} ${src}
      DEPENDS ${src}
      DEPFILE ${out}.d
      COMMENT "GLSL -> SPIR-V ${name}.comp"
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
