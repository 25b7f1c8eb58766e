#include "grasp/contact_cache.h"

#include <cstring>
#include <sstream>

namespace aerograsp {
namespace {

constexpr char kMagic[8] = {'A', 'G', 'C', 'O', 'N', 'T', 'A', 'C'};
constexpr std::uint32_t kVersion = 1;

bool HostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

class Writer {
 public:
  template <typename T>
  void Put(const T& v) {
    char buf[sizeof(T)];
    std::memcpy(buf, &v, sizeof(T));
    out_.append(buf, sizeof(T));
  }
  void PutVector(const Eigen::Vector3d& v) {
    for (int k = 0; k < 3; ++k) Put(v[k]);
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(const std::string& bytes, std::size_t end) : bytes_(bytes), end_(end) {}
  template <typename T>
  bool Get(T* v) {
    if (pos_ + sizeof(T) > end_) return false;
    std::memcpy(v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return true;
  }
  bool GetVector(Eigen::Vector3d* v) {
    for (int k = 0; k < 3; ++k) {
      if (!Get(&(*v)[k])) return false;
    }
    return true;
  }
  std::size_t remaining() const { return end_ - pos_; }

 private:
  const std::string& bytes_;
  std::size_t end_;
  std::size_t pos_ = 0;
};

constexpr std::size_t kPairBytes = 12 * sizeof(double) + sizeof(std::int32_t);

}  // namespace

std::uint64_t Fnv1a64(const void* data, std::size_t size, std::uint64_t seed) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = seed;
  for (std::size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

std::uint64_t HashMesh(const TriangleMesh& mesh) {
  std::uint64_t h = Fnv1a64(nullptr, 0);
  const std::uint64_t counts[2] = {mesh.vertices.size(), mesh.triangles.size()};
  h = Fnv1a64(counts, sizeof(counts), h);
  for (const Eigen::Vector3d& v : mesh.vertices) h = Fnv1a64(v.data(), 3 * sizeof(double), h);
  for (const Eigen::Vector3i& t : mesh.triangles) h = Fnv1a64(t.data(), 3 * sizeof(int), h);
  return h;
}

ContactCacheKey MakeContactCacheKey(const TriangleMesh& mesh, const GripperConfig& gripper,
                                    const ContactOptions& options) {
  return {HashMesh(mesh), options.resolution_m, gripper.max_aperture_m, gripper.finger_clearance_m};
}

const char* CacheStatusName(CacheStatus status) {
  switch (status) {
    case CacheStatus::kOk:
      return "ok";
    case CacheStatus::kStale:
      return "stale";
    case CacheStatus::kCorrupt:
      return "corrupt";
  }
  return "?";
}

std::string SerializeContacts(const ContactSet& contacts, const ContactCacheKey& key) {
  Writer w;
  w.bytes().append(kMagic, sizeof(kMagic));
  w.Put(kVersion);
  w.Put(key.mesh_hash);
  w.Put(key.resolution_m);
  w.Put(key.max_aperture_m);
  w.Put(key.finger_clearance_m);
  for (std::int32_t v :
       {contacts.rays, contacts.rays_hit, contacts.rays_skipped, contacts.pairs_too_wide}) {
    w.Put(v);
  }
  w.Put(contacts.max_width_m);
  w.Put(static_cast<std::uint64_t>(contacts.pairs.size()));
  for (const ContactPair& p : contacts.pairs) {
    w.PutVector(p.a.p_o);
    w.PutVector(p.a.n_o);
    w.PutVector(p.b.p_o);
    w.PutVector(p.b.n_o);
    w.Put(static_cast<std::int32_t>(p.axis));
  }
  w.Put(Fnv1a64(w.bytes().data(), w.bytes().size()));
  return std::move(w.bytes());
}

CacheReadResult DeserializeContacts(const std::string& bytes, const ContactCacheKey& expected,
                                    ContactSet* contacts) {
  auto corrupt = [](const std::string& why) { return CacheReadResult{CacheStatus::kCorrupt, why}; };
  if (!HostIsLittleEndian()) return corrupt("big-endian host: the cache format is little-endian");
  if (bytes.size() < sizeof(kMagic) + sizeof(std::uint32_t) + sizeof(std::uint64_t) ||
      std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    return corrupt("not an aerograsp contact cache (bad magic or too short)");
  }
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t stored_sum;
  std::memcpy(&stored_sum, bytes.data() + body, sizeof(stored_sum));
  Reader r(bytes, body);
  char magic[sizeof(kMagic)];
  for (char& c : magic) r.Get(&c);
  std::uint32_t version = 0;
  r.Get(&version);
  if (version != kVersion) {
    return {CacheStatus::kStale,
            "format version " + std::to_string(version) + ", expected " + std::to_string(kVersion)};
  }
  if (Fnv1a64(bytes.data(), body) != stored_sum) return corrupt("checksum mismatch");
  ContactCacheKey key;
  ContactSet set;
  std::int32_t counts[4];
  std::uint64_t n = 0;
  if (!r.Get(&key.mesh_hash) || !r.Get(&key.resolution_m) || !r.Get(&key.max_aperture_m) ||
      !r.Get(&key.finger_clearance_m) || !r.Get(&counts[0]) || !r.Get(&counts[1]) ||
      !r.Get(&counts[2]) || !r.Get(&counts[3]) || !r.Get(&set.max_width_m) || !r.Get(&n)) {
    return corrupt("truncated header");
  }
  if (!(key == expected)) {
    std::ostringstream why;
    why << "key mismatch: file has mesh hash " << std::hex << key.mesh_hash << std::dec
        << ", resolution " << key.resolution_m << " m, aperture " << key.max_aperture_m
        << " m, clearance " << key.finger_clearance_m << " m; wanted mesh hash " << std::hex
        << expected.mesh_hash << std::dec << ", resolution " << expected.resolution_m
        << " m, aperture " << expected.max_aperture_m << " m, clearance "
        << expected.finger_clearance_m << " m";
    return {CacheStatus::kStale, why.str()};
  }
  if (n != r.remaining() / kPairBytes || r.remaining() % kPairBytes != 0) {
    return corrupt("pair count " + std::to_string(n) + " does not match the " +
                   std::to_string(r.remaining()) + " bytes that follow");
  }
  set.resolution_m = key.resolution_m;
  set.rays = counts[0];
  set.rays_hit = counts[1];
  set.rays_skipped = counts[2];
  set.pairs_too_wide = counts[3];
  set.pairs.resize(n);
  for (ContactPair& p : set.pairs) {
    std::int32_t axis = 0;
    r.GetVector(&p.a.p_o);
    r.GetVector(&p.a.n_o);
    r.GetVector(&p.b.p_o);
    r.GetVector(&p.b.n_o);
    r.Get(&axis);
    if (axis < 0 || axis > 2 || !p.a.p_o.allFinite() || !p.b.p_o.allFinite()) {
      return corrupt("a pair has a bad axis or a non-finite point");
    }
    p.axis = axis;
  }
  *contacts = std::move(set);
  return {CacheStatus::kOk, ""};
}

}  // namespace aerograsp
