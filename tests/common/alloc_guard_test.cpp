#include "tests/common/alloc_guard.h"

#include <gtest/gtest.h>

#include <memory>
#include <thread>
#include <vector>

namespace sulcus::test {
namespace {

// Keeps the optimiser from removing the allocations under test.
template <typename T>
void Escape(T* p) {
  asm volatile("" : : "g"(p) : "memory");
}

TEST(AllocationGuard, CountsNewAndContainerGrowth) {
  AllocationGuard guard;
  auto p = std::make_unique<int>(7);
  Escape(p.get());
  std::vector<double> v;
  v.reserve(100);
  Escape(v.data());
  EXPECT_EQ(guard.allocations(), 2u);
  EXPECT_GE(guard.bytes(), sizeof(int) + 100 * sizeof(double));
}

TEST(AllocationGuard, ZeroForArithmetic) {
  double acc = 0;
  AllocationGuard guard;
  for (int i = 0; i < 1000; ++i) acc += i * 0.5;
  Escape(&acc);
  EXPECT_EQ(guard.allocations(), 0u);
}

TEST(AllocationGuard, IgnoresOtherThreadsAndNests) {
  AllocationGuard outer;
  std::thread t([] {
    auto p = std::make_unique<int>(1);
    Escape(p.get());
  });
  const std::size_t after_spawn = outer.allocations();  // the thread's own state
  t.join();
  {
    AllocationGuard inner;
    auto p = std::make_unique<int>(2);
    Escape(p.get());
    EXPECT_EQ(inner.allocations(), 1u);
  }
  EXPECT_EQ(outer.allocations(), after_spawn + 1);
}

}  // namespace
}  // namespace sulcus::test
