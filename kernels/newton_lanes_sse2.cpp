// The lane kernels compiled for sse2 (see kernels/CMakeLists.txt for the flags).
#include "kernels/newton_lanes_impl.h"

INVMAP_NEWTON_LANES_ISA(Sse2, xsimd::sse2)
