#include "telemetry/mcap_writer.h"

#include <fcntl.h>
#include <lz4frame.h>
#include <unistd.h>
#include <zstd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace aerograsp {
namespace {

enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr int kZstdLevel = 3;

/// Little-endian serialisation of a record's fields (mcap.dev/spec, "Serialization").
class Bytes {
 public:
  void U8(std::uint8_t v) { b_.push_back(v); }
  void U16(std::uint16_t v) { Le(v, 2); }
  void U32(std::uint32_t v) { Le(v, 4); }
  void U64(std::uint64_t v) { Le(v, 8); }
  void Str(const std::string& s) {
    U32(static_cast<std::uint32_t>(s.size()));
    b_.insert(b_.end(), s.begin(), s.end());
  }
  void Raw(const std::uint8_t* data, std::size_t size) { b_.insert(b_.end(), data, data + size); }
  void Raw(const std::vector<std::uint8_t>& v) { b_.insert(b_.end(), v.begin(), v.end()); }
  void StrMap(const std::map<std::string, std::string>& m) {
    Bytes inner;
    for (const auto& [k, v] : m) inner.Str(k), inner.Str(v);
    U32(static_cast<std::uint32_t>(inner.b_.size()));
    Raw(inner.b_);
  }
  template <typename Value>
  void U16Map(const std::map<std::uint16_t, Value>& m) {
    U32(static_cast<std::uint32_t>(m.size() * (2 + sizeof(Value))));
    for (const auto& [k, v] : m) U16(k), Le(v, sizeof(Value));
  }
  std::vector<std::uint8_t>& bytes() { return b_; }

 private:
  void Le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t> b_;
};

/// <opcode><uint64 content length><content> appended to `out`.
void AppendRecord(Op op, Bytes& content, std::vector<std::uint8_t>* out) {
  Bytes head;
  head.U8(op);
  head.U64(content.bytes().size());
  out->insert(out->end(), head.bytes().begin(), head.bytes().end());
  out->insert(out->end(), content.bytes().begin(), content.bytes().end());
}

const std::array<std::uint32_t, 256>& CrcTable() {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  return table;
}

std::string CompressionName(const std::string& option) {
  if (option == "none") return "";
  if (option == "lz4" || option == "zstd") return option;
  throw std::invalid_argument("MCAP compression '" + option + "' is not one of none, lz4, zstd");
}

std::vector<std::uint8_t> Compress(const std::string& compression,
                                   const std::vector<std::uint8_t>& in) {
  std::vector<std::uint8_t> out;
  if (compression == "zstd") {
    out.resize(ZSTD_compressBound(in.size()));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), kZstdLevel);
    if (ZSTD_isError(n)) throw std::runtime_error(ZSTD_getErrorName(n));
    out.resize(n);
  } else {  // lz4, frame format
    out.resize(LZ4F_compressFrameBound(in.size(), nullptr));
    const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), nullptr);
    if (LZ4F_isError(n)) throw std::runtime_error(LZ4F_getErrorName(n));
    out.resize(n);
  }
  return out;
}

}  // namespace

std::uint32_t Crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc) {
  const auto& table = CrcTable();
  std::uint32_t c = crc ^ 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) c = table[(c ^ data[i]) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

McapWriter::McapWriter(const std::string& path, const McapWriterOptions& options)
    : path_(path), options_(options) {
  options_.compression = CompressionName(options.compression);
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw std::runtime_error(path + ": cannot be created: " + std::strerror(errno));
  }
  std::vector<std::uint8_t> start(kMagic, kMagic + 8);
  Bytes header;
  header.Str(options_.profile);
  header.Str(options_.library);
  AppendRecord(kHeader, header, &start);
  if (!Emit(start, true)) {
    const std::string error = error_;
    throw std::runtime_error(error);
  }
}

McapWriter::~McapWriter() {
  if (!closed_) Close();
}

void McapWriter::Fail(const std::string& what, int errno_value) {
  error_ =
      path_ + ": " + what + (errno_value ? std::string(": ") + std::strerror(errno_value) : "");
  if (fd_ >= 0) {
    // Back to the last complete record: what was written stays readable.
    if (::ftruncate(fd_, static_cast<off_t>(offset_)) != 0) {
      error_ += " (and the partial record could not be cut off)";
    }
    ::close(fd_);
    fd_ = -1;
  }
  chunk_.clear();
  chunk_index_.clear();
}

