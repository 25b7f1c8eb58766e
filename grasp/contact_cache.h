// The contact cache (paper Sect. 4.1): the untransformed contacts of an object
// as a versioned binary blob keyed by the mesh's content, the grid resolution
// and the gripper, with a checksum. This module only converts between a
// ContactSet and bytes; the app reads and writes the file.
//
// Layout (little-endian): "AGCONTAC" | u32 version | u64 mesh hash |
// f64 resolution_m | f64 max_aperture_m | f64 finger_clearance_m |
// i32 rays, rays_hit, rays_skipped, pairs_too_wide | f64 max_width_m |
// u64 pair count | per pair: f64 a.p_o[3], a.n_o[3], b.p_o[3], b.n_o[3], i32 axis |
// u64 FNV-1a 64 checksum of every byte before it.
#pragma once

#include <cstdint>
#include <string>

#include "grasp/contacts.h"

namespace aerograsp {

/// What the cached contacts depend on.
struct ContactCacheKey {
  std::uint64_t mesh_hash = 0;  ///< HashMesh of the object's mesh
  double resolution_m = 0.0;
  double max_aperture_m = 0.0;
  double finger_clearance_m = 0.0;

  bool operator==(const ContactCacheKey& o) const {
    return mesh_hash == o.mesh_hash && resolution_m == o.resolution_m &&
           max_aperture_m == o.max_aperture_m && finger_clearance_m == o.finger_clearance_m;
  }
};

/// FNV-1a 64 of a byte range (the cache's checksum; also a content hash).
std::uint64_t Fnv1a64(const void* data, std::size_t size,
                      std::uint64_t seed = 14695981039346656037ull);

/// Content hash of a mesh: its vertices (as doubles) and triangle indices, in
/// order (colours are not part of the geometry and are left out).
std::uint64_t HashMesh(const TriangleMesh& mesh);

ContactCacheKey MakeContactCacheKey(const TriangleMesh& mesh, const GripperConfig& gripper,
                                    const ContactOptions& options);

/// The cache file's bytes for `contacts` computed under `key`.
std::string SerializeContacts(const ContactSet& contacts, const ContactCacheKey& key);

enum class CacheStatus {
  kOk,       ///< read, key and checksum match
  kStale,    ///< a valid file for another mesh, resolution, gripper or format version
  kCorrupt,  ///< not a cache file, truncated, or the checksum does not match
};
const char* CacheStatusName(CacheStatus status);

struct CacheReadResult {
  CacheStatus status = CacheStatus::kCorrupt;
  std::string reason;  ///< what did not match, for the log ("" when kOk)
};

/// Parses cache bytes; fills `contacts` only when the result is kOk, so a stale
/// or corrupt blob is never trusted.
CacheReadResult DeserializeContacts(const std::string& bytes, const ContactCacheKey& expected,
                                    ContactSet* contacts);

}  // namespace aerograsp
