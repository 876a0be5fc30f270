/* A newRound whose time goes to the kernel, not to the app's own code: for
 * 300 ms of wall time it maps 32 MB with MAP_POPULATE (the kernel zeroes
 * every page inside the one call) and unmaps them again, as a machine short
 * of memory makes the kernel work on a process's behalf in a page fault.
 * Its user time stays far below a 50 ms budget (measured as a program:
 * user 0.00 s, system 0.21 s). */
#include <stddef.h>
#include <sys/mman.h>
#include <time.h>

static long long NowMs(void) {
  struct timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  return (long long)now.tv_sec * 1000 + now.tv_nsec / 1000000;
}

static void FaultPages(void) {
  const size_t size = (size_t)32 << 20;
  const long long end = NowMs() + 300;
  while (NowMs() < end) {
    void* pages = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_POPULATE, -1, 0);
    if (pages == MAP_FAILED) return;
    munmap(pages, size);
  }
}
#define MISBEHAVE(ldmap) ((void)(ldmap), FaultPages())
#include "hostile.h"