bool McapWriter::Emit(const std::vector<std::uint8_t>& bytes, bool data) {
  if (failed() || fd_ < 0) return false;
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      Fail("write failed after " + std::to_string(offset_) + " bytes", n < 0 ? errno : ENOSPC);
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  offset_ += bytes.size();
  if (data) data_crc_ = Crc32(bytes.data(), bytes.size(), data_crc_);
  return true;
}

std::uint16_t McapWriter::AddSchema(const std::string& name, const std::string& encoding,
                                    const std::string& data) {
  schemas_.push_back({name, encoding, data});
  const auto id = static_cast<std::uint16_t>(schemas_.size());
  Bytes r;
  r.U16(id);
  r.Str(name);
  r.Str(encoding);
  r.Str(data);
  AppendRecord(kSchema, r, &chunk_);  // in the chunk: a streaming reader meets it first
  return id;
}

std::uint16_t McapWriter::AddChannel(std::uint16_t schema_id, const std::string& topic,
                                     const std::string& message_encoding,
                                     const std::map<std::string, std::string>& metadata) {
  channels_.push_back({schema_id, topic, message_encoding, metadata});
  sequence_.push_back(0);
  channel_counts_.push_back(0);
  const auto id = static_cast<std::uint16_t>(channels_.size() - 1);
  Bytes r;
  r.U16(id);
  r.U16(schema_id);
  r.Str(topic);
  r.Str(message_encoding);
  r.StrMap(metadata);
  AppendRecord(kChannel, r, &chunk_);
  return id;
}

void McapWriter::Write(std::uint16_t channel, std::uint64_t log_time_ns,
                       std::uint64_t publish_time_ns, const std::vector<std::uint8_t>& data) {
  if (failed() || closed_ || channel >= channels_.size()) return;
  chunk_index_[channel].push_back({log_time_ns, chunk_.size()});
  Bytes r;
  r.U16(channel);
  r.U32(++sequence_[channel]);
  r.U64(log_time_ns);
  r.U64(publish_time_ns);
  r.Raw(data);
  AppendRecord(kMessage, r, &chunk_);
  if (!chunk_has_messages_ || log_time_ns < chunk_start_) chunk_start_ = log_time_ns;
  if (!chunk_has_messages_ || log_time_ns > chunk_end_) chunk_end_ = log_time_ns;
  if (message_count_ == 0 || log_time_ns < start_time_) start_time_ = log_time_ns;
  if (message_count_ == 0 || log_time_ns > end_time_) end_time_ = log_time_ns;
  chunk_has_messages_ = true;
  ++message_count_;
  ++channel_counts_[channel];
  if (chunk_.size() >= options_.chunk_size_bytes) FlushChunk();
}

void McapWriter::FlushChunk() {
  if (chunk_.empty() || failed()) return;
  ChunkIndexEntry entry;
  entry.start_time = chunk_has_messages_ ? chunk_start_ : 0;
  entry.end_time = chunk_has_messages_ ? chunk_end_ : 0;
  entry.chunk_offset = offset_;
  entry.uncompressed_size = chunk_.size();
  std::vector<std::uint8_t> out;
  {
    std::vector<std::uint8_t> compressed;
    try {
      if (!options_.compression.empty()) compressed = Compress(options_.compression, chunk_);
    } catch (const std::exception& e) {
      Fail(std::string("chunk compression failed: ") + e.what(), 0);
      return;
    }
    const std::vector<std::uint8_t>& records = options_.compression.empty() ? chunk_ : compressed;
    entry.compressed_size = records.size();
    Bytes r;
    r.U64(entry.start_time);
    r.U64(entry.end_time);
    r.U64(chunk_.size());
    r.U32(Crc32(chunk_.data(), chunk_.size()));
    r.Str(options_.compression);
    r.U64(records.size());
    r.Raw(records);
    AppendRecord(kChunk, r, &out);
  }
  entry.chunk_length = out.size();
  for (const auto& [channel, index] : chunk_index_) {
    entry.index_offsets[channel] = offset_ + out.size();
    Bytes r;
    r.U16(channel);
    r.U32(static_cast<std::uint32_t>(index.size() * 16));
    for (const auto& [time, offset] : index) r.U64(time), r.U64(offset);
    AppendRecord(kMessageIndex, r, &out);
  }
  entry.index_length = out.size() - entry.chunk_length;
  chunk_.clear();
  chunk_index_.clear();
  chunk_has_messages_ = false;
  if (Emit(out, true)) chunk_indexes_.push_back(std::move(entry));
}

