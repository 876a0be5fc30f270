#include <stdlib.h>
#include <string.h>
/* 1 GB at a time, touched, and never freed: over any sane limit at once. */
static void Hoard(void) {
  for (int i = 0; i < 64; ++i) {
    char* block = malloc((size_t)1 << 30);
    if (block != NULL) memset(block, 1, (size_t)1 << 30);
  }
}
#define MISBEHAVE(ldmap) Hoard()
#include "hostile.h"
