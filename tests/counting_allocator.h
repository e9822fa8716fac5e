#pragma once
// A counting global operator new for the allocation tests. Include it in exactly one file of
// a test executable of its own (the replacement affects the whole program). Every allocation
// while pwsim_test::g_counting is true adds one to pwsim_test::g_allocations.

#include <atomic>
#include <cstdlib>
#include <new>

namespace pwsim_test {
inline std::atomic<bool> g_counting{true};
inline std::atomic<long> g_allocations{0};
}  // namespace pwsim_test

void* operator new(std::size_t size) {
  if (pwsim_test::g_counting.load(std::memory_order_relaxed)) ++pwsim_test::g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
