static void Spin(void) {
  volatile unsigned long counter = 0;
  for (;;) ++counter;
}
#define MISBEHAVE(ldmap) Spin()
#include "hostile.h"
