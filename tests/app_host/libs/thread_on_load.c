/* A constructor that starts a thread: a fork copies only the forking
 * thread, so a held host must never have one. The loader's filter refuses
 * the clone3 (and clone) pthread_create makes. */
#include <pthread.h>

static void* Spin(void* unused) {
  for (;;) (void)unused;
  return 0;
}

__attribute__((constructor)) static void StartThread(void) {
  pthread_t thread;
  (void)pthread_create(&thread, 0, Spin, 0);
}
#define MISBEHAVE(ldmap) (void)0
#include "hostile.h"
