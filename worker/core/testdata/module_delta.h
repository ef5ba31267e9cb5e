// Program modules for hand-built StateDeltas: a module file's bytes travel in the delta as
// ModuleChunks under their wire hash (lowercase hex SHA-256), computed here with OpenSSL directly
// rather than with the code under test.
#ifndef TESSERA_WORKER_CORE_TESTDATA_MODULE_DELTA_H_
#define TESSERA_WORKER_CORE_TESTDATA_MODULE_DELTA_H_

#include <openssl/evp.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include "tessera/v1/state.pb.h"

namespace tessera::testing {

inline std::string ReadModuleFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline std::string Sha256Hex(const std::string& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  EVP_Digest(bytes.data(), bytes.size(), digest, &size, EVP_sha256(), nullptr);
  std::string hex;
  for (unsigned i = 0; i < size; ++i) {
    char two[3];
    std::snprintf(two, sizeof(two), "%02x", digest[i]);
    hex += two;
  }
  return hex;
}

// Appends `bytes` to `delta` as slices of at most `slice` bytes; returns their hash.
inline std::string AddModuleBytes(v1::StateDelta* delta, const std::string& bytes,
                                  size_t slice = size_t{4} << 20) {
  const std::string hash = Sha256Hex(bytes);
  for (size_t begin = 0; begin < bytes.size(); begin += slice) {
    v1::ModuleChunk* c = delta->add_modules();
    c->set_module_hash(hash);
    c->set_offset(begin);
    c->set_total_size(bytes.size());
    c->set_data(bytes.substr(begin, std::min(slice, bytes.size() - begin)));
  }
  return hash;
}

}  // namespace tessera::testing

#endif  // TESSERA_WORKER_CORE_TESTDATA_MODULE_DELTA_H_
