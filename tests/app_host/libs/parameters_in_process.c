/* parameters.c linked into the test itself (in-process CAbiApp), its entry
 * renamed so it does not clash with anything. Its globals are shared by
 * every robot of the process; every robot reads the same parameters, so
 * sharing them changes nothing. */
#define syrof_app_entry parameters_app_entry
#include "parameters.c"

/* What the in-process instance read, for the test to check. */
double parameters_app_target_x_m(void) { return target_x_m; }
uint8_t parameters_app_checks(void) { return checks; }
