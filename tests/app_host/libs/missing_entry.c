#include "syrof/app.h"
/* Everything but syrof_app_entry. */
uint8_t lonely_init(const syrof_app_info* info) {
  (void)info;
  return 0;
}
