// What newlib's rdimon (semihosting) system calls and the missing start files
// leave undefined. Kept to the few symbols a link actually asks for.

#include <sys/stat.h>

#include <cerrno>

extern "C" {

// Identifies this image to __cxa_atexit, which registers the destructors of
// static objects. crtbegin.o defines it, and -nostartfiles leaves it out.
void* __dso_handle = nullptr;

// Semihosting has no directories; GoogleTest only asks for one when told to
// write a report file (--gtest_output).
int mkdir(const char* /*path*/, mode_t /*mode*/) {
  errno = ENOSYS;
  return -1;
}

}  // extern "C"
