// src/kernel/kernel_variant.hpp -- the kernels compiled for more than one instruction set,
// and the choice among them at run time (internal to the library).
//
// The library must run on any x86-64 (SSE2), yet the 3D kernel is 7-10 % faster compiled for
// x86-64-v3 (AVX2, BMI1/2, LZCNT; docs/benchmarks.md): its code is mostly scalar, and gains from
// the three-operand VEX encodings and BMI's bit operations more than from the wider vectors of
// its map and lane operations (TETIA_KERNEL_AVX, barycentric_map.hpp). So
// its entry points (entry_points.hpp) and the 2D kernel (tri_kernel.hpp) are compiled twice, and
// the public functions (tetia/tet_intersection.hpp, tetia/tri_intersection.hpp) and OneToMany
// call the variant chosen once, when the library is loaded: x86-64-v3 where the CPU (and the
// operating system, for the AVX state) supports it, the baseline otherwise, or as the
// environment variable TETIA_KERNEL_VARIANT asks ("baseline" or "x86-64-v3"; a variant this CPU
// cannot run, or any other value, is not taken: the automatic choice stands). Every variant
// computes the same numbers bit for bit (entry_points.hpp), so the choice changes the speed only.
//
// Contract: kernel_variant() is the chosen variant (thread-safe; chosen when the library is
// loaded, or by the first call if that comes earlier, and fixed for the life of the process);
// kernel_variants() lists every variant this CPU can run, the baseline first (the tests compare
// them). Where the library was built without the x86-64-v3 variant (another architecture, a
// compiler without the flags, or -DTETIA_KERNEL_VARIANTS=OFF) the baseline is the only one.
#pragma once

#include <atomic>
#include <vector>

#include "tetia/geometry.hpp"
#include "tetia/polyhedron.hpp"
#include "tetia/tet_intersection.hpp"
#include "tetia/tri_intersection.hpp"

namespace tetia::detail {

struct Conditioning;
class OneToMany;

/// One compilation of the kernel's entry points.
struct KernelVariant {
  const char* name;  // "baseline", "x86-64-v3"
  double (*volume)(const Tet& U, const Tet& V);                             // intersection_volume
  Moments (*moments)(const Tet& U, const Tet& V);                           // intersection_moments
  Polyhedron (*intersect)(const Tet& U, const Tet& V, IntersectionStats* stats);  // intersect
  Moments (*one_to_many_moments)(const OneToMany& s, const Tet& t, const Conditioning& ct, unsigned* t_faces);
  Moments (*one_to_many_intersect)(const OneToMany& s, const Tet& t, const Conditioning& ct, Polyhedron& out,
                                   unsigned* t_faces);
  // The 2D kernel (src/kernel/tri_kernel.hpp).
  double (*tri_area)(const Triangle& A, const Triangle& B);                               // intersection_area
  Moments2 (*tri_moments)(const Triangle& A, const Triangle& B);                          // intersection_moments
  Polygon (*tri_intersect)(const Triangle& A, const Triangle& B, TriIntersectionStats* stats);  // intersect
};

namespace baseline {
extern const KernelVariant variant;
}
#if defined(TETIA_KERNEL_X86_64_V3)
namespace x86_64_v3 {
extern const KernelVariant variant;
}
#endif

/// The chosen variant, set when the library is loaded (null before).
extern std::atomic<const KernelVariant*> chosen_kernel_variant;
/// Chooses (CPUID, TETIA_KERNEL_VARIANT), sets chosen_kernel_variant, returns the choice.
const KernelVariant& choose_kernel_variant();

/// The variant the entry points call: a load and a test, so that an entry point is a jump.
inline const KernelVariant& kernel_variant() {
  const KernelVariant* v = chosen_kernel_variant.load(std::memory_order_relaxed);
  return v != nullptr ? *v : choose_kernel_variant();
}
/// Every variant this CPU can run, the baseline first.
std::vector<const KernelVariant*> kernel_variants();

}  // namespace tetia::detail
