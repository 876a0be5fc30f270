/* inputs.c linked into the test itself (in-process CAbiApp), its entry
 * renamed so it does not clash with anything. It keeps nothing in globals,
 * so every robot of the process reads its own input. */
#define syrof_app_entry inputs_app_entry
#include "inputs.c"
