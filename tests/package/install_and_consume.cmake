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
# Configures and builds a project against the installed package, as a robot stack would. A sanitizer build's static
# library needs the sanitizer runtimes in the consumer too.
function(build_against_package source binary what)
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${source}" -B "${binary}" -G Ninja "-DCMAKE_PREFIX_PATH=${prefix}"
                          "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_LINK_FLAGS}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc)
    message(FATAL_ERROR "configuring ${what} failed:\n${out}\n${err}")
  endif()
  execute_process(COMMAND "${CMAKE_COMMAND}" --build "${binary}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc)
    message(FATAL_ERROR "building ${what} failed:\n${out}\n${err}")
  endif()
endfunction()
build_against_package("${SOURCE}" "${WORK}/build" "the consumer")
# A relocated install finds its assets through SVA_ASSETS.
set(ENV{SVA_ASSETS} "${prefix}/share/sva/assets")
execute_process(COMMAND "${WORK}/build/consumer" "${WORK}/data" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(rc)
  message(FATAL_ERROR "the consumer failed: ${rc}")
endif()
# The C++ examples a new user copies (examples/cpp_*), each built against the same installed package and run on the
# map and readings the consumer made (two objects: ball 0, pebble 1). A new example must be added here: the glob
# below fails on one it does not know.
function(run_example name expect)
  get_filename_component(example "${SOURCE}/../../../examples/${name}" ABSOLUTE)
  build_against_package("${example}" "${WORK}/${name}" "examples/${name}")
  execute_process(COMMAND "${WORK}/${name}/${name}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${name}: ${out}${err}")
  if(rc OR NOT out MATCHES "${expect}")
    message(FATAL_ERROR "examples/${name} failed (${rc}) or did not print \"${expect}\"")
  endif()
endfunction()
run_example(cpp_recognize "after 6 readings: pebble" "${WORK}/data/tiny.svam" "${WORK}/data/tiny.svad" 1 6)
run_example(cpp_estimate_cost
            "^6 readings, 2 objects: update [0-9.]+ ms .*; light estimate\\(0\\) [0-9.]+ ms, .*; full estimate\\(3\\) [0-9.]+ ms \\(fine pose (on|not yet)\\); [1-9][0-9]* hypotheses, best pebble"
            "${WORK}/data/tiny.svam" "${WORK}/data/tiny.svad" 6 1)
file(GLOB examples RELATIVE "${SOURCE}/../../../examples" "${SOURCE}/../../../examples/cpp_*")
list(REMOVE_ITEM examples cpp_recognize cpp_estimate_cost)
if(examples)
  message(FATAL_ERROR "examples not run by tests/package/install_and_consume.cmake: ${examples}")
endif()
