// An MCAP writer (the format of mcap.dev/spec, major version 0): messages
// batched in chunks (optionally lz4- or zstd-compressed, each with the CRC32 of
// its records), a message index per channel after each chunk, then the data
// end (with the data section's CRC32), the summary (schemas, channels,
// statistics with per-channel counts, chunk and metadata indexes), the
// summary offsets and the footer (with the summary's CRC32), so readers seek
// by time and topic without scanning.
//
// Failures (a full disk, a file-size limit, an I/O error) never throw from
// Write or Close: the file is cut back to its last complete chunk and its
// indexes, so a streaming reader reads everything up to there; the writer
// keeps the error and ignores later calls.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace aerograsp {

/// CRC-32 (ISO-HDLC, as zlib), continuing from `crc` (0 to start).
std::uint32_t Crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0);

struct McapWriterOptions {
  std::string profile = "ros2";       ///< the Header's profile
  std::string library = "aerograsp";  ///< the Header's library
  std::string compression = "zstd";   ///< "none" | "lz4" | "zstd"
  /// A chunk is closed once its uncompressed records pass this size.
  std::size_t chunk_size_bytes = 1 << 20;
};

class McapWriter {
 public:
  /// Creates `path` (truncating it) and writes the magic and the header.
  /// @throws std::runtime_error naming the path and the reason when it cannot
  /// be created or written; std::invalid_argument for an unknown compression.
  McapWriter(const std::string& path, const McapWriterOptions& options);
  /// Closes the file if Close was not called.
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// A schema (ids from 1); `encoding` e.g. "ros2msg".
  std::uint16_t AddSchema(const std::string& name, const std::string& encoding,
                          const std::string& data);
  /// A channel (ids from 0) of messages in `message_encoding` (e.g. "cdr").
  std::uint16_t AddChannel(std::uint16_t schema_id, const std::string& topic,
                           const std::string& message_encoding,
                           const std::map<std::string, std::string>& metadata = {});
  /// A message on `channel` (its sequence counts the channel's messages).
  /// Times in nanoseconds; messages may come in any time order.
  void Write(std::uint16_t channel, std::uint64_t log_time_ns, std::uint64_t publish_time_ns,
             const std::vector<std::uint8_t>& data);
  /// A metadata record (name and key-value pairs), indexed in the summary.
  void AddMetadata(const std::string& name, const std::map<std::string, std::string>& values);
  /// Writes the open chunk, the summary and the footer, and closes the file.
  void Close();

  bool failed() const { return !error_.empty(); }
  /// What failed, with the path ("" while all is well).
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }
  std::uint64_t message_count() const { return message_count_; }
  /// Bytes in the file so far (complete records only after a failure).
  std::uint64_t bytes_written() const { return offset_; }

 private:
  struct ChunkIndexEntry {
    std::uint64_t start_time = 0, end_time = 0, chunk_offset = 0, chunk_length = 0;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
    std::uint64_t index_length = 0, compressed_size = 0, uncompressed_size = 0;
  };
  struct Schema {
    std::string name, encoding, data;
  };
  struct Channel {
    std::uint16_t schema_id = 0;
    std::string topic, encoding;
    std::map<std::string, std::string> metadata;
  };

  void FlushChunk();
  /// Appends `bytes` to the file, the data-section CRC running when `data`.
  bool Emit(const std::vector<std::uint8_t>& bytes, bool data);
  void Fail(const std::string& what, int errno_value);

  std::string path_;
  McapWriterOptions options_;
  int fd_ = -1;
  bool closed_ = false;
  std::string error_;
  std::uint64_t offset_ = 0;             // bytes in the file
  std::uint32_t data_crc_ = 0;           // running CRC of the data section
  std::vector<Schema> schemas_;          // id - 1
  std::vector<Channel> channels_;        // id
  std::vector<std::uint32_t> sequence_;  // per channel
  std::vector<std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0;
  std::uint64_t start_time_ = 0, end_time_ = 0;

  // The open chunk: its uncompressed records and per-channel message index.
  std::vector<std::uint8_t> chunk_;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  bool chunk_has_messages_ = false;
  std::vector<ChunkIndexEntry> chunk_indexes_;
  struct MetadataEntry {
    std::uint64_t offset = 0, length = 0;
    std::string name;
  };
  std::vector<MetadataEntry> metadata_;
};

}  // namespace aerograsp
