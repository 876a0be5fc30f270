#include <stddef.h>
__attribute__((constructor)) static void CrashOnLoad(void) {
  volatile int* volatile nowhere = NULL;
  *nowhere = 1;
}
#define MISBEHAVE(ldmap) (void)0
#include "hostile.h"
