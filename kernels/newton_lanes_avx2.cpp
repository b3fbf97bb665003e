// The lane kernels compiled for avx2 (see kernels/CMakeLists.txt for the flags).
#include "kernels/newton_lanes_impl.h"

INVMAP_NEWTON_LANES_ISA(Avx2, xsimd::avx2)
