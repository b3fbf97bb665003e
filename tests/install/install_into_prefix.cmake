# ctest install_into_prefix (the fixture of the install tests): `cmake
# --install` of this build into an empty prefix, then checks of what it put
# there: the public headers and nothing internal, the CMake package, the
# command, and a library that exports invmap's public names only.
#
#   cmake -DBUILD_DIR=<build> -DSOURCE_DIR=<source> -DPREFIX=<prefix>
#         -DLIBDIR=<lib> -DBINDIR=<bin> -DNM=<nm> -DVERSION=<x.y.z> -P install_into_prefix.cmake
cmake_minimum_required(VERSION 3.20)

function(fail message)
  message(FATAL_ERROR "install_into_prefix: ${message}")
endfunction()

file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX}
                RESULT_VARIABLE failed OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(failed)
  fail("cmake --install failed:\n${log}")
endif()

# Headers: exactly those of include/invmap/ in the source tree.
file(GLOB_RECURSE installed RELATIVE ${PREFIX}/include ${PREFIX}/include/*)
file(GLOB expected RELATIVE ${SOURCE_DIR}/include ${SOURCE_DIR}/include/invmap/*.h)
list(SORT installed)
list(SORT expected)
if(NOT installed STREQUAL expected)
  fail("installed headers [${installed}], expected [${expected}]")
endif()

foreach(file ${LIBDIR}/cmake/invmap/invmapConfig.cmake ${LIBDIR}/cmake/invmap/invmapConfigVersion.cmake
             ${LIBDIR}/libinvmap.so ${BINDIR}/invmap)
  if(NOT EXISTS ${PREFIX}/${file})
    fail("${file} is not installed")
  endif()
endforeach()

# The command runs from the prefix, with the package's version.
execute_process(COMMAND ${PREFIX}/${BINDIR}/invmap --version
                RESULT_VARIABLE failed OUTPUT_VARIABLE version ERROR_VARIABLE version)
if(failed OR NOT version STREQUAL "invmap ${VERSION}\n")
  fail("${PREFIX}/${BINDIR}/invmap --version: \"${version}\", expected \"invmap ${VERSION}\"")
endif()

# The library's dynamic symbols: functions and data it defines must be
# invmap's public ones (namespace invmap, but not the internal namespaces
# engine, kernels or detail, nor a class's Impl), never TBB's, Embree's,
# Eigen's or the standard library's.
execute_process(COMMAND ${NM} -D --defined-only --demangle ${PREFIX}/${LIBDIR}/libinvmap.so
                RESULT_VARIABLE failed OUTPUT_VARIABLE symbols ERROR_VARIABLE error)
if(failed)
  fail("${NM} failed: ${error}")
endif()
string(REPLACE "\n" ";" symbols "${symbols}")
set(public 0)
foreach(line IN LISTS symbols)
  # "<address> <type> <name>": T/W/V/D/B/R are definitions a program could bind to.
  if(NOT line MATCHES "^[0-9a-f]+ [TWVDBRtwvdbr] (.*)$")
    continue()
  endif()
  set(name "${CMAKE_MATCH_1}")
  if(name MATCHES "^_init$|^_fini$")
    continue()
  endif()
  if(NOT name MATCHES "invmap::" OR name MATCHES "invmap::(engine|kernels|detail)::|::Impl::")
    fail("libinvmap exports an internal or foreign name: ${name}")
  endif()
  math(EXPR public "${public} + 1")
endforeach()
if(public EQUAL 0)
  fail("libinvmap exports no invmap names")
endif()
message(STATUS "installed into ${PREFIX}; libinvmap exports ${public} public names")
