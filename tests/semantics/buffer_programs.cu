// Programs for buffer tests: one copy program per element type, an in-place accumulator, and a
// 2D/3D index check.
#include <optix_world.h>

using namespace optix;

rtDeclareVariable(unsigned int, index1, rtLaunchIndex, );
rtDeclareVariable(uint2, index2, rtLaunchIndex, );
rtDeclareVariable(uint3, index3, rtLaunchIndex, );

struct UserElement {
  float a;
  int b;
  char tag[12];
};

#define COPY_PROGRAM(T, name) \
  rtBuffer<T, 1> in_##name;   \
  rtBuffer<T, 1> out_##name;  \
  RT_PROGRAM void copy_##name() { out_##name[index1] = in_##name[index1]; }

COPY_PROGRAM(float, float1)
COPY_PROGRAM(float2, float2)
COPY_PROGRAM(float3, float3)
COPY_PROGRAM(float4, float4)
COPY_PROGRAM(char, byte1)
COPY_PROGRAM(char4, byte4)
COPY_PROGRAM(unsigned char, ubyte1)
COPY_PROGRAM(uchar3, ubyte3)
COPY_PROGRAM(uchar4, ubyte4)
COPY_PROGRAM(short, short1)
COPY_PROGRAM(short2, short2)
COPY_PROGRAM(unsigned short, ushort1)
COPY_PROGRAM(ushort4, ushort4)
COPY_PROGRAM(int, int1)
COPY_PROGRAM(int3, int3)
COPY_PROGRAM(unsigned int, uint1)
COPY_PROGRAM(uint2, uint2)
COPY_PROGRAM(uint4, uint4)
COPY_PROGRAM(UserElement, user)

// INPUT_OUTPUT: every launch adds one to each element.
rtBuffer<int, 1> counter;
RT_PROGRAM void increment() { counter[index1] += 1; }

// 2D and 3D buffers: each element records its own index.
rtBuffer<uint2, 2> grid2;
RT_PROGRAM void write_index2() { grid2[index2] = index2; }
rtBuffer<uint4, 3> grid3;
RT_PROGRAM void write_index3() { grid3[index3] = make_uint4(index3.x, index3.y, index3.z, 7u); }

// Scatter: every launch index adds to one shared element (atomics on buffer elements).
rtBuffer<unsigned int, 1> histogram;
RT_PROGRAM void scatter() { atomicAdd(&histogram[index1 % 4], 1u); }
