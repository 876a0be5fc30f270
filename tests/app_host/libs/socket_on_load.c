#include <sys/socket.h>
/* Opens a socket from a constructor: the loader's filter refuses it too. */
__attribute__((constructor)) static void ConnectOnLoad(void) { (void)socket(AF_INET, SOCK_STREAM, 0); }
#define MISBEHAVE(ldmap) (void)0
#include "hostile.h"
