/* cooperative.c linked into the test itself (in-process CAbiApp), its
 * entry renamed so it does not clash with anything. */
#define syrof_app_entry cooperative_app_entry
#include "cooperative.c"
