// Renders on the devices TESSERA_DEVICES names (the test asks for worker processes), with a
// prebuilt module and one compiled from source at run time, checks every element, and prints the
// executable of each tessera-worker it spawned so the test can tell which worker ran.
#include <dirent.h>
#include <optix.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace {

RTcontext g_context = nullptr;

void Check(RTresult code, const char* what) {
  if (code == RT_SUCCESS) return;
  const char* message = nullptr;
  rtContextGetErrorString(g_context, code, &message);
  std::fprintf(stderr, "consumer: %s failed: %s\n", what, message != nullptr ? message : "?");
  std::exit(1);
}

// Children of this process whose executable is called tessera-worker.
void PrintWorkerExecutables() {
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return;
  while (dirent* entry = readdir(proc)) {
    const std::string pid = entry->d_name;
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat("/proc/" + pid + "/stat");
    std::string line;
    std::getline(stat, line);
    const size_t paren = line.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream rest(line.substr(paren + 2));
    std::string state;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid != static_cast<long>(getpid())) continue;
    char exe[PATH_MAX];
    const ssize_t n = readlink(("/proc/" + pid + "/exe").c_str(), exe, sizeof(exe) - 1);
    if (n <= 0) continue;
    const std::string path(exe, static_cast<size_t>(n));
    if (path.size() >= 15 && path.compare(path.size() - 15, 15, "/tessera-worker") == 0) {
      std::printf("worker %s\n", path.c_str());
    }
  }
  closedir(proc);
}

bool OutputIs(RTbuffer buffer, unsigned w, unsigned h, unsigned add, bool gradient) {
  void* data = nullptr;
  Check(rtBufferMap(buffer, &data), "rtBufferMap");
  const unsigned* values = static_cast<const unsigned*>(data);
  bool ok = true;
  for (unsigned y = 0; y < h && ok; ++y) {
    for (unsigned x = 0; x < w && ok; ++x) {
      const unsigned expected = gradient ? y * w + x : add + x;
      if (values[y * w + x] != expected) {
        std::fprintf(stderr, "consumer: element (%u, %u) is %u, not %u\n", x, y, values[y * w + x],
                     expected);
        ok = false;
      }
    }
  }
  Check(rtBufferUnmap(buffer), "rtBufferUnmap");
  return ok;
}

std::string ReadFile(const char* path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

int main() {
  constexpr unsigned kW = 64, kH = 48;
  Check(rtContextCreate(&g_context), "rtContextCreate");
  Check(rtContextSetEntryPointCount(g_context, 2), "rtContextSetEntryPointCount");
  RTbuffer output;
  Check(rtBufferCreate(g_context, RT_BUFFER_OUTPUT, &output), "rtBufferCreate");
  Check(rtBufferSetFormat(output, RT_FORMAT_UNSIGNED_INT), "rtBufferSetFormat");
  Check(rtBufferSetSize2D(output, kW, kH), "rtBufferSetSize2D");
  RTvariable variable;
  Check(rtContextDeclareVariable(g_context, "output", &variable), "declare output");
  Check(rtVariableSetObject(variable, output), "set output");
  RTvariable value;
  Check(rtContextDeclareVariable(g_context, "value", &value), "declare value");
  Check(rtVariableSet1ui(value, 1000), "set value");

  RTprogram gradient;
  Check(rtProgramCreateFromPTXFile(g_context, MODULE_PATH, "gradient", &gradient),
        "rtProgramCreateFromPTXFile");
  Check(rtContextSetRayGenerationProgram(g_context, 0, gradient), "set gradient");
  const std::string source = ReadFile(PROGRAM_SOURCE);
  RTprogram fill;
  Check(rtProgramCreateFromPTXString(g_context, source.c_str(), "fill", &fill),
        "rtProgramCreateFromPTXString");
  Check(rtContextSetRayGenerationProgram(g_context, 1, fill), "set fill");

  Check(rtContextLaunch2D(g_context, 0, kW, kH), "launch of gradient");
  if (!OutputIs(output, kW, kH, 0, true)) return 1;
  Check(rtContextLaunch2D(g_context, 1, kW, kH), "launch of fill");
  if (!OutputIs(output, kW, kH, 1000, false)) return 1;
  PrintWorkerExecutables();
  Check(rtContextDestroy(g_context), "rtContextDestroy");
  std::printf("consumer: both launches wrote what they should\n");
  return 0;
}
