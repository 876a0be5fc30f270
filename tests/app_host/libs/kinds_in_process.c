/* kinds.c linked into the test itself (in-process CAbiApp), its entry
 * renamed so it does not clash with anything. */
#define syrof_app_entry kinds_app_entry
#include "kinds.c"
