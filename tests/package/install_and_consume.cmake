# Installs the build tree into a temporary prefix, then configures, builds and
# runs a consumer project against it: the installable CMake package works.
set(prefix "${WORK}/prefix")
file(REMOVE_RECURSE "${WORK}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${prefix}" RESULT_VARIABLE rc OUTPUT_QUIET)
if(rc)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
# Benchmark-only kernels (bench/roofline) are never part of the package.
file(GLOB_RECURSE installed RELATIVE "${prefix}" "${prefix}/*")
foreach(f ${installed})
  if(f MATCHES "roofline|hash_scatter|fixed_point_scatter|sva_bench")
    message(FATAL_ERROR "the package ships a benchmark-only file: ${f}")
  endif()
endforeach()
# A sanitizer build's static library needs the sanitizer runtimes in the consumer too.
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${WORK}/build" -G Ninja "-DCMAKE_PREFIX_PATH=${prefix}"
                        "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_LINK_FLAGS}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "configuring the consumer failed:\n${out}\n${err}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK}/build" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "building the consumer failed:\n${out}\n${err}")
endif()
# A relocated install finds its assets through SVA_ASSETS.
set(ENV{SVA_ASSETS} "${prefix}/share/sva/assets")
execute_process(COMMAND "${WORK}/build/consumer" "${WORK}/data" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(rc)
  message(FATAL_ERROR "the consumer failed: ${rc}")
endif()
# The example a new user copies (examples/cpp_recognize), built against the same installed package and run on
# the map and readings the consumer made.
get_filename_component(example "${SOURCE}/../../../examples/cpp_recognize" ABSOLUTE)
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${example}" -B "${WORK}/example" -G Ninja "-DCMAKE_PREFIX_PATH=${prefix}"
                        "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_LINK_FLAGS}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "configuring examples/cpp_recognize failed:\n${out}\n${err}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK}/example" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc)
  message(FATAL_ERROR "building examples/cpp_recognize failed:\n${out}\n${err}")
endif()
execute_process(COMMAND "${WORK}/example/cpp_recognize" "${WORK}/data/tiny.svam" "${WORK}/data/tiny.svad" 1 6
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(rc OR NOT out MATCHES "after 6 readings: pebble")
  message(FATAL_ERROR "examples/cpp_recognize failed (${rc}) or did not recognise the pebble after 6 readings")
endif()
