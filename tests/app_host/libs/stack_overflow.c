/* Unbounded recursion with a frame the compiler cannot drop. */
static int Recurse(volatile char* previous) {
  volatile char frame[4096];
  frame[0] = previous != 0 ? previous[0] : 1;
  return Recurse(frame) + frame[1];
}
#define MISBEHAVE(ldmap) (void)Recurse(0)
#include "hostile.h"
