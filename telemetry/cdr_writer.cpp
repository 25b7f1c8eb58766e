#include "telemetry/cdr_writer.h"

#include <cstring>

namespace aerograsp {

namespace {
constexpr std::size_t kHeaderSize = 4;
static_assert(sizeof(float) == 4 && sizeof(double) == 8, "IEEE 754 float and double");
}  // namespace

CdrWriter::CdrWriter() : bytes_{0x00, 0x01, 0x00, 0x00} {}  // CDR_LE, no options

void CdrWriter::Align(std::size_t size) {
  const std::size_t offset = bytes_.size() - kHeaderSize;
  const std::size_t pad = (size - offset % size) % size;
  bytes_.insert(bytes_.end(), pad, 0);
}

template <typename T>
void CdrWriter::Primitive(T v) {
  Align(sizeof(T));
  std::uint8_t raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));
#if __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
#endif
  bytes_.insert(bytes_.end(), raw, raw + sizeof(T));
}

void CdrWriter::UInt8(std::uint8_t v) { bytes_.push_back(v); }
void CdrWriter::UInt16(std::uint16_t v) { Primitive(v); }
void CdrWriter::Int32(std::int32_t v) { Primitive(v); }
void CdrWriter::UInt32(std::uint32_t v) { Primitive(v); }
void CdrWriter::Int64(std::int64_t v) { Primitive(v); }
void CdrWriter::UInt64(std::uint64_t v) { Primitive(v); }
void CdrWriter::Float32(float v) { Primitive(v); }
void CdrWriter::Float64(double v) { Primitive(v); }

void CdrWriter::String(const std::string& v) {
  UInt32(static_cast<std::uint32_t>(v.size() + 1));
  bytes_.insert(bytes_.end(), v.begin(), v.end());
  bytes_.push_back(0);
}

void CdrWriter::SequenceLength(std::size_t n) { UInt32(static_cast<std::uint32_t>(n)); }

void CdrWriter::ByteSequence(const std::uint8_t* data, std::size_t size) {
  SequenceLength(size);
  bytes_.insert(bytes_.end(), data, data + size);
}

void CdrWriter::Float64Sequence(const std::vector<double>& v) {
  SequenceLength(v.size());
  for (double x : v) Float64(x);
}

void CdrWriter::StringSequence(const std::vector<std::string>& v) {
  SequenceLength(v.size());
  for (const std::string& s : v) String(s);
}

}  // namespace aerograsp
