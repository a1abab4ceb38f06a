// tests/support/count_allocations.hpp -- replaces the global operator new and delete of the test
// program that includes it, counting allocations in tetia::testsupport::allocations, so that a
// test can check that a kernel allocates nothing; and failing the allocation whose count is
// tetia::testsupport::fail_allocation (-1: none), so that a test can run out of memory anywhere.
// Include it in exactly one source file of a test program (each tests/test_*.cpp is its own
// program).
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace tetia::testsupport {
inline std::atomic<long> allocations{0};
inline std::atomic<long> fail_allocation{-1};
}

// A replacement operator new may take its memory from malloc and the matching operator delete
// return it with free; GCC's -Wmismatched-new-delete does not see that they are a pair.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
  if (++tetia::testsupport::allocations == tetia::testsupport::fail_allocation.load()) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// The other forms too: a replaced delete is used by every library in the process (Gmsh's
// dependencies allocate with the nothrow and array forms), so all of them must pair up.
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (++tetia::testsupport::allocations == tetia::testsupport::fail_allocation.load()) return nullptr;
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
#pragma GCC diagnostic pop
