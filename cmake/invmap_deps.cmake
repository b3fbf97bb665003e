# Strict dependency lookup: every missing package stops the configure step with
# a message naming the Debian package that provides it. Nothing is downloaded.

macro(invmap_require package debian)
  find_package(${package} ${ARGN} QUIET)
  if(NOT ${package}_FOUND)
    message(FATAL_ERROR "invmap needs ${package}: install the Debian package '${debian}' "
                        "(or run scripts/setup.sh, which installs everything).")
  endif()
endmacro()

invmap_require(Eigen3 libeigen3-dev 3.3 NO_MODULE)
invmap_require(xsimd libxsimd-dev)
invmap_require(TBB libtbb-dev)
invmap_require(embree libembree-dev 3)
invmap_require(nlohmann_json nlohmann-json3-dev)
invmap_require(CLI11 libcli11-dev)
invmap_require(liblzf liblzf-dev)
if(INVMAP_BUILD_TESTS)
  invmap_require(GTest libgtest-dev)
endif()
if(INVMAP_BUILD_BENCH)
  invmap_require(benchmark libbenchmark-dev)
endif()
