// Checks the board's cycle counter on qemu: counts that match a loop of known
// length, a second measurement of the same loop within one tick of the first,
// and no jump across SysTick wrap-arounds. Prints the counts; CTest runs the
// image twice and requires identical output (determinism under -icount).
// Exits non-zero on the first failed check.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>

#include "syrof/board/cycles.h"

namespace {

using syrof::board::cycle_counter_read;
using syrof::board::cycle_counter_start;
using syrof::board::kCycleCounterResolution;

// Two instructions per iteration (subtract, branch), whatever the optimizer.
void spin(std::uint32_t iterations) {
  asm volatile(
      "1: subs %0, %0, #1\n\t"
      "bne 1b"
      : "+r"(iterations)
      :
      : "cc");
}

std::uint64_t measure_spin(std::uint32_t iterations) {
  const std::uint64_t begin = cycle_counter_read();
  spin(iterations);
  return cycle_counter_read() - begin;
}

int failures = 0;

void expect(bool condition, const char* what, unsigned long long value) {
  if (!condition) {
    std::printf("FAILED: %s (got %llu)\n", what, value);
    ++failures;
  }
}

std::uint64_t distance(std::uint64_t a, std::uint64_t b) { return a > b ? a - b : b - a; }

}  // namespace

int main() {
  cycle_counter_start();

  // A loop of 2 * n instructions reads 2 * n, give or take a tick at each end
  // and the reads themselves (a few hundred instructions in a Debug build).
  constexpr std::uint64_t kTolerance = 10 * kCycleCounterResolution;
  for (const std::uint32_t iterations : {1'000u, 100'000u, 10'000'000u}) {
    const std::uint64_t first = measure_spin(iterations);
    const std::uint64_t second = measure_spin(iterations);
    std::printf("spin %lu: %llu cycles, again %llu\n", static_cast<unsigned long>(iterations),
                static_cast<unsigned long long>(first), static_cast<unsigned long long>(second));
    expect(distance(first, 2ull * iterations) <= kTolerance, "count matches the loop length", first);
    expect(distance(first, second) <= kCycleCounterResolution, "the same loop measures the same", second);
  }

  // Read continuously across the first wrap-around of SysTick (2^24 ticks): a
  // lost or doubled period would show as a jump or a step backwards. Reads are
  // slow under -icount (each ends a translation block), so spin up to just
  // before the wrap-around first.
  constexpr std::uint64_t kWrap = (std::uint64_t{1} << 24) * kCycleCounterResolution;
  constexpr std::uint64_t kWindow = 1'000'000;
  spin(static_cast<std::uint32_t>((kWrap - kWindow - cycle_counter_read()) / 2));
  std::uint64_t previous = cycle_counter_read();
  const std::uint64_t window_start = previous;
  std::uint64_t largest_step = 0;
  while (previous < kWrap + kWindow) {
    const std::uint64_t now = cycle_counter_read();
    expect(now >= previous, "non-decreasing across a wrap-around", now);
    if (now < previous) break;
    if (now - previous > largest_step) largest_step = now - previous;
    previous = now;
  }
  std::printf("read from %llu to %llu cycles across the wrap-around at %llu, largest step %llu\n",
              static_cast<unsigned long long>(window_start), static_cast<unsigned long long>(previous),
              static_cast<unsigned long long>(kWrap), static_cast<unsigned long long>(largest_step));
  expect(window_start < kWrap, "the reads start before the wrap-around", window_start);
  // A lost or doubled period would be a step of 2^24 ticks.
  expect(largest_step <= kTolerance, "no jump across a wrap-around", largest_step);

  std::printf(failures == 0 ? "cycle counter: OK\n" : "cycle counter: %d checks FAILED\n", failures);
  return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
