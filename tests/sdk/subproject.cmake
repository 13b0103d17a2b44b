# test_subproject: Annex added with add_subdirectory to a parent project (configure only)
# leaves the build type alone and defines its libraries but no tests, benchmarks,
# fuzzers, editor or reference library. Arguments (-D): SOURCE_DIR WORK_DIR C_COMPILER
# CXX_COMPILER SANITIZE (the build's ANNEX_SANITIZE). Under a sanitizer the parent
# configures Annex with the same ANNEX_SANITIZE, builds Annex's spec reader (annex_formats,
# annex_common: the libraries build fast, the runtime would take many minutes) and a
# program of the parent's on it, checks that the program carries the sanitizer's
# runtime (the link flags reach a parent's executable) and runs it on a good and a bad
# spec under the sanitizer.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/parent)
file(WRITE ${WORK_DIR}/parent/read_spec.cpp [=[
// A parent project's program on Annex's spec reader: prints the objects or the error.
#include <cstdio>

#include "annex/formats/haptic_format.h"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const annex::Result<annex::HapticSpec> spec = annex::read_haptic_file(argv[1]);
  if (!spec) {
    std::printf("%s\n", spec.error().format().c_str());
    return 1;
  }
  for (const annex::VirtualObject& o : spec->objects) std::printf("object %s\n", o.name.c_str());
  return 0;
}
]=])
file(WRITE ${WORK_DIR}/parent/CMakeLists.txt "
cmake_minimum_required(VERSION 3.25)
project(parent LANGUAGES C CXX)
add_subdirectory(${SOURCE_DIR} annex)
if(ANNEX_SANITIZE)
  add_executable(read_spec read_spec.cpp)
  target_link_libraries(read_spec PRIVATE annex::formats)
  set_target_properties(read_spec PROPERTIES CXX_STANDARD 20 CXX_STANDARD_REQUIRED ON)
endif()
foreach(t annex annex_c annex_runtime annex_formats annex_common)
  if(NOT TARGET \${t})
    message(FATAL_ERROR \"subproject: no target \${t}\")
  endif()
endforeach()
foreach(t annex-bench annex-bench-scan test_c_api test_runtime_tracking fuzz_haptic annex-author
          annex_reference annex_python)
  if(TARGET \${t})
    message(FATAL_ERROR \"subproject: builds \${t}\")
  endif()
endforeach()
if(CMAKE_BUILD_TYPE)
  message(FATAL_ERROR \"subproject: the build type was set to '\${CMAKE_BUILD_TYPE}'\")
endif()
message(STATUS \"subproject: libraries only, build type untouched\")
")
set(sanitize_arg "")
if(SANITIZE)
  set(sanitize_arg -DANNEX_SANITIZE=${SANITIZE})
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${WORK_DIR}/parent -B ${WORK_DIR}/build -G Ninja
                        -DCMAKE_C_COMPILER=${C_COMPILER} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
                        ${sanitize_arg}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring a parent project failed:\n${out}\n${err}")
endif()
string(FIND "${out}" "subproject: libraries only" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the parent's checks did not run:\n${out}")
endif()

if(NOT SANITIZE)
  return()
endif()
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(run_rc "${rc}" PARENT_SCOPE)
  set(run_output "${out}${err}" PARENT_SCOPE)
endfunction()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build --target read_spec)
if(NOT run_rc EQUAL 0)
  message(FATAL_ERROR "building the parent's program failed:\n${run_output}")
endif()
set(exe ${WORK_DIR}/build/read_spec)
run(readelf --syms --wide ${exe})
if(SANITIZE STREQUAL "thread")
  set(runtime_symbols __tsan_init)
else()
  set(runtime_symbols __asan_init __ubsan_handle)
endif()
foreach(symbol ${runtime_symbols})
  string(FIND "${run_output}" "${symbol}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the parent's program lacks ${symbol}: ANNEX_SANITIZE=${SANITIZE} did not reach it")
  endif()
endforeach()
run(${exe} ${SOURCE_DIR}/samples/specs/study.haptic)
if(NOT run_rc EQUAL 0 OR NOT run_output MATCHES "object champagne_bottle")
  message(FATAL_ERROR "the parent's program on study.haptic (${run_rc}):\n${run_output}")
endif()
file(WRITE ${WORK_DIR}/bad.haptic "annex-haptic 1\nobject cup\n  primitive body cylinder\n    radius x\n")
run(${exe} ${WORK_DIR}/bad.haptic)
if(NOT run_rc EQUAL 1 OR NOT run_output MATCHES "bad.haptic:4:")
  message(FATAL_ERROR "the parent's program on a bad spec (${run_rc}, want 1 and a located error):\n${run_output}")
endif()
message(STATUS "subproject: Annex's reader and the parent's program ran under ANNEX_SANITIZE=${SANITIZE}")
