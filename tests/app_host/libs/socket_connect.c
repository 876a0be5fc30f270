#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
static void Connect(void) {
  int fd = socket(AF_INET, SOCK_STREAM, 0);
  struct sockaddr_in address = {0};
  address.sin_family = AF_INET;
  address.sin_port = htons(9);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  (void)connect(fd, (struct sockaddr*)&address, sizeof address);
  close(fd);
}
#define MISBEHAVE(ldmap) Connect()
#include "hostile.h"
