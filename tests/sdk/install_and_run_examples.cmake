# test_examples: installs the build into a fresh prefix, then configures, builds and runs
# examples/ against it as an outside project would (only CMAKE_PREFIX_PATH points at
# Annex), checks that the programs link no PCL, VTK, CGAL or OpenNI2 themselves, that
# pkg-config finds the C API, and that the installed Python module imports.
# Arguments (-D): BUILD_DIR SOURCE_DIR WORK_DIR C_COMPILER CXX_COMPILER PYTHON PROJECT_VERSION
# LINK_FLAGS, COMPILE_FLAGS and PRELOAD (the sanitizer's flags and runtime under
# ANNEX_SANITIZE: the examples are then instrumented too, and run under the sanitizer).
cmake_minimum_required(VERSION 3.25)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    list(JOIN ARGN " " cmd)
    message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

function(expect text what)
  string(FIND "${run_output}" "${text}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${what}: '${text}' not in the output:\n${run_output}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

foreach(f include/annex/annex.h include/annex/version.h include/annex/runtime/annex_session.h
          lib/cmake/Annex/AnnexConfig.cmake lib/cmake/Annex/AnnexConfigVersion.cmake
          lib/pkgconfig/annex.pc)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
# Bench- and test-only code stays out of the package.
foreach(f include/annex/reference include/annex/runtime/renderer.h include/annex/formats/mesh_io.h)
  if(EXISTS ${prefix}/${f})
    message(FATAL_ERROR "installed but not part of the package: ${f}")
  endif()
endforeach()

run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${WORK_DIR}/build -G Ninja
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=${C_COMPILER} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    "-DCMAKE_C_FLAGS=${COMPILE_FLAGS}" "-DCMAKE_CXX_FLAGS=${COMPILE_FLAGS}"
    "-DCMAKE_EXE_LINKER_FLAGS=${LINK_FLAGS}")
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
# Under a sanitizer: the examples' own code is instrumented (its checks are in them); a
# report stops a program with a non-zero status (and leaks are checked at exit), which
# fails the runs below.
if(COMPILE_FLAGS)
  foreach(exe annex_example_c annex_example_cpp)
    run(readelf --syms --wide ${WORK_DIR}/build/${exe})
    foreach(check __asan_report_load __ubsan_handle)
      string(FIND "${run_output}" "${check}" at)
      if(at EQUAL -1)
        message(FATAL_ERROR "${exe} is not instrumented (no ${check}*): COMPILE_FLAGS not applied")
      endif()
    endforeach()
  endforeach()
  message(STATUS "examples instrumented with: ${COMPILE_FLAGS}")
endif()

# The programs need libannex_c / libannex, none of the libraries inside them.
foreach(exe annex_example_c annex_example_cpp)
  run(readelf -d ${WORK_DIR}/build/${exe})
  string(REGEX MATCHALL "Shared library: \\[[^]]+\\]" needed "${run_output}")
  message(STATUS "${exe}: ${needed}")
  if(needed MATCHES "pcl|vtk|VTK|CGAL|OpenNI|gmp|boost")
    message(FATAL_ERROR "${exe} links a dependency of Annex itself: ${needed}")
  endif()
endforeach()

set(spec ${SOURCE_DIR}/samples/specs/study.haptic)
file(GLOB frames ${SOURCE_DIR}/samples/recordings/tabletop/frame_*.pcd)
list(SORT frames)
run(${WORK_DIR}/build/annex_example_c ${spec} ${frames})
message(STATUS "annex_example_c:\n${run_output}")
expect("annex ${PROJECT_VERSION} (C ABI" "C example")
foreach(name champagne_bottle lamp)
  expect(" annexed ${name} p" "C example")
  expect("frame 3 ${name} on p" "C example")
endforeach()

run(${WORK_DIR}/build/annex_example_cpp ${spec} ${frames})
message(STATUS "annex_example_cpp:\n${run_output}")
expect("annex ${PROJECT_VERSION} (headers ${PROJECT_VERSION})" "C++ example")
expect("match champagne_bottle p" "C++ example")
expect("frame 3 lamp p" "C++ example")

# pkg-config: the relocatable annex.pc of the prefix compiles and links the C example.
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
run(pkg-config --modversion annex)
string(STRIP "${run_output}" pc_version)
if(NOT pc_version STREQUAL PROJECT_VERSION)
  message(FATAL_ERROR "pkg-config annex: version '${pc_version}', want ${PROJECT_VERSION}")
endif()
run(pkg-config --cflags --libs annex)
separate_arguments(pc_flags UNIX_COMMAND "${run_output}")
separate_arguments(extra_link UNIX_COMMAND "${LINK_FLAGS}")
separate_arguments(extra_compile UNIX_COMMAND "${COMPILE_FLAGS}")
run(${C_COMPILER} -std=c11 ${extra_compile} ${SOURCE_DIR}/examples/annex_example.c ${pc_flags} ${extra_link}
    -Wl,-rpath,${prefix}/lib -o ${WORK_DIR}/annex_example_pkgconfig)
run(${WORK_DIR}/annex_example_pkgconfig ${spec} ${frames})
expect("frame 3 lamp on p" "pkg-config build of the C example")

# The Python module under the prefix.
if(PYTHON)
  set(ENV{PYTHONPATH} ${prefix}/lib/python3/dist-packages)
  if(PRELOAD)  # an instrumented module in an uninstrumented python3
    set(ENV{LD_PRELOAD} ${PRELOAD})
    set(ENV{ASAN_OPTIONS} detect_leaks=0)
  endif()
  run(${PYTHON} -c "print(__import__('annex').__version__, __import__('annex').__file__)")
  expect("${PROJECT_VERSION} ${prefix}/lib/python3/dist-packages/annex" "installed Python module")
endif()
message(STATUS "examples built and run against ${prefix}")
