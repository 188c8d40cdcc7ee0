#pragma once
// Counts heap allocations made by the current thread while a guard is alive
// (docs/architecture.md, "Rules the code keeps"; after Drake's LimitMalloc). Linking
// sulcus_test_common replaces the global operator new/delete with counting versions.
//
//   AllocationGuard guard;
//   Step(model, &data);
//   EXPECT_EQ(guard.allocations(), 0);

#include <cstddef>

namespace sulcus::test {

class AllocationGuard {
 public:
  AllocationGuard();
  ~AllocationGuard();
  AllocationGuard(const AllocationGuard&) = delete;
  AllocationGuard& operator=(const AllocationGuard&) = delete;

  /// Allocations (calls of any operator new, or malloc through it) since construction.
  std::size_t allocations() const;
  /// Bytes requested by those allocations.
  std::size_t bytes() const;

 private:
  std::size_t start_count_;
  std::size_t start_bytes_;
  bool was_active_;
};

}  // namespace sulcus::test
