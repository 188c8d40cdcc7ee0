#include "tests/common/alloc_guard.h"

#include <cstdlib>
#include <new>

namespace {

// Thread-local so that other threads (gtest, a haptic thread) do not disturb the
// count of the thread under test.
thread_local std::size_t t_count = 0;
thread_local std::size_t t_bytes = 0;
thread_local bool t_active = false;

void* CountedAlloc(std::size_t size, std::size_t align) {
  if (t_active) {
    ++t_count;
    t_bytes += size;
  }
  if (size == 0) size = 1;
  void* p = align > alignof(std::max_align_t)
                ? std::aligned_alloc(align, (size + align - 1) / align * align)
                : std::malloc(size);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

void* operator new(std::size_t n) { return CountedAlloc(n, 0); }
void* operator new[](std::size_t n) { return CountedAlloc(n, 0); }
void* operator new(std::size_t n, std::align_val_t a) {
  return CountedAlloc(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return CountedAlloc(n, static_cast<std::size_t>(a));
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return CountedAlloc(n, 0);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return CountedAlloc(n, 0);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace sulcus::test {

AllocationGuard::AllocationGuard()
    : start_count_(t_count), start_bytes_(t_bytes), was_active_(t_active) {
  t_active = true;
}

AllocationGuard::~AllocationGuard() { t_active = was_active_; }

std::size_t AllocationGuard::allocations() const { return t_count - start_count_; }
std::size_t AllocationGuard::bytes() const { return t_bytes - start_bytes_; }

}  // namespace sulcus::test
