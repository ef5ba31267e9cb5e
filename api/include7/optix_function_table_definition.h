/* Defines the function table that optix_stubs.h calls through. Exactly one translation unit of
 * an application includes this header, as with OptiX. */
#ifndef TESSERA_OPTIX7_OPTIX_FUNCTION_TABLE_DEFINITION_H_
#define TESSERA_OPTIX7_OPTIX_FUNCTION_TABLE_DEFINITION_H_

#include "optix_function_table.h"

#ifndef OPTIX_FUNCTION_TABLE_SYMBOL
/* An application that mixes several OptiX SDKs renames the table, as OptiX allows. */
#define OPTIX_FUNCTION_TABLE_SYMBOL g_optixFunctionTable
#endif

#ifdef __cplusplus
extern "C" {
#endif

OptixFunctionTable OPTIX_FUNCTION_TABLE_SYMBOL;

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX7_OPTIX_FUNCTION_TABLE_DEFINITION_H_ */
