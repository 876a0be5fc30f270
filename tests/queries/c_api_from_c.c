/* Compiled as C: the C API's header is plain C, and a C caller gets the
 * same answer as C++. Called from c_api_test.cpp. */
#include <stddef.h>

#include "syrof/queries/queries.h"

int syrof_queries_c_caller_leader(void) {
  const syrof_queries_member members[3] = {{9, 0, 0}, {4, 100, 0}, {6, 0, 100}};
  uint16_t leader = SYROF_QUERIES_NO_ROBOT;
  if (syrof_queries_leader(members, 3, &leader) != SYROF_QUERIES_OK) return -1;
  return (int)leader;
}
