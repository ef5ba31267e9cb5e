#include "tools/tessera/render/accumulation_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace tessera::render {
namespace {

constexpr char kMagic[] = "TESSERA-ACCUM 1";

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the file's floats are little-endian");

}  // namespace

std::string AccumulationPath(const std::string& image_path) { return image_path + ".accum"; }

absl::Status WriteAccumulation(const std::string& path, const Accumulation& a) {
  if (a.key.find('\n') != std::string::npos) {
    return absl::InvalidArgumentError("an accumulation key must be one line");
  }
  const std::string temp = absl::StrCat(path, ".", getpid(), ".tmp");
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out << kMagic << "\nwidth " << a.width << "\nheight " << a.height << "\nsamples " << a.samples
        << "\nkey " << a.key << "\n\n";
    out.write(reinterpret_cast<const char*>(a.sums.data()),
              static_cast<std::streamsize>(a.sums.size() * sizeof(float)));
    out.flush();
    if (!out) {
      const std::string why = std::strerror(errno);
      std::remove(temp.c_str());
      return absl::InternalError("cannot write '" + path + "': " + why);
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temp.c_str());
    return absl::InternalError("cannot write '" + path + "': " + why);
  }
  return absl::OkStatus();
}

absl::StatusOr<Accumulation> ReadAccumulation(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (errno == ENOENT) return absl::NotFoundError("no accumulation '" + path + "'");
    return absl::InvalidArgumentError("cannot read '" + path + "': " + std::strerror(errno));
  }
  auto bad = [&](const std::string& why) {
    return absl::InvalidArgumentError("'" + path +
                                      "' is not a tessera render accumulation: " + why);
  };
  std::string line;
  if (!std::getline(in, line) || line != kMagic)
    return bad("it does not start with " + std::string(kMagic));
  Accumulation a;
  bool have_width = false, have_height = false, have_samples = false;
  while (std::getline(in, line) && !line.empty()) {
    const size_t space = line.find(' ');
    const std::string name = line.substr(0, space);
    const std::string value = space == std::string::npos ? "" : line.substr(space + 1);
    if (name == "width") {
      have_width = absl::SimpleAtoi(value, &a.width);
    } else if (name == "height") {
      have_height = absl::SimpleAtoi(value, &a.height);
    } else if (name == "samples") {
      have_samples = absl::SimpleAtoi(value, &a.samples);
    } else if (name == "key") {
      a.key = value;
    }  // other names: later versions' additions, skipped
  }
  if (!have_width || !have_height || !have_samples || a.width <= 0 || a.height <= 0) {
    return bad("its header lacks a size or sample count");
  }
  a.sums.resize(static_cast<size_t>(a.width) * static_cast<size_t>(a.height) * 4);
  in.read(reinterpret_cast<char*>(a.sums.data()),
          static_cast<std::streamsize>(a.sums.size() * sizeof(float)));
  if (static_cast<size_t>(in.gcount()) != a.sums.size() * sizeof(float)) {
    return bad("it is cut short");
  }
  return a;
}

}  // namespace tessera::render
