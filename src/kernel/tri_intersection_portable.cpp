// src/kernel/tri_intersection_portable.cpp -- the 2D kernel in the portable variant of
// tet_intersection_portable.cpp (for tests/test_kernel_variants.cpp only), which names these
// entry points. The 2D kernel has no SSE2 branch, so this is the baseline's code compiled once
// more. Nothing but tri_kernel.hpp may be defined here.
#define TETIA_KERNEL_VARIANT portable
#include "tri_kernel.hpp"
