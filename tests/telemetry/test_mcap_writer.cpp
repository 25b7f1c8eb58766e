#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "telemetry/mcap_sink.h"
#include "telemetry/mcap_writer.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

const Bytes kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

fs::path TempFile(const std::string& name) {
  return fs::temp_directory_path() /
         ("aerograsp_mcap_" + name + "_" + std::to_string(getpid()) + ".mcap");
}

Bytes ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}

std::uint64_t Le(const Bytes& b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= std::uint64_t(b.at(at + i)) << (8 * i);
  return v;
}

struct Record {
  std::uint8_t op;
  std::size_t offset;    // of the opcode
  std::size_t content;   // of the content
  std::uint64_t length;  // of the content
};

/// The records after the leading magic, up to the footer (or the end).
std::vector<Record> Records(const Bytes& file) {
  std::vector<Record> records;
  std::size_t at = 8;
  while (at + 9 <= file.size()) {
    const Record r{file[at], at, at + 9, Le(file, at + 1, 8)};
    if (r.content + r.length > file.size()) break;  // cut short
    records.push_back(r);
    at = r.content + r.length;
    if (r.op == 0x02) break;
  }
  return records;
}

Bytes Payload(std::uint8_t fill, std::size_t n) { return Bytes(n, fill); }

TEST(Crc32Test, MatchesTheStandardCheckValue) {
  const std::string text = "123456789";
  EXPECT_EQ(Crc32(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), 0xCBF43926u);
  // Continuing a CRC over a split buffer gives the same value.
  const auto* p = reinterpret_cast<const std::uint8_t*>(text.data());
  EXPECT_EQ(Crc32(p + 4, 5, Crc32(p, 4)), 0xCBF43926u);
}

class McapWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = TempFile("records");
    McapWriterOptions options;
    options.compression = "none";
    options.chunk_size_bytes = 100;  // a chunk after every second message
    McapWriter w(path_.string(), options);
    const std::uint16_t schema = w.AddSchema("std_msgs/msg/String", "ros2msg", "string data\n");
    const std::uint16_t a = w.AddChannel(schema, "/a", "cdr", {{"k", "v"}});
    const std::uint16_t b = w.AddChannel(schema, "/b", "cdr");
    for (int k = 0; k < 5; ++k) w.Write(k % 2 ? b : a, 1000 + k, 1000 + k, Payload(k, 40));
    w.AddMetadata("run", {{"seed", "1"}});
    w.Close();
    EXPECT_FALSE(w.failed()) << w.error();
    file_ = ReadAll(path_);
    records_ = Records(file_);
  }
  void TearDown() override { fs::remove(path_); }
  std::vector<Record> Of(std::uint8_t op) const {
    std::vector<Record> out;
    for (const Record& r : records_)
      if (r.op == op) out.push_back(r);
    return out;
  }
  fs::path path_;
  Bytes file_;
  std::vector<Record> records_;
};

TEST_F(McapWriterTest, MagicAtBothEndsHeaderFirstFooterLast) {
  ASSERT_GT(file_.size(), 16u);
  EXPECT_EQ(Bytes(file_.begin(), file_.begin() + 8), kMagic);
  EXPECT_EQ(Bytes(file_.end() - 8, file_.end()), kMagic);
  ASSERT_FALSE(records_.empty());
  EXPECT_EQ(records_.front().op, 0x01);
  EXPECT_EQ(records_.back().op, 0x02);
  EXPECT_EQ(records_.back().content + records_.back().length + 8, file_.size());
}

TEST_F(McapWriterTest, ChunksCarryTheirRecordsCrcAndAreFollowedByMessageIndexes) {
  const std::vector<Record> chunks = Of(0x06);
  ASSERT_EQ(chunks.size(), 3u);  // 2 + 2 + 1 messages
  for (const Record& c : chunks) {
    const std::size_t at = c.content;
    const std::uint64_t uncompressed = Le(file_, at + 16, 8);
    const std::uint32_t crc = static_cast<std::uint32_t>(Le(file_, at + 24, 4));
    const std::uint64_t name_length = Le(file_, at + 28, 4);
    EXPECT_EQ(name_length, 0u);  // no compression
    const std::size_t records_at = at + 32 + name_length + 8;
    EXPECT_EQ(Le(file_, at + 32 + name_length, 8), uncompressed);
    EXPECT_EQ(crc, Crc32(file_.data() + records_at, uncompressed));
    // The next record is a message index.
    const std::size_t next = c.content + c.length;
    EXPECT_EQ(file_[next], 0x07);
  }
}

TEST_F(McapWriterTest, ChunkIndexesPointAtTheirChunksAndMessageIndexes) {
  const std::vector<Record> indexes = Of(0x08);
  const std::vector<Record> chunks = Of(0x06);
  ASSERT_EQ(indexes.size(), chunks.size());
  for (std::size_t i = 0; i < indexes.size(); ++i) {
    const std::size_t at = indexes[i].content;
    EXPECT_EQ(Le(file_, at + 16, 8), chunks[i].offset);
    EXPECT_EQ(Le(file_, at + 24, 8), chunks[i].length + 9);
    const std::uint64_t map_bytes = Le(file_, at + 32, 4);
    ASSERT_GT(map_bytes, 0u);
    for (std::size_t e = 0; e < map_bytes; e += 10) {
      const std::uint64_t index_offset = Le(file_, at + 36 + e + 2, 8);
      EXPECT_EQ(file_.at(index_offset), 0x07);
      EXPECT_EQ(Le(file_, index_offset + 9, 2), Le(file_, at + 36 + e, 2));  // same channel
    }
  }
}

