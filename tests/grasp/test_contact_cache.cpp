#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "grasp/contact_cache.h"
#include "tests/common/test_meshes.h"

namespace aerograsp {
namespace {

using ::testing::HasSubstr;

class ContactCacheTest : public ::testing::Test {
 protected:
  ContactCacheTest()
      : mesh_(test::BoxMesh(Eigen::Vector3d(0.08, 0.06, 0.04))),
        contacts_(ComputeContactPairs(mesh_, GripperConfig{}, ContactOptions{})),
        key_(MakeContactCacheKey(mesh_, GripperConfig{}, ContactOptions{})),
        bytes_(SerializeContacts(contacts_, key_)) {}
  TriangleMesh mesh_;
  ContactSet contacts_;
  ContactCacheKey key_;
  std::string bytes_;
};

TEST_F(ContactCacheTest, RoundTripRestoresEveryPair) {
  ContactSet read;
  const CacheReadResult r = DeserializeContacts(bytes_, key_, &read);
  ASSERT_EQ(r.status, CacheStatus::kOk) << r.reason;
  ASSERT_EQ(read.pairs.size(), contacts_.pairs.size());
  EXPECT_EQ(read.rays, contacts_.rays);
  EXPECT_EQ(read.resolution_m, contacts_.resolution_m);
  for (std::size_t i = 0; i < read.pairs.size(); ++i) {
    EXPECT_EQ(read.pairs[i].a.p_o, contacts_.pairs[i].a.p_o);
    EXPECT_EQ(read.pairs[i].b.n_o, contacts_.pairs[i].b.n_o);
    EXPECT_EQ(read.pairs[i].axis, contacts_.pairs[i].axis);
  }
}

TEST_F(ContactCacheTest, OtherResolutionOrGripperOrMeshIsStale) {
  ContactSet read;
  ContactCacheKey other = key_;
  other.resolution_m = 0.01;
  CacheReadResult r = DeserializeContacts(bytes_, other, &read);
  EXPECT_EQ(r.status, CacheStatus::kStale);
  EXPECT_THAT(r.reason, HasSubstr("resolution 0.015 m"));
  other = key_;
  other.max_aperture_m = 0.15;
  EXPECT_EQ(DeserializeContacts(bytes_, other, &read).status, CacheStatus::kStale);
  TriangleMesh moved = mesh_;
  moved.vertices[0].x() += 1e-9;
  EXPECT_NE(HashMesh(moved), key_.mesh_hash);
  EXPECT_EQ(DeserializeContacts(
                bytes_, MakeContactCacheKey(moved, GripperConfig{}, ContactOptions{}), &read)
                .status,
            CacheStatus::kStale);
  EXPECT_TRUE(read.pairs.empty());  // never filled from a rejected blob
}

TEST_F(ContactCacheTest, NewerFormatVersionIsStale) {
  std::string bytes = bytes_;
  bytes[8] = 2;  // the u32 version follows the 8-byte magic
  ContactSet read;
  const CacheReadResult r = DeserializeContacts(bytes, key_, &read);
  EXPECT_EQ(r.status, CacheStatus::kStale);
  EXPECT_THAT(r.reason, HasSubstr("version 2"));
}

TEST_F(ContactCacheTest, FlippedByteTruncationAndGarbageAreCorrupt) {
  ContactSet read;
  std::string flipped = bytes_;
  flipped[bytes_.size() / 2] ^= 0x40;
  CacheReadResult r = DeserializeContacts(flipped, key_, &read);
  EXPECT_EQ(r.status, CacheStatus::kCorrupt);
  EXPECT_THAT(r.reason, HasSubstr("checksum"));
  EXPECT_EQ(DeserializeContacts(bytes_.substr(0, bytes_.size() - 20), key_, &read).status,
            CacheStatus::kCorrupt);
  EXPECT_EQ(DeserializeContacts("ply\nformat ascii 1.0\n", key_, &read).status,
            CacheStatus::kCorrupt);
  EXPECT_EQ(DeserializeContacts("", key_, &read).status, CacheStatus::kCorrupt);
  EXPECT_TRUE(read.pairs.empty());
}

}  // namespace
}  // namespace aerograsp
