#include <unistd.h>
/* Sleeps: no CPU time, so only the wall cap stops it. */
static void Doze(void) {
  for (;;) sleep(1);
}
#define MISBEHAVE(ldmap) Doze()
#include "hostile.h"
