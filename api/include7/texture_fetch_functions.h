/* CUDA 12's texture_fetch_functions.h held the texture reference API, which CUDA 12 removed; code
 * that includes it by name for the object functions gets them (texture_indirect_functions.h). */
#ifndef TESSERA_OPTIX7_TEXTURE_FETCH_FUNCTIONS_H_
#define TESSERA_OPTIX7_TEXTURE_FETCH_FUNCTIONS_H_

#include "texture_indirect_functions.h"

#endif /* TESSERA_OPTIX7_TEXTURE_FETCH_FUNCTIONS_H_ */
