/* bench_app.c linked into the benchmark (CAbiApp), its entry renamed. */
#define syrof_app_entry bench_app_entry
#include "bench_app.c"
