/* A constructor that looks for what it was not handed: every descriptor the
 * host might have inherited (read with pread, which needs no open), a file
 * below its own folder (DIR/elsewhere/hidden/tests.yaml, as a course folder
 * holds), a file beside it that is not a shared object (DIR/notes.txt), and
 * a shared object beside it (DIR/libsibling.so, which the loader may
 * need), DIR being SYROF_TEST_SNOOP_DIR, where the test copies it (the
 * host loads it through /proc/self/fd, so it cannot ask where it lies).
 * It prints what it read; the app then behaves. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* The first line of what was read, printable bytes only. */
static void PrintLine(const char* what, const char* bytes, ssize_t size) {
  char line[128];
  size_t length = 0;
  for (ssize_t i = 0; i < size && bytes[i] != '\n' && length + 1 < sizeof line; ++i) {
    line[length++] = bytes[i] >= 0x20 && bytes[i] < 0x7f ? bytes[i] : '?';
  }
  line[length] = '\0';
  printf("read %s: %s\n", what, line);
}

static void TryToRead(const char* path) {
  const int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    printf("cannot read %s: %s\n", path, strerror(errno));
    return;
  }
  char bytes[256];
  const ssize_t got = read(fd, bytes, sizeof bytes);
  close(fd);
  if (got >= 0) PrintLine(path, bytes, got);
}

__attribute__((constructor)) static void SnoopOnLoad(void) {
  char bytes[256];
  int descriptors_read = 0;
  for (int fd = 0; fd < 1024; ++fd) {
    const ssize_t got = pread(fd, bytes, sizeof bytes, 0);
    if (got > 0) {
      char what[32];
      snprintf(what, sizeof what, "descriptor %d", fd);
      PrintLine(what, bytes, got);
      ++descriptors_read;
    }
  }
  printf("descriptors read: %d\n", descriptors_read);
  const char* folder = SYROF_TEST_SNOOP_DIR;
  static const char* const kNames[] = {"elsewhere/hidden/tests.yaml", "notes.txt", "libsibling.so"};
  for (size_t i = 0; i < sizeof kNames / sizeof kNames[0]; ++i) {
    char path[640];
    snprintf(path, sizeof path, "%s/%s", folder, kNames[i]);
    TryToRead(path);
  }
  fflush(stdout);
}

#define MISBEHAVE(ldmap) (void)0
#include "hostile.h"
