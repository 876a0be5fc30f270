#include <stdio.h>
/* The test checks this file does not exist afterwards. */
static void Write(void) {
  FILE* file = fopen(SYROF_TEST_WRITTEN_FILE, "w");
  if (file != NULL) {
    fputs("escaped\n", file);
    fclose(file);
  }
}
#define MISBEHAVE(ldmap) Write()
#include "hostile.h"
