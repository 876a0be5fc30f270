#include <string.h>
#include <unistd.h>
/* 400 MB to stdout, 64 KB at a time. */
static void Flood(void) {
  static char block[65536];
  memset(block, 'x', sizeof block);
  for (int i = 0; i < 6400; ++i) {
    if (write(1, block, sizeof block) < 0) return;
  }
}
#define MISBEHAVE(ldmap) Flood()
#include "hostile.h"
