#include "acceleration_blob.h"

#include <cstring>

#include "absl/strings/str_cat.h"
#include "hash.h"
#include "status.h"
#include "tessera/rt.h"

namespace tessera::api {
namespace {

// Layout (little-endian; docs/acceleration_data.md):
//   0  char[8] magic "TSRACCEL"
//   8  u32     format version
//  12  u32     0 (reserved)
//  16  u64     size of the whole blob, checksum included
//  24  payload: platform, builder, traverser, properties, node kind, inputs, bounds
//  end u64     XXH64 of every byte before it
constexpr char kMagic[8] = {'T', 'S', 'R', 'A', 'C', 'C', 'E', 'L'};
constexpr size_t kHeaderBytes = 24;
constexpr size_t kChecksumBytes = 8;

class Writer {
 public:
  void U8(uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void U32(uint32_t v) { out_.append(reinterpret_cast<const char*>(&v), 4); }
  void U64(uint64_t v) { out_.append(reinterpret_cast<const char*>(&v), 8); }
  void Str(const std::string& s) {
    U32(static_cast<uint32_t>(s.size()));
    out_ += s;
  }
  void Bytes(const void* p, size_t n) { out_.append(static_cast<const char*>(p), n); }
  std::string& out() { return out_; }

 private:
  std::string out_;
};

// Reads the payload; every read checks what is left, so a lying length cannot run past the end.
class Reader {
 public:
  Reader(const char* p, size_t n) : p_(p), end_(p + n) {}
  bool U8(uint8_t* v) { return Raw(v, 1); }
  bool U32(uint32_t* v) { return Raw(v, 4); }
  bool U64(uint64_t* v) { return Raw(v, 8); }
  bool Str(std::string* s) {
    uint32_t n = 0;
    if (!U32(&n) || n > Left()) return false;
    s->assign(p_, n);
    p_ += n;
    return true;
  }
  bool Raw(void* v, size_t n) {
    if (n > Left()) return false;
    std::memcpy(v, p_, n);
    p_ += n;
    return true;
  }
  size_t Left() const { return static_cast<size_t>(end_ - p_); }

