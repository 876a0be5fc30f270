#include <stdlib.h>
#define MISBEHAVE(ldmap) abort()
#include "hostile.h"
