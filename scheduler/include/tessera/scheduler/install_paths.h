// Where the parts of Tessera are, found from the library itself so that an installed prefix
// (`cmake --install`, GNUInstallDirs layout) works wherever it is put, and a build tree keeps
// working without being installed.
#ifndef TESSERA_SCHEDULER_INSTALL_PATHS_H_
#define TESSERA_SCHEDULER_INSTALL_PATHS_H_

#include <string>

namespace tessera::scheduler {

// The file that holds this code: libtessera.so when linked into it, else the executable; empty
// when neither can be told.
std::string ThisBinaryPath();

// The directory part of `path` ("." for a bare name).
std::string DirName(const std::string& path);

// In the installed layout beside ThisBinaryPath() (<libdir>): tessera-worker in <bindir>, and
// the directory of the program-side headers, <includedir>/tessera. Empty when ThisBinaryPath()
// is unknown; the files need not exist (a build tree has neither).
std::string InstalledWorkerPath();
std::string InstalledIncludeDir();

// Whether ThisBinaryPath() lies in the build tree it was built in.
bool RunningFromBuildTree();

// An installed (or copied) library that has to use the build tree's worker or headers, because
// its own (`missing`) are not there, says so once per part on stderr: they may be another version.
// Nothing is said for a library used from its build tree.
enum class InstalledPart { kWorker, kHeaders };
void NoteBuildTreeFallback(InstalledPart part, const std::string& missing, const std::string& used);

}  // namespace tessera::scheduler

#endif  // TESSERA_SCHEDULER_INSTALL_PATHS_H_
