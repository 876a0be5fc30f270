#include <unistd.h>
#define MISBEHAVE(ldmap) (void)fork()
#include "hostile.h"
