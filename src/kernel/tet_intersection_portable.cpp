// src/kernel/tet_intersection_portable.cpp -- the 3D kernel's entry points compiled with their
// portable scalar code (-U__SSE2__: every TETIA_KERNEL_SSE2 branch takes its other side), for
// tests/test_kernel_variants.cpp only, which compares them with the baseline bit for bit. The
// library never calls them: on x86-64 it runs the SSE2 code, and this is the code every other
// architecture runs. Nothing but entry_points.hpp may be defined here (tests/CMakeLists.txt
// checks it, as for the x86-64-v3 variant).
#define TETIA_KERNEL_VARIANT portable
#define TETIA_KERNEL_VARIANT_NAME "portable"
#include "entry_points.hpp"
