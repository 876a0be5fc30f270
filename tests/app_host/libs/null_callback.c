#include "syrof/app.h"
static uint8_t Init(const syrof_app_info* info) {
  (void)info;
  return 0;
}
/* No new_round: the loader's check refuses the descriptor. */
SYROF_APP_DEFINE("incomplete", Init, 0, 0)
