// The host's malloc family (allocation_guard.cpp): glibc's allocator, with
// one difference: an allocation it refuses (the address-space limit) is
// reported as the verdict `memory` through the handler, which does not
// return. Without this a refused malloc returns NULL and a student's app
// usually dies on the NULL, which would read as a crash.
#pragma once

#include <cstddef>

namespace syrof::app_host {

/// `handler(size)` runs when an allocation of `size` bytes is refused; it
/// must not return. Null: refusals return NULL as glibc's do.
void SetAllocationRefusedHandler(void (*handler)(size_t size));

/// False in a sanitizer build (the sanitizer's runtime owns malloc).
bool AllocationGuardActive();

}  // namespace syrof::app_host
