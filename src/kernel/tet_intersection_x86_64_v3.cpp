// src/kernel/tet_intersection_x86_64_v3.cpp -- the 3D kernel's entry points compiled for
// x86-64-v3 without FMA (CMakeLists.txt), called where the CPU runs them
// (kernel_variant.hpp): the same numbers as the baseline's, bit for bit, about 10 % sooner.
// Nothing but entry_points.hpp may be defined here: every function this object file defines
// must be this variant's own (entry_points.hpp, "Linkage"; the build checks it).
#define TETIA_KERNEL_VARIANT x86_64_v3
#define TETIA_KERNEL_VARIANT_NAME "x86-64-v3"
#include "entry_points.hpp"
