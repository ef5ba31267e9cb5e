/* Compiles the public headers as C99 with -Wall -Wextra -pedantic -Werror and calls into
 * libtessera from C: the headers must stay usable from C applications. */
#include <stdio.h>

#include "tessera/rt.h"
#include "tessera/rt_ext.h"
/* optix.h from C gives the host API only (the program-side API is C++). */
#include "optix.h"
#include "optix_world.h"

int main(void) {
  unsigned int version = 0;
  const char* error = NULL;
  RTcontext context = NULL;
  if (rtGetVersion(&version) != RT_SUCCESS || version != OPTIX_VERSION) return 1;
  if (tesseraDeviceSpecValidate("inproc,local:2", &error) != RT_SUCCESS) return 2;
  if (tesseraDeviceSpecValidate("local:x", &error) != RT_ERROR_INVALID_VALUE || error == NULL) {
    return 3;
  }
  if (rtContextDestroy(context) != RT_ERROR_INVALID_CONTEXT) return 4;
  {
    char address[4];
    if (tesseraDeviceGetAddress(-1, sizeof(address), address) != RT_ERROR_INVALID_VALUE) return 5;
  }
  printf("OptiX host API %u from C99\n", version);
  return 0;
}
