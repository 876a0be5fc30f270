/* A constructor that reads files outside the library's folder while the
 * loader's filter still allows read-only opens: a canary beside the test
 * libraries' folder, the machine's accounts, its own environment. Landlock
 * confines the load stage to the library's and the system's library
 * folders, so each open fails; the app then behaves. */
#include <errno.h>
#include <stdio.h>
#include <string.h>

static void TryToRead(const char* path) {
  FILE* file = fopen(path, "r");
  if (file == NULL) {
    printf("cannot read %s: %s\n", path, strerror(errno));
    return;
  }
  char line[256] = {0};
  if (fgets(line, sizeof line, file) != NULL) printf("read %s: %s\n", path, line);
  fclose(file);
}

__attribute__((constructor)) static void ReadOnLoad(void) {
  TryToRead(SYROF_TEST_CANARY_FILE);
  TryToRead("/etc/passwd");
  TryToRead("/proc/self/environ");
  fflush(stdout);
}

#define MISBEHAVE(ldmap) (void)0
#include "hostile.h"
