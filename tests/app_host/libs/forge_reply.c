#include <unistd.h>
/* Writes a short message on the host's channel (descriptor 3) as if it
 * were the reply: the parent must see a malformed reply, not trust it. */
#define MISBEHAVE(ldmap) (void)write(3, "forged", 6)
#include "hostile.h"
