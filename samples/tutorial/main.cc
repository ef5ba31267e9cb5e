// tessera-tutorial: renders the OptiX SDK tutorial's steps with Tessera.
#include <iostream>

#include "tutorial/cli.h"

int main(int argc, char** argv) {
  return tessera::tutorial::RunTutorialMain(argc, argv, std::cout, std::cerr);
}
