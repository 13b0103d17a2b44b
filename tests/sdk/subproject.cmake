# test_subproject: Annex added with add_subdirectory to a parent project (configure only)
# leaves the build type alone and defines its libraries but no tests, benchmarks,
# fuzzers, editor or reference library. Arguments (-D): SOURCE_DIR WORK_DIR C_COMPILER
# CXX_COMPILER.
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/parent)
file(WRITE ${WORK_DIR}/parent/CMakeLists.txt "
cmake_minimum_required(VERSION 3.25)
project(parent LANGUAGES C CXX)
add_subdirectory(${SOURCE_DIR} annex)
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
execute_process(COMMAND ${CMAKE_COMMAND} -S ${WORK_DIR}/parent -B ${WORK_DIR}/build -G Ninja
                        -DCMAKE_C_COMPILER=${C_COMPILER} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring a parent project failed:\n${out}\n${err}")
endif()
string(FIND "${out}" "subproject: libraries only" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the parent's checks did not run:\n${out}")
endif()
