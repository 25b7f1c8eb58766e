// A little-endian CDR encoder (OMG CDR as ROS 2's rmw layers write it, XCDR1
// plain: the 4-byte encapsulation header 00 01 00 00, then each primitive
// aligned to its own size, at most 8, counted from the byte after the
// header). Strings are a uint32 length including the terminating NUL, the
// bytes, the NUL; sequences a uint32 element count, then the elements;
// fixed arrays the elements only.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace aerograsp {

class CdrWriter {
 public:
  CdrWriter();

  void Bool(bool v) { UInt8(v ? 1 : 0); }
  void UInt8(std::uint8_t v);
  void UInt16(std::uint16_t v);
  void Int32(std::int32_t v);
  void UInt32(std::uint32_t v);
  void Int64(std::int64_t v);
  void UInt64(std::uint64_t v);
  void Float32(float v);
  void Float64(double v);
  void String(const std::string& v);
  /// A sequence's element count (the elements follow, written by the caller).
  void SequenceLength(std::size_t n);
  /// uint8[] as a sequence: the count, then the bytes.
  void ByteSequence(const std::uint8_t* data, std::size_t size);
  /// float64[] as a sequence: the count, then the values.
  void Float64Sequence(const std::vector<double>& v);
  /// string[] as a sequence.
  void StringSequence(const std::vector<std::string>& v);

  /// The encoded bytes, header included.
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  std::vector<std::uint8_t> Take() { return std::move(bytes_); }

 private:
  template <typename T>
  void Primitive(T v);
  void Align(std::size_t size);
  std::vector<std::uint8_t> bytes_;
};

}  // namespace aerograsp
