/* Calls a function no library defines: dlopen(RTLD_NOW) refuses it. */
#include <stddef.h>
extern int syrof_no_such_function(void);
#define MISBEHAVE(ldmap) (void)syrof_no_such_function()
#include "hostile.h"
