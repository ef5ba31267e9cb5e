/* The stack-size helpers of the OptiX SDK (optixUtil*): they combine the stack sizes that
 * optixProgramGroupGetStackSize reports into the three arguments of optixPipelineSetStackSize,
 * with the formulas of the OptiX 7.7 Programming Guide, section 6.7 (listings 6.14 to 6.17).
 * They are arithmetic on OptixStackSizes and need nothing of the runtime but
 * optixProgramGroupGetStackSize. C++ (inline functions), as host code uses them. */
#ifndef TESSERA_OPTIX7_OPTIX_STACK_SIZE_H_
#define TESSERA_OPTIX7_OPTIX_STACK_SIZE_H_

#include "optix.h"

#ifdef __cplusplus
extern "C" {
#endif

inline unsigned int tesseraOptixMaxU_(unsigned int a, unsigned int b) { return a > b ? a : b; }
inline unsigned int tesseraOptixMinU_(unsigned int a, unsigned int b) { return a < b ? a : b; }

/* Folds `programGroup`'s stack sizes into `stackSizes` (field-wise maximum). 7.7 passes the
 * pipeline the group is linked into (0 if none); older releases have no such argument. */
#if OPTIX_VERSION >= 70700
inline OptixResult optixUtilAccumulateStackSizes(OptixProgramGroup programGroup,
                                                 OptixStackSizes* stackSizes,
                                                 OptixPipeline pipeline) {
#else
inline OptixResult optixUtilAccumulateStackSizes(OptixProgramGroup programGroup,
                                                 OptixStackSizes* stackSizes) {
  const OptixPipeline pipeline = 0;
#endif
  if (!stackSizes) return OPTIX_ERROR_INVALID_VALUE;
  OptixStackSizes local;
  const OptixResult result = optixProgramGroupGetStackSize(programGroup, &local, pipeline);
  if (result != OPTIX_SUCCESS) return result;
  stackSizes->cssRG = tesseraOptixMaxU_(stackSizes->cssRG, local.cssRG);
  stackSizes->cssMS = tesseraOptixMaxU_(stackSizes->cssMS, local.cssMS);
  stackSizes->cssCH = tesseraOptixMaxU_(stackSizes->cssCH, local.cssCH);
  stackSizes->cssAH = tesseraOptixMaxU_(stackSizes->cssAH, local.cssAH);
  stackSizes->cssIS = tesseraOptixMaxU_(stackSizes->cssIS, local.cssIS);
  stackSizes->cssCC = tesseraOptixMaxU_(stackSizes->cssCC, local.cssCC);
  stackSizes->dssDC = tesseraOptixMaxU_(stackSizes->dssDC, local.dssDC);
  return OPTIX_SUCCESS;
}

/* Listing 6.15 with the direct-callable sizes of listing 6.14, given the continuation-callable
 * call tree's stack (cssCCTree); the building block of the helpers below. */
inline OptixResult tesseraOptixUtilComputeStackSizes_(
    const OptixStackSizes* stackSizes, unsigned int cssCCTree, unsigned int maxTraceDepth,
    unsigned int dcFromTraversal, unsigned int dcFromState,
    unsigned int* directCallableStackSizeFromTraversal,
    unsigned int* directCallableStackSizeFromState, unsigned int* continuationStackSize) {
  if (!stackSizes || !directCallableStackSizeFromTraversal || !directCallableStackSizeFromState ||
      !continuationStackSize)
    return OPTIX_ERROR_INVALID_VALUE;
  const unsigned int cssCHOrMSPlusCCTree =
      tesseraOptixMaxU_(stackSizes->cssCH, stackSizes->cssMS) + cssCCTree;
  *directCallableStackSizeFromTraversal = dcFromTraversal;
  *directCallableStackSizeFromState = dcFromState;
  *continuationStackSize =
      stackSizes->cssRG + cssCCTree +
      (tesseraOptixMaxU_(1u, maxTraceDepth) - 1u) * cssCHOrMSPlusCCTree +
      tesseraOptixMinU_(maxTraceDepth, 1u) *
          tesseraOptixMaxU_(cssCHOrMSPlusCCTree, stackSizes->cssIS + stackSizes->cssAH);
  return OPTIX_SUCCESS;
}

/* Listings 6.14 and 6.15. */
inline OptixResult optixUtilComputeStackSizes(const OptixStackSizes* stackSizes,
                                              unsigned int maxTraceDepth, unsigned int maxCCDepth,
                                              unsigned int maxDCDepth,
                                              unsigned int* directCallableStackSizeFromTraversal,
                                              unsigned int* directCallableStackSizeFromState,
                                              unsigned int* continuationStackSize) {
  if (!stackSizes) return OPTIX_ERROR_INVALID_VALUE;
  return tesseraOptixUtilComputeStackSizes_(
      stackSizes, maxCCDepth * stackSizes->cssCC, maxTraceDepth, maxDCDepth * stackSizes->dssDC,
      maxDCDepth * stackSizes->dssDC, directCallableStackSizeFromTraversal,
      directCallableStackSizeFromState, continuationStackSize);
}

/* Listing 6.16: direct callables called during traversal (IS, AH) and from state (RG, MS, CH)
 * accounted separately, each with its own stack sizes and depth. */
inline OptixResult optixUtilComputeStackSizesDCSplit(
    const OptixStackSizes* stackSizes, unsigned int dssDCFromTraversal, unsigned int dssDCFromState,
    unsigned int maxTraceDepth, unsigned int maxCCDepth, unsigned int maxDCDepthFromTraversal,
    unsigned int maxDCDepthFromState, unsigned int* directCallableStackSizeFromTraversal,
    unsigned int* directCallableStackSizeFromState, unsigned int* continuationStackSize) {
  if (!stackSizes) return OPTIX_ERROR_INVALID_VALUE;
  return tesseraOptixUtilComputeStackSizes_(
      stackSizes, maxCCDepth * stackSizes->cssCC, maxTraceDepth,
      maxDCDepthFromTraversal * dssDCFromTraversal, maxDCDepthFromState * dssDCFromState,
      directCallableStackSizeFromTraversal, directCallableStackSizeFromState,
      continuationStackSize);
}

/* Listing 6.17: the continuation-callable call tree's stack given directly (cssCCTree). */
inline OptixResult optixUtilComputeStackSizesCssCCTree(
    const OptixStackSizes* stackSizes, unsigned int cssCCTree, unsigned int maxTraceDepth,
    unsigned int maxDCDepth, unsigned int* directCallableStackSizeFromTraversal,
    unsigned int* directCallableStackSizeFromState, unsigned int* continuationStackSize) {
  if (!stackSizes) return OPTIX_ERROR_INVALID_VALUE;
  return tesseraOptixUtilComputeStackSizes_(
      stackSizes, cssCCTree, maxTraceDepth, maxDCDepth * stackSizes->dssDC,
      maxDCDepth * stackSizes->dssDC, directCallableStackSizeFromTraversal,
      directCallableStackSizeFromState, continuationStackSize);
}

/* Guide section 6.7.1, listing 6.19: camera rays (miss MS1, closest hits CH1) whose closest
 * hits trace shadow rays (MS2, CH2); trace depth 2, no any-hit, intersection or callables. */
inline OptixResult optixUtilComputeStackSizesSimplePathTracer(
    OptixProgramGroup programGroupRG, OptixProgramGroup programGroupMS1,
    const OptixProgramGroup* programGroupCH1, unsigned int programGroupCH1Count,
    OptixProgramGroup programGroupMS2, const OptixProgramGroup* programGroupCH2,
    unsigned int programGroupCH2Count, unsigned int* directCallableStackSizeFromTraversal,
    unsigned int* directCallableStackSizeFromState, unsigned int* continuationStackSize,
    OptixPipeline pipeline) {
  if (!programGroupCH1 && programGroupCH1Count > 0) return OPTIX_ERROR_INVALID_VALUE;
  if (!programGroupCH2 && programGroupCH2Count > 0) return OPTIX_ERROR_INVALID_VALUE;
  if (!directCallableStackSizeFromTraversal || !directCallableStackSizeFromState ||
      !continuationStackSize)
    return OPTIX_ERROR_INVALID_VALUE;
  OptixResult result;
  OptixStackSizes rg, ms1, ms2, ch1, ch2;
  result = optixProgramGroupGetStackSize(programGroupRG, &rg, pipeline);
  if (result != OPTIX_SUCCESS) return result;
  result = optixProgramGroupGetStackSize(programGroupMS1, &ms1, pipeline);
  if (result != OPTIX_SUCCESS) return result;
  result = optixProgramGroupGetStackSize(programGroupMS2, &ms2, pipeline);
  if (result != OPTIX_SUCCESS) return result;
  unsigned int cssCH1 = 0, cssCH2 = 0;
  for (unsigned int i = 0; i < programGroupCH1Count; ++i) {
    result = optixProgramGroupGetStackSize(programGroupCH1[i], &ch1, pipeline);
    if (result != OPTIX_SUCCESS) return result;
    cssCH1 = tesseraOptixMaxU_(cssCH1, ch1.cssCH);
  }
  for (unsigned int i = 0; i < programGroupCH2Count; ++i) {
    result = optixProgramGroupGetStackSize(programGroupCH2[i], &ch2, pipeline);
    if (result != OPTIX_SUCCESS) return result;
    cssCH2 = tesseraOptixMaxU_(cssCH2, ch2.cssCH);
  }
  /* Listing 6.19: MS2 and CH2 run only below CH1. */
  const unsigned int level1 =
      tesseraOptixMaxU_(ms1.cssMS, cssCH1 + tesseraOptixMaxU_(ms2.cssMS, cssCH2));
  *directCallableStackSizeFromTraversal = 0;
  *directCallableStackSizeFromState = 0;
  *continuationStackSize = rg.cssRG + level1;
  return OPTIX_SUCCESS;
}

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX7_OPTIX_STACK_SIZE_H_ */
