#pragma once
// Lock-free hand-offs between the haptic thread and the rest (docs/architecture.md,
// "Rules the code keeps"): a triple buffer for the latest snapshot, a fixed-capacity
// single-producer / single-consumer ring for events and commands, and a histogram of
// times that another thread can read at any moment. No locks, no allocation after
// construction; every shared word is an atomic, so ThreadSanitizer can check them.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

namespace sulcus {

/// The latest value from one writer to one reader. The writer fills back() and
/// calls Publish(); the reader calls Acquire() and reads front(), which stays
/// untouched by the writer until the reader's next Acquire().
template <class T>
class TripleBuffer {
 public:
  TripleBuffer() : slots_(std::make_unique<T[]>(3)) {}
  explicit TripleBuffer(const T& initial) : TripleBuffer() {
    for (int i = 0; i < 3; ++i) slots_[i] = initial;
  }

  // Writer side.
  T& back() { return slots_[back_]; }
  void Publish() {
    back_ = middle_.exchange(static_cast<std::uint8_t>(back_ | kFresh),
                             std::memory_order_acq_rel) &
            kIndex;
  }

  // Reader side. Returns true when a newer value than the last one was taken.
  bool Acquire() {
    if ((middle_.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    return true;
  }
  const T& front() const { return slots_[front_]; }

 private:
  static constexpr std::uint8_t kFresh = 4, kIndex = 3;
  std::unique_ptr<T[]> slots_;
  std::uint8_t back_ = 0;   // writer's
  std::uint8_t front_ = 1;  // reader's
  std::atomic<std::uint8_t> middle_{2};
};

/// A fixed-capacity ring from one producer thread to one consumer thread.
/// Push fails (and counts a drop) when full; it never waits.
template <class T, std::size_t N>
class SpscRing {
  static_assert(N >= 2 && (N & (N - 1)) == 0, "capacity must be a power of two");

 public:
  SpscRing() : items_(std::make_unique<T[]>(N)) {}

  bool Push(const T& item) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == N) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    items_[head & (N - 1)] = item;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  bool Pop(T* item) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    *item = items_[tail & (N - 1)];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  std::size_t size() const noexcept {
    return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
  }
  static constexpr std::size_t capacity() { return N; }
  std::uint64_t dropped() const noexcept {
    return dropped_.load(std::memory_order_relaxed);
  }

 private:
  std::unique_ptr<T[]> items_;
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
  std::atomic<std::uint64_t> dropped_{0};
};

/// Times in microseconds, 1 us bins up to kMaxUs, the rest in an overflow bin
/// (whose largest value is kept exactly). Written by one thread, read by any.
class TimeHistogram {
 public:
  static constexpr int kMaxUs = 20000;

  TimeHistogram() : bins_(std::make_unique<std::atomic<std::uint32_t>[]>(kMaxUs + 1)) {
    Clear();
  }

  void Add(double us) noexcept {
    if (!(us >= 0)) us = 0;  // NaN or negative (clock step) counts as 0
    const int bin = us >= kMaxUs ? kMaxUs : static_cast<int>(us);
    bins_[bin].fetch_add(1, std::memory_order_relaxed);
    count_.fetch_add(1, std::memory_order_relaxed);
    if (us > max_us_.load(std::memory_order_relaxed))
      max_us_.store(us, std::memory_order_relaxed);
  }

  /// Not while the writer runs.
  void Clear() noexcept {
    for (int i = 0; i <= kMaxUs; ++i) bins_[i].store(0, std::memory_order_relaxed);
    count_.store(0, std::memory_order_relaxed);
    max_us_.store(0, std::memory_order_relaxed);
  }

  std::uint64_t count() const noexcept { return count_.load(std::memory_order_relaxed); }
  double max_us() const noexcept { return max_us_.load(std::memory_order_relaxed); }
  /// Number of values >= us (at 1 us resolution).
  std::uint64_t CountAtLeast(double us) const noexcept;
  /// The p-quantile (0..1), the upper edge of its bin; the maximum in the overflow
  /// bin; 0 when empty.
  double Percentile(double p) const noexcept;

 private:
  std::unique_ptr<std::atomic<std::uint32_t>[]> bins_;
  std::atomic<std::uint64_t> count_{0};
  std::atomic<double> max_us_{0};
};

inline std::uint64_t TimeHistogram::CountAtLeast(double us) const noexcept {
  std::uint64_t n = 0;
  const int from = us <= 0 ? 0 : (us >= kMaxUs ? kMaxUs : static_cast<int>(us));
  for (int i = from; i <= kMaxUs; ++i) n += bins_[i].load(std::memory_order_relaxed);
  return n;
}

inline double TimeHistogram::Percentile(double p) const noexcept {
  std::uint64_t total = 0;
  for (int i = 0; i <= kMaxUs; ++i) total += bins_[i].load(std::memory_order_relaxed);
  if (total == 0) return 0;
  const double want = p * static_cast<double>(total);
  std::uint64_t seen = 0;
  for (int i = 0; i < kMaxUs; ++i) {
    seen += bins_[i].load(std::memory_order_relaxed);
    if (static_cast<double>(seen) >= want && seen > 0)
      return i + 1.0 < max_us() ? i + 1.0 : max_us();
  }
  return max_us();
}

}  // namespace sulcus
