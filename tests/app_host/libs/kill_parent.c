#include <signal.h>
#include <unistd.h>
#define MISBEHAVE(ldmap) (void)kill(getppid(), SIGKILL)
#include "hostile.h"