TEST_F(McapWriterTest, MessageIndexOffsetsLandOnMessagesInTheChunk) {
  const Record chunk = Of(0x06).front();
  const std::size_t records_at = chunk.content + 32 + 8;
  for (const Record& index : Of(0x07)) {
    if (index.offset != chunk.content + chunk.length) continue;  // the first chunk's indexes
    const std::uint64_t entries = Le(file_, index.content + 2, 4) / 16;
    for (std::uint64_t e = 0; e < entries; ++e) {
      const std::uint64_t time = Le(file_, index.content + 6 + 16 * e, 8);
      const std::uint64_t offset = Le(file_, index.content + 6 + 16 * e + 8, 8);
      EXPECT_EQ(file_.at(records_at + offset), 0x05);                  // a message
      EXPECT_EQ(Le(file_, records_at + offset + 9 + 2 + 4, 8), time);  // its log time
    }
  }
}

TEST_F(McapWriterTest, StatisticsCountMessagesPerChannel) {
  const std::vector<Record> stats = Of(0x0B);
  ASSERT_EQ(stats.size(), 1u);
  const std::size_t at = stats[0].content;
  EXPECT_EQ(Le(file_, at, 8), 5u);       // messages
  EXPECT_EQ(Le(file_, at + 8, 2), 1u);   // schemas
  EXPECT_EQ(Le(file_, at + 10, 4), 2u);  // channels
  EXPECT_EQ(Le(file_, at + 18, 4), 1u);  // metadata
  EXPECT_EQ(Le(file_, at + 22, 4), 3u);  // chunks
  EXPECT_EQ(Le(file_, at + 26, 8), 1000u);
  EXPECT_EQ(Le(file_, at + 34, 8), 1004u);
  ASSERT_EQ(Le(file_, at + 42, 4), 20u);  // two (uint16, uint64) entries
  EXPECT_EQ(Le(file_, at + 46 + 2, 8), 3u);
  EXPECT_EQ(Le(file_, at + 56 + 2, 8), 2u);
}

TEST_F(McapWriterTest, FooterCrcsCoverTheSummaryAndTheDataSection) {
  const Record footer = records_.back();
  const std::uint64_t summary_start = Le(file_, footer.content, 8);
  const std::uint64_t summary_offset_start = Le(file_, footer.content + 8, 8);
  ASSERT_GT(summary_start, 0u);
  EXPECT_EQ(file_.at(summary_offset_start), 0x0E);
  const std::uint32_t summary_crc =
      Crc32(file_.data() + summary_start, footer.content + 16 - summary_start);
  EXPECT_EQ(Le(file_, footer.content + 16, 4), summary_crc);
  const std::size_t data_end = summary_start - 13;
  ASSERT_EQ(file_.at(data_end), 0x0F);
  EXPECT_EQ(Le(file_, data_end + 9, 4), Crc32(file_.data(), data_end));
}

TEST_F(McapWriterTest, SummaryOffsetsNameEachGroup) {
  std::vector<std::uint64_t> groups;
  for (const Record& r : Of(0x0E)) {
    const std::uint8_t op = file_[r.content];
    const std::uint64_t start = Le(file_, r.content + 1, 8);
    EXPECT_EQ(file_.at(start), op);
    groups.push_back(op);
  }
  EXPECT_THAT(groups, ::testing::ElementsAre(0x03, 0x04, 0x0B, 0x08, 0x0D));
}

TEST(McapWriterErrorsTest, UnwritablePathIsRefusedWithItsName) {
  const fs::path dir = TempFile("dir");
  fs::create_directories(dir);  // a folder where the file should be
  try {
    McapWriter w(dir.string(), {});
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(dir.string() + ": cannot be created"));
  }
  fs::remove_all(dir);
}

TEST(McapWriterErrorsTest, UnknownCompressionIsRefused) {
  McapWriterOptions options;
  options.compression = "gzip";
  EXPECT_THROW(McapWriter(TempFile("gzip").string(), options), std::invalid_argument);
}

// A file-size limit in a child process: past it the sink says so once, the
// run goes on, and the file ends on its last complete chunk and indexes.
TEST(McapSinkFullDiskTest, SaysSoOnceAndKeepsCompleteChunks) {
  const fs::path path = TempFile("full");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    signal(SIGXFSZ, SIG_IGN);
    rlimit limit{64 * 1024, 64 * 1024};
    if (setrlimit(RLIMIT_FSIZE, &limit) != 0) _exit(3);
    McapConfig config;
    config.compression = "none";
    config.chunk_size_kib = 16;
    config.state_rate_hz = 1000.0;
    int notes = 0;
    std::string note;
    McapSink sink(path.string(), config, [&](const std::string& line) { ++notes, note = line; });
    for (int k = 0; k < 3000; ++k)
      sink.Log(0.01 * k, TelemetryLevel::kInfo, "test", "a line of the run " + std::to_string(k));
    sink.Close();
    const bool said = note.find(path.string() + ": write failed after") != std::string::npos &&
                      note.find("stay readable") != std::string::npos;
    _exit(notes == 1 && said ? 0 : 2);
  }
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const Bytes file = ReadAll(path);
  ASSERT_LE(file.size(), 64u * 1024);
  EXPECT_EQ(Bytes(file.begin(), file.begin() + 8), kMagic);
  const std::vector<Record> records = Records(file);
  ASSERT_FALSE(records.empty());
  // Every byte belongs to a complete record; the last is a message index.
  EXPECT_EQ(records.back().content + records.back().length, file.size());
  EXPECT_EQ(records.back().op, 0x07);
  int chunks = 0;
  for (const Record& r : records) chunks += r.op == 0x06;
  EXPECT_GE(chunks, 2);
  fs::remove(path);
}

}  // namespace
}  // namespace aerograsp
