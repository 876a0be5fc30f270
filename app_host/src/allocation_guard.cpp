#include "allocation_guard.h"

#include <cerrno>
#include <cstdint>
#include <cstdlib>

namespace syrof::app_host {
namespace {

void (*refused_handler)(size_t) = nullptr;

[[maybe_unused]] void Refused(size_t size) {
  if (refused_handler != nullptr) refused_handler(size);
}

}  // namespace

void SetAllocationRefusedHandler(void (*handler)(size_t size)) { refused_handler = handler; }

#if defined(SYROF_APP_HOST_SANITIZED)
bool AllocationGuardActive() { return false; }
#else
bool AllocationGuardActive() { return true; }
#endif

}  // namespace syrof::app_host

#if !defined(SYROF_APP_HOST_SANITIZED)
// The executable comes first in the dynamic linker's search order and is
// linked with -rdynamic, so these are the malloc family of every library in
// the host (the student's, libstdc++'s operator new, the loader's once it
// has relocated). glibc exports its allocator under __libc_* for exactly
// this kind of wrapper. free, malloc_usable_size and the rest stay glibc's:
// the memory is glibc's.
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* pointer, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void* __libc_valloc(size_t size);
void* __libc_pvalloc(size_t size);

void* malloc(size_t size) {
  void* pointer = __libc_malloc(size);
  if (pointer == nullptr) syrof::app_host::Refused(size);
  return pointer;
}

void* calloc(size_t count, size_t size) {
  void* pointer = __libc_calloc(count, size);
  if (pointer == nullptr && count != 0 && size != 0) {
    syrof::app_host::Refused(size > SIZE_MAX / count ? SIZE_MAX : count * size);
  }
  return pointer;
}

void* realloc(void* old_pointer, size_t size) {
  void* pointer = __libc_realloc(old_pointer, size);
  // realloc(p, 0) frees p and may return NULL: not a refusal.
  if (pointer == nullptr && size != 0) syrof::app_host::Refused(size);
  return pointer;
}

void* reallocarray(void* old_pointer, size_t count, size_t size) {
  if (size != 0 && count > SIZE_MAX / size) {
    syrof::app_host::Refused(SIZE_MAX);
    errno = ENOMEM;
    return nullptr;
  }
  return realloc(old_pointer, count * size);
}

void* memalign(size_t alignment, size_t size) {
  void* pointer = __libc_memalign(alignment, size);
  if (pointer == nullptr && errno == ENOMEM) syrof::app_host::Refused(size);
  return pointer;
}

void* aligned_alloc(size_t alignment, size_t size) { return memalign(alignment, size); }

int posix_memalign(void** result, size_t alignment, size_t size) {
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0 || alignment == 0) return EINVAL;
  void* pointer = __libc_memalign(alignment, size);
  if (pointer == nullptr) {
    syrof::app_host::Refused(size);
    return ENOMEM;
  }
  *result = pointer;
  return 0;
}

void* valloc(size_t size) {
  void* pointer = __libc_valloc(size);
  if (pointer == nullptr) syrof::app_host::Refused(size);
  return pointer;
}

void* pvalloc(size_t size) {
  void* pointer = __libc_pvalloc(size);
  if (pointer == nullptr) syrof::app_host::Refused(size);
  return pointer;
}
}  // extern "C"
#endif
