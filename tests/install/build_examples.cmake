# ctest install_find_package: examples/ configured as a project of its own
# against the installed prefix (find_package(invmap), then invmap::invmap, as
# a user's project would), built and run; each example must link the
# installed libinvmap, not the build tree's.
#
#   cmake -DSOURCE_DIR=<source> -DPREFIX=<prefix> -DLIBDIR=<lib> -DWORK=<dir>
#         -DVERSION=<x.y.z> -DGENERATOR=<generator> -DMAKE_PROGRAM=<make>
#         -DCXX=<compiler> -P build_examples.cmake
cmake_minimum_required(VERSION 3.20)

function(fail message)
  message(FATAL_ERROR "install_find_package: ${message}")
endfunction()

file(REMOVE_RECURSE ${WORK})
execute_process(
  COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${WORK} -G ${GENERATOR}
          -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release
          -DCMAKE_PREFIX_PATH=${PREFIX} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
  RESULT_VARIABLE failed OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(failed)
  fail("configuring examples/ against ${PREFIX} failed:\n${log}")
endif()
set(found "invmap ${VERSION} found in ${PREFIX}/${LIBDIR}/cmake/invmap")
string(FIND "${log}" "${found}" at)
if(at EQUAL -1)
  fail("expected \"${found}\" in the configure output:\n${log}")
endif()

execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK} RESULT_VARIABLE failed OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(failed)
  fail("building examples/ failed:\n${log}")
endif()

file(REAL_PATH ${PREFIX}/${LIBDIR}/libinvmap.so installed)
foreach(example api_example grid_example)
  set(program ${WORK}/invmap_${example})
  file(GET_RUNTIME_DEPENDENCIES EXECUTABLES ${program} RESOLVED_DEPENDENCIES_VAR libraries
       UNRESOLVED_DEPENDENCIES_VAR unresolved)
  set(linked "")
  foreach(library IN LISTS libraries)
    if(library MATCHES "libinvmap\\.so")
      file(REAL_PATH ${library} linked)
    endif()
  endforeach()
  if(NOT linked STREQUAL installed)
    fail("${example} loads libinvmap from \"${linked}\", expected ${installed} (unresolved: ${unresolved})")
  endif()
  execute_process(COMMAND ${program} RESULT_VARIABLE failed OUTPUT_VARIABLE output ERROR_VARIABLE output)
  if(failed)
    fail("${example} failed (${failed}):\n${output}")
  endif()
  message(STATUS "${example}:\n${output}")
endforeach()
