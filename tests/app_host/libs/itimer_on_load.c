/* A constructor that sets an interval timer (its SIGALRM would end a copy
 * a while into its run). The loader's filter refuses setitimer; a fork
 * would not copy the timer either. */
#include <sys/time.h>

__attribute__((constructor)) static void SetTimer(void) {
  struct itimerval every = {{0, 50000}, {0, 50000}};
  (void)setitimer(ITIMER_REAL, &every, 0);
}
#define MISBEHAVE(ldmap) (void)0
#include "hostile.h"