void McapWriter::AddMetadata(const std::string& name,
                             const std::map<std::string, std::string>& values) {
  if (failed() || closed_) return;
  FlushChunk();  // metadata records live outside chunks
  Bytes r;
  r.Str(name);
  r.StrMap(values);
  std::vector<std::uint8_t> out;
  AppendRecord(kMetadata, r, &out);
  const std::uint64_t at = offset_;
  if (Emit(out, true)) metadata_.push_back({at, out.size(), name});
}

void McapWriter::Close() {
  if (closed_) return;
  closed_ = true;
  FlushChunk();
  if (failed()) return;
  std::vector<std::uint8_t> out;
  {
    Bytes r;
    r.U32(data_crc_);
    AppendRecord(kDataEnd, r, &out);
  }
  const std::uint64_t summary_start = offset_ + out.size();
  struct Group {
    Op op;
    std::uint64_t start, length;
  };
  std::vector<Group> groups;
  const auto group = [&](Op op, const auto& append_all) {
    const std::uint64_t start = offset_ + out.size();
    append_all();
    const std::uint64_t length = offset_ + out.size() - start;
    if (length > 0) groups.push_back({op, start, length});
  };
  group(kSchema, [&] {
    for (std::size_t i = 0; i < schemas_.size(); ++i) {
      Bytes r;
      r.U16(static_cast<std::uint16_t>(i + 1));
      r.Str(schemas_[i].name);
      r.Str(schemas_[i].encoding);
      r.Str(schemas_[i].data);
      AppendRecord(kSchema, r, &out);
    }
  });
  group(kChannel, [&] {
    for (std::size_t i = 0; i < channels_.size(); ++i) {
      Bytes r;
      r.U16(static_cast<std::uint16_t>(i));
      r.U16(channels_[i].schema_id);
      r.Str(channels_[i].topic);
      r.Str(channels_[i].encoding);
      r.StrMap(channels_[i].metadata);
      AppendRecord(kChannel, r, &out);
    }
  });
  group(kStatistics, [&] {
    Bytes r;
    r.U64(message_count_);
    r.U16(static_cast<std::uint16_t>(schemas_.size()));
    r.U32(static_cast<std::uint32_t>(channels_.size()));
    r.U32(0);  // attachments
    r.U32(static_cast<std::uint32_t>(metadata_.size()));
    r.U32(static_cast<std::uint32_t>(chunk_indexes_.size()));
    r.U64(message_count_ ? start_time_ : 0);
    r.U64(message_count_ ? end_time_ : 0);
    std::map<std::uint16_t, std::uint64_t> counts;
    for (std::size_t i = 0; i < channel_counts_.size(); ++i)
      counts[static_cast<std::uint16_t>(i)] = channel_counts_[i];
    r.U16Map(counts);
    AppendRecord(kStatistics, r, &out);
  });
  group(kChunkIndex, [&] {
    for (const ChunkIndexEntry& e : chunk_indexes_) {
      Bytes r;
      r.U64(e.start_time);
      r.U64(e.end_time);
      r.U64(e.chunk_offset);
      r.U64(e.chunk_length);
      r.U16Map(e.index_offsets);
      r.U64(e.index_length);
      r.Str(options_.compression);
      r.U64(e.compressed_size);
      r.U64(e.uncompressed_size);
      AppendRecord(kChunkIndex, r, &out);
    }
  });
  group(kMetadataIndex, [&] {
    for (const MetadataEntry& m : metadata_) {
      Bytes r;
      r.U64(m.offset);
      r.U64(m.length);
      r.Str(m.name);
      AppendRecord(kMetadataIndex, r, &out);
    }
  });
  const std::uint64_t summary_offset_start = offset_ + out.size();
  for (const Group& g : groups) {
    Bytes r;
    r.U8(g.op);
    r.U64(g.start);
    r.U64(g.length);
    AppendRecord(kSummaryOffset, r, &out);
  }
  // The footer; the summary CRC runs from the summary's start through the
  // footer's summary_offset_start.
  Bytes footer;
  footer.U8(kFooter);
  footer.U64(8 + 8 + 4);
  footer.U64(summary_start);
  footer.U64(summary_offset_start);
  const std::size_t summary_from = summary_start - offset_;
  std::uint32_t crc = Crc32(out.data() + summary_from, out.size() - summary_from);
  crc = Crc32(footer.bytes().data(), footer.bytes().size(), crc);
  footer.U32(crc);
  footer.Raw(kMagic, 8);
  out.insert(out.end(), footer.bytes().begin(), footer.bytes().end());
  if (!Emit(out, false)) return;
  if (::close(fd_) != 0) Fail("close failed", errno);
  fd_ = -1;
}

}  // namespace aerograsp
