#include <stddef.h>
#include "syrof/app.h"
/* Only robot 2 crashes, in its third new_round. */
static int rounds = 0;
static void MaybeCrash(const syrof_ldmap* ldmap) {
  if (ldmap->self_id == 2 && ++rounds == 3) {
    volatile int* volatile nowhere = NULL;
    *nowhere = 1;
  }
}
#define MISBEHAVE(ldmap) MaybeCrash(ldmap)
#include "hostile.h"
