#include <stdlib.h>
#define MISBEHAVE(ldmap) exit(0)
#include "hostile.h"
