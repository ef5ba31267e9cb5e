// Globals named like glibc functions that CUDA does not declare, then library headers included
// after them, which must still work.
// The math header first, as SDK programs often start: it must bring the rename too.
#include <optixu_math_namespace.h>
// clang-format off: in this order
#include <optix.h>
// clang-format on

using namespace optix;

rtDeclareVariable(uint2, index, rtLaunchIndex, );
rtDeclareVariable(float, time, , );
rtDeclareVariable(float, gamma, , ) = 2.2f;
rtDeclareVariable(unsigned int, random, , );
rtDeclareVariable(int, select, , );
rtDeclareVariable(int, rindex, , );
rtBuffer<float4, 2> output_buffer;

#include <strings.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <ctime>
#include <functional>
#include <iomanip>
#include <iostream>
#include <locale>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <variant>

RT_PROGRAM void shade_names() {
  std::variant<int, float> v = 1.0f;
  std::mt19937 rng(index.x + 31u * index.y);
  std::stringstream text;
  text << std::setw(3) << v.index();
  std::map<int, int> m;
  m[1] = static_cast<int>(rng() % 7u);
  char buf[8];
  std::strcpy(buf, "abc");
  const float g = powf(time, 1.0f / gamma) + float(random) + float(select) + float(rindex);
  const auto t0 = std::chrono::steady_clock::now();
  output_buffer[index] =
      make_float4(g, float(m.size() + text.str().size()), float(std::strlen(buf)),
                  float(t0.time_since_epoch().count() > 0));
}
