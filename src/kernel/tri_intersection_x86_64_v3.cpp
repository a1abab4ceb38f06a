// src/kernel/tri_intersection_x86_64_v3.cpp -- the 2D kernel compiled for x86-64-v3 without FMA
// (CMakeLists.txt), called where the CPU runs it (kernel_variant.hpp): the same numbers as the
// baseline's, bit for bit. Nothing but tri_kernel.hpp may be defined here (the build checks it).
#define TETIA_KERNEL_VARIANT x86_64_v3
#include "tri_kernel.hpp"
