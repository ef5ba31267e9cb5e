// A host application for the end-to-end tests: renders the e2e scene through the C API on the
// devices of --spec, prints each launch's time, then `ready` and, with --wait, sleeps until it is
// killed (the orphan test kills it with SIGKILL and watches its workers). With --keep-context it
// returns from main without destroying its context, as applications that leave cleanup to the
// exit do.
//
//   e2e_host [--spec local:2] [--size W H] [--launches N] [--iterations K] [--wait]
//            [--keep-context]
//
// --iterations K launches entry point 1 instead (K traces per launch index: a compute-bound load).
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "e2e_scene.h"
#include "tessera/rt_ext.h"

int main(int argc, char** argv) {
  std::string spec = "local:2";
  unsigned width = 64, height = 64;
  int launches = 1;
  int iterations = 0;
  bool wait = false;
  bool keep_context = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--spec") && i + 1 < argc) {
      spec = argv[++i];
    } else if (!std::strcmp(argv[i], "--size") && i + 2 < argc) {
      width = static_cast<unsigned>(std::atoi(argv[++i]));
      height = static_cast<unsigned>(std::atoi(argv[++i]));
    } else if (!std::strcmp(argv[i], "--launches") && i + 1 < argc) {
      launches = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--iterations") && i + 1 < argc) {
      iterations = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--wait")) {
      wait = true;
    } else if (!std::strcmp(argv[i], "--keep-context")) {
      keep_context = true;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--spec S] [--size W H] [--launches N] [--iterations K] [--wait] "
                   "[--keep-context]\n",
                   argv[0]);
      return 2;
    }
  }
  RTcontext ctx = nullptr;
  if (rtContextCreate(&ctx) != RT_SUCCESS) return 1;
  RTresult r = tesseraContextSetDeviceSpec(ctx, spec.c_str());
  if (r != RT_SUCCESS) {
    std::fprintf(stderr, "%s\n", tessera::e2e::ErrorText(ctx, r).c_str());
    return 1;
  }
  tessera::e2e::Scene scene;
  std::string error;
  if (tessera::e2e::BuildScene(ctx, width, height, &scene, &error) != RT_SUCCESS) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  const unsigned entry = iterations > 0 ? 1 : 0;
  if (iterations > 0 && rtVariableSet1i(scene.iterations, iterations) != RT_SUCCESS) return 1;
  for (int i = 0; i < launches; ++i) {
    auto start = std::chrono::steady_clock::now();
    r = rtContextLaunch2D(ctx, entry, width, height);
    double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (r != RT_SUCCESS) {
      std::fprintf(stderr, "launch: %s\n", tessera::e2e::ErrorText(ctx, r).c_str());
      return 1;
    }
    std::printf("launch %d %s %ux%u %.1f ms\n", i, spec.c_str(), width, height, ms);
  }
  std::printf("ready\n");
  std::fflush(stdout);
  while (wait) pause();
  if (!keep_context) rtContextDestroy(ctx);
  return 0;
}
