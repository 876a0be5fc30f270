#include <stddef.h>
static void Crash(void) {
  volatile int* volatile nowhere = NULL;
  *nowhere = 1;
}
#define MISBEHAVE(ldmap) Crash()
#include "hostile.h"
