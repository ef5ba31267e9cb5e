/* Which OptiX 7 release the headers of this include root describe. OptiX 7.7 (OPTIX_VERSION
 * 70700, function table ABI 84) unless the application says otherwise: an application written
 * against an older 7.x SDK that spells the older names (optixModuleCreateFromPTX,
 * OPTIX_ERROR_INVALID_PTX, OptixPipelineLinkOptions::debugLevel) defines OPTIX_VERSION before
 * the first OptiX header, e.g. -DOPTIX_VERSION=70600 (docs/optix7.md). Only the source-level
 * names change; the function table and the structs' layouts stay 7.7's, so an older spelling
 * reaches the same entry point. */
#ifndef TESSERA_OPTIX7_VERSION_H_
#define TESSERA_OPTIX7_VERSION_H_

#ifndef OPTIX_VERSION
/* major * 10000 + minor * 100 + micro */
#define OPTIX_VERSION 70700
#endif

#if OPTIX_VERSION < 70000 || OPTIX_VERSION > 70799
#error "Tessera's OptiX 7 headers describe OptiX 7.0 to 7.7: OPTIX_VERSION must be 70000..70700"
#endif

#endif /* TESSERA_OPTIX7_VERSION_H_ */