 private:
  const char* p_;
  const char* end_;
};

absl::Status Refused(const std::string& why) {
  return RtError(RT_ERROR_INVALID_VALUE, absl::StrCat("acceleration data refused: ", why));
}

}  // namespace

const std::string& AccelerationDataPlatform() {
  static const auto* platform = new std::string(absl::StrCat("tessera-embree3 ",
#if defined(__x86_64__)
                                                             "x86_64",
#elif defined(__aarch64__)
                                                             "aarch64",
#else
                                                             "unknown-cpu",
#endif
                                                             "-linux ",
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
                                                             "little-endian"
#else
                                                             "big-endian"
#endif
                                                             ));
  return *platform;
}

std::string EncodeAccelerationBlob(const AccelerationBlob& blob) {
  Writer w;
  w.Bytes(kMagic, sizeof(kMagic));
  w.U32(kAccelerationDataVersion);
  w.U32(0);
  w.U64(0);  // the size, once known
  w.Str(AccelerationDataPlatform());
  w.Str(blob.builder);
  w.Str(blob.traverser);
  w.U32(static_cast<uint32_t>(blob.properties.size()));
  for (const auto& [name, value] : blob.properties) {
    w.Str(name);
    w.Str(value);
  }
  w.U32(blob.node_kind);
  w.U32(static_cast<uint32_t>(blob.inputs.size()));
  for (size_t i = 0; i < blob.inputs.size(); ++i) {
    const BuildInput& in = blob.inputs[i];
    w.U32(in.kind);
    w.U64(in.primitive_count);
    w.Str(in.bounds_program);
    const bool has = i < blob.bounds.size() && !blob.bounds[i].empty();
    w.U8(has ? 1 : 0);
    if (has) w.Bytes(blob.bounds[i].data(), blob.bounds[i].size() * sizeof(float));
  }
  std::string& out = w.out();
  const uint64_t size = out.size() + kChecksumBytes;
  std::memcpy(&out[16], &size, 8);
  const uint64_t checksum = Hash64(out.data(), out.size());
  out.append(reinterpret_cast<const char*>(&checksum), 8);
  return std::move(out);
}

absl::StatusOr<AccelerationBlob> DecodeAccelerationBlob(const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  if (size < sizeof(kMagic) || std::memcmp(p, kMagic, sizeof(kMagic)) != 0) {
    return Refused(size < sizeof(kMagic)
                       ? absl::StrCat("only ", size, " bytes, too short to be Tessera's")
                       : "not data from Tessera's rtAccelerationGetData (wrong magic)");
  }
  if (size < kHeaderBytes + kChecksumBytes) {
    return Refused(absl::StrCat("truncated: ", size, " bytes, less than a header"));
  }
  uint32_t version = 0;
  uint64_t recorded = 0;
  std::memcpy(&version, p + 8, 4);
  std::memcpy(&recorded, p + 16, 8);
  if (version != kAccelerationDataVersion) {
    return Refused(absl::StrCat("format version ", version, "; this Tessera reads version ",
                                kAccelerationDataVersion, " (rebuild and save it again)"));
  }
  if (recorded != size) {
    return Refused(absl::StrCat(recorded > size ? "truncated" : "has trailing bytes", ": ", size,
                                " bytes where the header says ", recorded));
  }
  uint64_t checksum = 0;
  std::memcpy(&checksum, p + size - kChecksumBytes, 8);
  if (checksum != Hash64(p, size - kChecksumBytes)) {
    return Refused("corrupted (checksum mismatch)");
  }
  Reader r(p + kHeaderBytes, size - kHeaderBytes - kChecksumBytes);
  const absl::Status malformed = Refused("malformed (its fields do not fit its size)");
  std::string platform;
  if (!r.Str(&platform)) return malformed;
  if (platform != AccelerationDataPlatform()) {
    return Refused(
        absl::StrCat("made on '", platform, "'; this is '", AccelerationDataPlatform(), "'"));
  }
  AccelerationBlob blob;
  uint32_t count = 0;
  if (!r.Str(&blob.builder) || !r.Str(&blob.traverser) || !r.U32(&count)) return malformed;
  for (uint32_t i = 0; i < count; ++i) {
    std::string name, value;
    if (!r.Str(&name) || !r.Str(&value)) return malformed;
    blob.properties[name] = value;
  }
  if (!r.U32(&blob.node_kind) || !r.U32(&count)) return malformed;
  if (blob.node_kind != RT_OBJECTTYPE_GEOMETRY_GROUP && blob.node_kind != RT_OBJECTTYPE_GROUP) {
    return Refused(absl::StrCat("malformed (node kind ", blob.node_kind, ")"));
  }
  // Each input takes at least 17 bytes: a count past that cannot be real (and must not allocate).
  if (count > r.Left() / 17) return malformed;
  blob.inputs.resize(count);
  blob.bounds.resize(count);
  for (uint32_t i = 0; i < count; ++i) {
    BuildInput& in = blob.inputs[i];
    uint8_t has = 0;
    if (!r.U32(&in.kind) || !r.U64(&in.primitive_count) || !r.Str(&in.bounds_program) ||
        !r.U8(&has) || has > 1) {
      return malformed;
    }
    if (has == 0) continue;
    if (in.primitive_count > r.Left() / (6 * sizeof(float))) return malformed;
    blob.bounds[i].resize(in.primitive_count * 6);
    if (!r.Raw(blob.bounds[i].data(), in.primitive_count * 6 * sizeof(float))) return malformed;
  }
  if (r.Left() != 0) return malformed;
  return blob;
}

std::string DescribeInputMismatch(const std::vector<BuildInput>& saved,
                                  const std::vector<BuildInput>& now) {
  if (saved.size() != now.size()) {
    return absl::StrCat("it was built over ", saved.size(), " children, the node now has ",
                        now.size());
  }
  for (size_t i = 0; i < saved.size(); ++i) {
    const BuildInput& a = saved[i];
    const BuildInput& b = now[i];
    if (a.kind != b.kind) {
      return absl::StrCat("child ", i, " was of object type ", a.kind, ", now ", b.kind);
    }
    if (a.primitive_count != b.primitive_count) {
      return absl::StrCat("child ", i, " had ", a.primitive_count, " primitives, now ",
                          b.primitive_count);
    }
    if (a.bounds_program != b.bounds_program) {
      return absl::StrCat("child ", i, "'s bounding-box program was ", a.bounds_program, ", now ",
                          b.bounds_program);
    }
  }
  return "";
}

}  // namespace tessera::api
