#define _GNU_SOURCE
/* A constructor that makes the very clone a held host makes its copies
 * with (CLONE_PARENT), the one a held host's loader filter lets through,
 * and leaves the process running (sleeping: the filter lets that through).
 * A plain host's filter refuses the clone (forbidden_syscall); the fork
 * server finds the process in the held host's group, kills it and starts
 * fresh hosts, which refuse it the same. */
#include <time.h>
#include <errno.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/syscall.h>
#include <unistd.h>

__attribute__((constructor)) static void CloneOnLoad(void) {
  const long made = syscall(SYS_clone, CLONE_PARENT, 0, 0, 0, 0);
  if (made == 0) {
    for (;;) {
      struct timespec second = {1, 0};
      nanosleep(&second, 0);
    }
  }
  if (made > 0) {
    printf("made process %ld\n", made);
  } else {
    printf("clone refused: %s\n", strerror(errno));
  }
}
#define MISBEHAVE(ldmap) (void)0
#include "hostile.h"
