// Mesh file formats: the PLY (ASCII, binary little/big endian), OBJ and STL
// (ASCII, binary) readers and the binary PLY writer. Standard library and
// Eigen only; each reader parses the whole file, already in memory, in one
// pass, so a 100k-triangle mesh loads in tens of milliseconds.
#include "core/mesh_formats.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

namespace aerograsp::mesh_formats {

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw MeshError(path + ": " + what);
}

std::string FormatNumber(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

namespace {

bool HostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// ---------------------------------------------------------------------------
// Text helpers

bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

// 1-based line number of byte offset `pos` (computed only for error messages).
std::size_t LineOf(const std::string& data, std::size_t pos) {
  pos = std::min(pos, data.size());
  return 1 + static_cast<std::size_t>(std::count(data.begin(), data.begin() + pos, '\n'));
}

// Parses a double at p (no leading spaces); returns the end or nullptr. Values
// out of range become +-infinity so that the finiteness check reports them.
const char* ParseDouble(const char* p, const char* end, double* value) {
  if (p < end && *p == '+') ++p;
  const std::from_chars_result r = std::from_chars(p, end, *value);
  if (r.ec == std::errc::invalid_argument) return nullptr;
  if (r.ec == std::errc::result_out_of_range) {
    // Overflow or underflow: strtod gives +-HUGE_VAL (caught later as
    // non-finite) or a zero/denormal, as the value deserves.
    *value = std::strtod(std::string(p, r.ptr).c_str(), nullptr);
  }
  return r.ptr;
}

// Splits one line (without its newline) into whitespace-separated tokens.
class LineTokens {
 public:
  LineTokens(const char* begin, const char* end) : p_(begin), end_(end) {}
  bool Next(std::string_view* token) {
    while (p_ < end_ && IsSpace(*p_)) ++p_;
    if (p_ == end_) return false;
    const char* start = p_;
    while (p_ < end_ && !IsSpace(*p_)) ++p_;
    *token = std::string_view(start, static_cast<std::size_t>(p_ - start));
    return true;
  }
  // Reads a whole token as a double; false if there is none or it is not a number.
  bool NextDouble(double* value) {
    std::string_view token;
    if (!Next(&token)) return false;
    const char* end = token.data() + token.size();
    return ParseDouble(token.data(), end, value) == end;
  }
  // The rest of the line, trimmed.
  std::string_view Rest() {
    while (p_ < end_ && IsSpace(*p_)) ++p_;
    const char* e = end_;
    while (e > p_ && IsSpace(e[-1])) --e;
    return std::string_view(p_, static_cast<std::size_t>(e - p_));
  }

 private:
  const char* p_;
  const char* end_;
};

// Iterates over the lines of a buffer, counting them.
class Lines {
 public:
  explicit Lines(const std::string& data) : p_(data.data()), end_(data.data() + data.size()) {}
  bool Next(const char** begin, const char** end) {
    if (p_ >= end_) return false;
    *begin = p_;
    const void* nl = std::memchr(p_, '\n', static_cast<std::size_t>(end_ - p_));
    const char* e = nl ? static_cast<const char*>(nl) : end_;
    *end = e;
    p_ = nl ? e + 1 : end_;
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }

 private:
  const char* p_;
  const char* end_;
  std::size_t number_ = 0;
};

std::string LinePrefix(std::size_t line) { return "line " + std::to_string(line) + ": "; }

std::uint8_t ColorByte(double value, double scale) {
  const double v = std::round(value * scale);
  if (!(v > 0.0)) return 0;
  if (v >= 255.0) return 255;
  return static_cast<std::uint8_t>(v);
}

// Appends the fan triangulation of a polygon (a, b, c, d, ...) -> (a,b,c), (a,c,d), ...
void AddFan(const int* indices, std::size_t count, std::vector<Eigen::Vector3i>* triangles) {
  for (std::size_t k = 1; k + 1 < count; ++k) {
    triangles->emplace_back(indices[0], indices[k], indices[k + 1]);
  }
}

// Merges exactly equal vertices (STL stores each triangle's corners
// separately): an open-addressing hash set of vertex indices. The points must
// be finite; -0.0 and +0.0 merge.
class VertexMerger {
 public:
  explicit VertexMerger(std::size_t expected) { Rehash(2 * expected); }

  int Add(const Eigen::Vector3d& p, std::vector<Eigen::Vector3d>* vertices) {
    if (2 * (vertices->size() + 1) > slots_.size()) Rehash(2 * slots_.size(), *vertices);
    std::size_t i = Hash(p) & mask_;
    while (slots_[i] >= 0) {
      if ((*vertices)[static_cast<std::size_t>(slots_[i])] == p) return slots_[i];
      i = (i + 1) & mask_;
    }
    slots_[i] = static_cast<int>(vertices->size());
    vertices->push_back(p);
    return slots_[i];
  }

 private:
  static std::size_t Hash(const Eigen::Vector3d& p) {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int a = 0; a < 3; ++a) {
      const double v = p[a] + 0.0;  // -0.0 becomes +0.0
      std::uint64_t bits = 0;
      std::memcpy(&bits, &v, sizeof(bits));
      h = (h ^ bits) * 0xBF58476D1CE4E5B9ull;
      h ^= h >> 29;
    }
    return static_cast<std::size_t>(h);
  }

  void Rehash(std::size_t capacity, const std::vector<Eigen::Vector3d>& vertices = {}) {
    std::size_t size = 16;
    while (size < capacity) size *= 2;
    slots_.assign(size, -1);
    mask_ = size - 1;
    for (std::size_t v = 0; v < vertices.size(); ++v) {
      std::size_t i = Hash(vertices[v]) & mask_;
      while (slots_[i] >= 0) i = (i + 1) & mask_;
      slots_[i] = static_cast<int>(v);
    }
  }

  std::vector<int> slots_;
  std::size_t mask_ = 0;
};

// ---------------------------------------------------------------------------
// PLY

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };
enum class PlyFormat { kAscii, kBinaryLittle, kBinaryBig };

bool ParsePlyType(std::string_view name, PlyType* type) {
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& entry : kNames) {
    if (name == entry.first) {
      *type = entry.second;
      return true;
    }
  }
  return false;
}

std::size_t SizeOf(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

bool IsFloatType(PlyType type) { return type == PlyType::kFloat32 || type == PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;  // the item type for a list
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t data_offset = 0;
};

PlyHeader ParsePlyHeader(const std::string& path, const std::string& data) {
  PlyHeader header;
  Lines lines(data);
  const char* begin = nullptr;
  const char* end = nullptr;
  if (!lines.Next(&begin, &end) || LineTokens(begin, end).Rest() != "ply") {
    Fail(path, "not a PLY file (the first line is not 'ply')");
  }
  bool have_format = false;
  bool have_end = false;
  while (lines.Next(&begin, &end)) {
    const std::string where = "line " + std::to_string(lines.number()) + " of the PLY header: ";
    LineTokens tokens(begin, end);
    std::string_view keyword;
    if (!tokens.Next(&keyword)) continue;
    if (keyword == "end_header") {
      have_end = true;
      header.data_offset = static_cast<std::size_t>(end - data.data());
      if (header.data_offset < data.size()) ++header.data_offset;  // the '\n'
      break;
    }
    if (keyword == "comment" || keyword == "obj_info") continue;
    std::string_view a, b, c, d;
    if (keyword == "format") {
      tokens.Next(&a);
      if (a == "ascii") {
        header.format = PlyFormat::kAscii;
      } else if (a == "binary_little_endian") {
        header.format = PlyFormat::kBinaryLittle;
      } else if (a == "binary_big_endian") {
        header.format = PlyFormat::kBinaryBig;
      } else {
        Fail(path, where + "unknown PLY format '" + std::string(a) +
                       "' (expected ascii, binary_little_endian or binary_big_endian)");
      }
      have_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      unsigned long long count = 0;
      if (!tokens.Next(&a) || !tokens.Next(&b) ||
          std::from_chars(b.data(), b.data() + b.size(), count).ptr != b.data() + b.size()) {
        Fail(path, where + "expected 'element NAME COUNT'");
      }
      element.name = std::string(a);
      element.count = static_cast<std::size_t>(count);
      header.elements.push_back(element);
    } else if (keyword == "property") {
      if (header.elements.empty()) Fail(path, where + "property before any element");
      PlyProperty property;
      if (!tokens.Next(&a)) Fail(path, where + "expected 'property TYPE NAME'");
      if (a == "list") {
        if (!tokens.Next(&b) || !tokens.Next(&c) || !tokens.Next(&d)) {
          Fail(path, where + "expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
        }
        property.is_list = true;
        if (!ParsePlyType(b, &property.count_type)) {
          Fail(path, where + "unknown property type '" + std::string(b) + "'");
        }
        if (IsFloatType(property.count_type)) {
          Fail(path, where + "list count type '" + std::string(b) + "' is not an integer type");
        }
        if (!ParsePlyType(c, &property.type)) {
          Fail(path, where + "unknown property type '" + std::string(c) + "'");
        }
        property.name = std::string(d);
      } else {
        if (!ParsePlyType(a, &property.type)) {
          Fail(path, where + "unknown property type '" + std::string(a) + "'");
        }
        if (!tokens.Next(&b)) Fail(path, where + "expected 'property TYPE NAME'");
        property.name = std::string(b);
      }
      header.elements.back().properties.push_back(property);
    } else {
      Fail(path, where + "unknown keyword '" + std::string(keyword) + "'");
    }
  }
  if (!have_end) Fail(path, "PLY header has no 'end_header' line");
  if (!have_format) Fail(path, "PLY header has no 'format' line");
  return header;
}

// Reads the values of a PLY body one by one, in ASCII or binary.
class PlyBodyReader {
 public:
  PlyBodyReader(const std::string& path, const std::string& data, const PlyHeader& header)
      : path_(path),
        data_(data),
        pos_(header.data_offset),
        ascii_(header.format == PlyFormat::kAscii),
        swap_(!ascii_ && ((header.format == PlyFormat::kBinaryLittle) != HostIsLittleEndian())) {}

  // Names the item being read, for error messages.
  void SetItem(const PlyElement* element, std::size_t index) {
    element_ = element;
    index_ = index;
  }

  double Double(PlyType type) {
    if (ascii_) return AsciiNumber();
    const char* p = Take(SizeOf(type));
    switch (type) {
      case PlyType::kInt8:
        return static_cast<std::int8_t>(*p);
      case PlyType::kUint8:
        return static_cast<std::uint8_t>(*p);
      case PlyType::kInt16:
        return Load<std::int16_t>(p);
      case PlyType::kUint16:
        return Load<std::uint16_t>(p);
      case PlyType::kInt32:
        return Load<std::int32_t>(p);
      case PlyType::kUint32:
        return Load<std::uint32_t>(p);
      case PlyType::kFloat32:
        return Load<float>(p);
      case PlyType::kFloat64:
        return Load<double>(p);
    }
    return 0.0;
  }

  // Every PLY integer type (at most 32 bits) is exact as a double, so one
  // decoder serves both; the check below rejects non-integral values.
  std::int64_t Int(PlyType type) {
    const std::size_t start = pos_;
    const double value = Double(type);
    if (!(std::abs(value) < 9e15) || value != std::floor(value)) {
      Fail(path_, Where(start) + "expected an integer, found " + FormatNumber(value));
    }
    return static_cast<std::int64_t>(value);
  }

  void Skip(const PlyProperty& property) {
    if (!property.is_list) {
      Double(property.type);
      return;
    }
    const std::int64_t count = Int(property.count_type);
    if (count < 0) Fail(path_, Where(pos_) + "negative list length " + std::to_string(count));
    if (!ascii_) {
      Take(static_cast<std::size_t>(count) * SizeOf(property.type));
    } else {
      for (std::int64_t k = 0; k < count; ++k) Double(property.type);
    }
  }

  std::string ItemName() const {
    return element_ ? element_->name + " " + std::to_string(index_) : std::string("data");
  }

  std::string Where(std::size_t pos) const {
    std::string where = ItemName() + ": ";
    if (ascii_) where = LinePrefix(LineOf(data_, pos)) + where;
    return where;
  }

 private:
  template <typename T>
  T Load(const char* p) const {
    char bytes[sizeof(T)];
    std::memcpy(bytes, p, sizeof(T));
    if (swap_) std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

  [[noreturn]] void Truncated() const {
    std::string what = "file is truncated: data ends";
    if (element_) {
      what += " in " + element_->name + " " + std::to_string(index_) + " of " +
              std::to_string(element_->count);
    }
    Fail(path_, what);
  }

  const char* Take(std::size_t bytes) {
    if (data_.size() - pos_ < bytes) Truncated();
    const char* p = data_.data() + pos_;
    pos_ += bytes;
    return p;
  }

  double AsciiNumber() {
    const char* end = data_.data() + data_.size();
    const char* p = data_.data() + pos_;
    while (p < end && IsSpace(*p)) ++p;
    if (p == end) Truncated();
    double value = 0.0;
    const char* next = ParseDouble(p, end, &value);
    if (next == nullptr || (next < end && !IsSpace(*next))) {
      const char* token_end = p;
      while (token_end < end && !IsSpace(*token_end)) ++token_end;
      Fail(path_, Where(static_cast<std::size_t>(p - data_.data())) + "expected a number, found '" +
                      std::string(p, token_end) + "'");
    }
    pos_ = static_cast<std::size_t>(next - data_.data());
    return value;
  }

  const std::string& path_;
  const std::string& data_;
  std::size_t pos_;
  bool ascii_;
  bool swap_;
  const PlyElement* element_ = nullptr;
  std::size_t index_ = 0;
};

int FindProperty(const PlyElement& element, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
      if (element.properties[i].name == name) return static_cast<int>(i);
    }
  }
  return -1;
}

}  // namespace

TriangleMesh LoadPly(const std::string& path, const std::string& data) {
  const PlyHeader header = ParsePlyHeader(path, data);
  const PlyElement* vertex_element = nullptr;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") vertex_element = &element;
  }
  if (vertex_element == nullptr) Fail(path, "PLY header declares no vertex element");
  const std::size_t vertex_count = vertex_element->count;

  TriangleMesh mesh;
  PlyBodyReader reader(path, data, header);
  std::vector<double> values;
  std::vector<int> polygon;
  for (const PlyElement& element : header.elements) {
    std::size_t min_item_bytes = 0;
    for (const PlyProperty& property : element.properties) {
      min_item_bytes += header.format == PlyFormat::kAscii
                            ? 2
                            : SizeOf(property.is_list ? property.count_type : property.type);
    }
    // A count the body cannot hold (a corrupt header) would otherwise spin or allocate.
    const std::size_t body_bytes = data.size() - header.data_offset;
    if (element.count > (body_bytes + 1) / std::max<std::size_t>(1, min_item_bytes) ||
        (element.count > 0 && element.properties.empty())) {
      Fail(path, "element '" + element.name + "' declares " + std::to_string(element.count) +
                     " entries of " + std::to_string(element.properties.size()) +
                     " properties, more than the " + std::to_string(body_bytes) +
                     " bytes after the header hold (corrupt header or truncated file?)");
    }
    const std::size_t reserve = element.count;
    if (&element == vertex_element) {
      const int ix = FindProperty(element, {"x"});
      const int iy = FindProperty(element, {"y"});
      const int iz = FindProperty(element, {"z"});
      if (ix < 0 || iy < 0 || iz < 0) Fail(path, "vertex element has no x, y and z properties");
      const int ir = FindProperty(element, {"red", "diffuse_red"});
      const int ig = FindProperty(element, {"green", "diffuse_green"});
      const int ib = FindProperty(element, {"blue", "diffuse_blue"});
      const bool has_color = ir >= 0 && ig >= 0 && ib >= 0;
      // Float colours are 0..1, integer ones 0..255.
      const double color_scale =
          has_color && IsFloatType(element.properties[static_cast<std::size_t>(ir)].type) ? 255.0
                                                                                          : 1.0;
      mesh.vertices.reserve(reserve);
      if (has_color) mesh.colors.reserve(reserve);
      values.assign(element.properties.size(), 0.0);
      for (std::size_t i = 0; i < element.count; ++i) {
        reader.SetItem(&element, i);
        for (std::size_t k = 0; k < element.properties.size(); ++k) {
          const PlyProperty& property = element.properties[k];
          if (property.is_list) {
            reader.Skip(property);
          } else {
            values[k] = reader.Double(property.type);
          }
        }
        const Eigen::Vector3d p(values[static_cast<std::size_t>(ix)],
                                values[static_cast<std::size_t>(iy)],
                                values[static_cast<std::size_t>(iz)]);
        if (!p.allFinite())
          Fail(path, "vertex " + std::to_string(i) + " has a non-finite coordinate");
        mesh.vertices.push_back(p);
        if (has_color) {
          mesh.colors.push_back({ColorByte(values[static_cast<std::size_t>(ir)], color_scale),
                                 ColorByte(values[static_cast<std::size_t>(ig)], color_scale),
                                 ColorByte(values[static_cast<std::size_t>(ib)], color_scale)});
        }
      }
    } else if (element.name == "face") {
      const int list = FindProperty(element, {"vertex_indices", "vertex_index"});
      if (list < 0 || !element.properties[static_cast<std::size_t>(list)].is_list) {
        Fail(path, "face element has no 'vertex_indices' list property");
      }
      const PlyProperty& indices = element.properties[static_cast<std::size_t>(list)];
      mesh.triangles.reserve(reserve);
      for (std::size_t i = 0; i < element.count; ++i) {
        reader.SetItem(&element, i);
        for (std::size_t k = 0; k < element.properties.size(); ++k) {
          if (static_cast<int>(k) != list) {
            reader.Skip(element.properties[k]);
            continue;
          }
          const std::int64_t count = reader.Int(indices.count_type);
          if (count < 3) {
            Fail(path, "face " + std::to_string(i) + " has " + std::to_string(count) +
                           " vertices (need at least 3)");
          }
          polygon.clear();
          for (std::int64_t j = 0; j < count; ++j) {
            const std::int64_t index = reader.Int(indices.type);
            if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count) {
              Fail(path, "face " + std::to_string(i) + " refers to vertex " +
                             std::to_string(index) + " but the file has " +
                             std::to_string(vertex_count) + " vertices");
            }
            polygon.push_back(static_cast<int>(index));
          }
          AddFan(polygon.data(), polygon.size(), &mesh.triangles);
        }
      }
    } else {
      for (std::size_t i = 0; i < element.count; ++i) {
        reader.SetItem(&element, i);
        for (const PlyProperty& property : element.properties) reader.Skip(property);
      }
    }
  }
  return mesh;
}

// ---------------------------------------------------------------------------
// OBJ

TriangleMesh LoadObj(const std::string& path, const std::string& data) {
  TriangleMesh mesh;
  std::vector<std::array<double, 3>> colors;  // as written; scaled once the range is known
  std::size_t colored = 0;
  double max_color = 0.0;
  std::int64_t max_index = -1;  // largest positive (forward) reference, 0-based
  std::size_t max_index_line = 0;
  std::vector<int> polygon;
  Lines lines(data);
  const char* begin = nullptr;
  const char* end = nullptr;
  while (lines.Next(&begin, &end)) {
    LineTokens tokens(begin, end);
    std::string_view keyword;
    if (!tokens.Next(&keyword)) continue;
    if (keyword == "v") {
      double v[7];
      int n = 0;
      while (n < 7 && tokens.NextDouble(&v[n])) ++n;
      if (n < 3) Fail(path, LinePrefix(lines.number()) + "vertex needs x, y and z");
      const Eigen::Vector3d p(v[0], v[1], v[2]);
      if (!p.allFinite()) {
        Fail(path, LinePrefix(lines.number()) + "vertex " +
                       std::to_string(mesh.vertices.size() + 1) + " has a non-finite coordinate");
      }
      mesh.vertices.push_back(p);
      if (n == 6) {
        colors.push_back({v[3], v[4], v[5]});
        max_color = std::max({max_color, v[3], v[4], v[5]});
        ++colored;
      } else {
        colors.push_back({0.0, 0.0, 0.0});
      }
    } else if (keyword == "f") {
      polygon.clear();
      std::string_view token;
      while (tokens.Next(&token)) {
        // "a", "a/b", "a//c" or "a/b/c": the vertex index is before the first '/'.
        const char* first = token.data();
        const char* last = first + token.size();
        const char* slash = std::find(first, last, '/');
        long long index = 0;
        const auto r = std::from_chars(first, slash, index);
        if (r.ec != std::errc() || r.ptr != slash || index == 0) {
          Fail(path, LinePrefix(lines.number()) + "bad vertex reference '" + std::string(token) +
                         "' in a face");
        }
        const auto defined = static_cast<long long>(mesh.vertices.size());
        long long resolved = 0;
        if (index < 0) {
          resolved = defined + index;
          if (resolved < 0) {
            Fail(path, LinePrefix(lines.number()) + "face refers to vertex " +
                           std::to_string(index) + " but only " + std::to_string(defined) +
                           " vertices are defined before it");
          }
        } else {
          resolved = index - 1;
          if (resolved > max_index) {
            max_index = resolved;
            max_index_line = lines.number();
          }
        }
        if (resolved > std::numeric_limits<int>::max()) {
          Fail(path, LinePrefix(lines.number()) + "vertex index " + std::to_string(index) +
                         " is too large");
        }
        polygon.push_back(static_cast<int>(resolved));
      }
      if (polygon.size() < 3) {
        Fail(path, LinePrefix(lines.number()) + "face has " + std::to_string(polygon.size()) +
                       " vertices (need at least 3)");
      }
      AddFan(polygon.data(), polygon.size(), &mesh.triangles);
    }
    // Other statements (vn, vt, o, g, s, usemtl, mtllib, l, comments) do not matter here.
  }
  if (max_index >= static_cast<std::int64_t>(mesh.vertices.size())) {
    Fail(path, LinePrefix(max_index_line) + "face refers to vertex " +
                   std::to_string(max_index + 1) + " but the file has " +
                   std::to_string(mesh.vertices.size()) + " vertices");
  }
  // Colours only when every vertex has one; 0..1 floats, or 0..255 from some exporters.
  if (colored == mesh.vertices.size() && colored > 0) {
    const double scale = max_color > 1.0 ? 1.0 : 255.0;
    mesh.colors.reserve(colors.size());
    for (const auto& c : colors) {
      mesh.colors.push_back(
          {ColorByte(c[0], scale), ColorByte(c[1], scale), ColorByte(c[2], scale)});
    }
  }
  return mesh;
}

// ---------------------------------------------------------------------------
// STL

namespace {

// An ASCII STL starts with "solid" and has only text in its first bytes; a
// binary STL may start with "solid" too, but its triangle count and floats
// are binary.
bool LooksLikeAsciiStl(const std::string& data) {
  std::size_t i = 0;
  while (i < data.size() && IsSpace(data[i])) ++i;
  if (data.compare(i, 5, "solid") != 0) return false;
  const std::size_t n = std::min<std::size_t>(data.size(), 512);
  for (std::size_t k = 0; k < n; ++k) {
    const auto c = static_cast<unsigned char>(data[k]);
    if (c < 32 && !IsSpace(static_cast<char>(c))) return false;
  }
  return true;
}

TriangleMesh LoadBinaryStl(const std::string& path, const std::string& data, std::uint32_t count) {
  TriangleMesh mesh;
  VertexMerger merger(static_cast<std::size_t>(count) / 2 + 16);
  mesh.vertices.reserve(static_cast<std::size_t>(count) / 2 + 16);
  mesh.triangles.reserve(count);
  const bool swap = !HostIsLittleEndian();
  for (std::uint32_t t = 0; t < count; ++t) {
    const char* record = data.data() + 84 + 50 * static_cast<std::size_t>(t);
    int corner[3];
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      for (int a = 0; a < 3; ++a) {
        char bytes[4];
        std::memcpy(bytes, record + 12 + 12 * k + 4 * a, 4);
        if (swap) std::reverse(bytes, bytes + 4);
        std::memcpy(&xyz[a], bytes, 4);
      }
      const Eigen::Vector3d p(xyz[0], xyz[1], xyz[2]);
      if (!p.allFinite()) {
        Fail(path, "triangle " + std::to_string(t) + " has a non-finite coordinate");
      }
      corner[k] = merger.Add(p, &mesh.vertices);
    }
    mesh.triangles.emplace_back(corner[0], corner[1], corner[2]);
  }
  return mesh;
}

TriangleMesh LoadAsciiStl(const std::string& path, const std::string& data) {
  TriangleMesh mesh;
  VertexMerger merger(data.size() / 200 + 16);
  std::vector<int> loop;
  bool in_facet = false;
  bool in_loop = false;
  std::size_t facet = 0;
  Lines lines(data);
  const char* begin = nullptr;
  const char* end = nullptr;
  while (lines.Next(&begin, &end)) {
    LineTokens tokens(begin, end);
    std::string_view keyword;
    if (!tokens.Next(&keyword)) continue;
    if (keyword == "vertex") {
      if (!in_loop) Fail(path, LinePrefix(lines.number()) + "'vertex' outside an 'outer loop'");
      Eigen::Vector3d p;
      if (!tokens.NextDouble(&p.x()) || !tokens.NextDouble(&p.y()) || !tokens.NextDouble(&p.z())) {
        Fail(path, LinePrefix(lines.number()) + "vertex needs x, y and z");
      }
      if (!p.allFinite()) {
        Fail(path, LinePrefix(lines.number()) + "vertex has a non-finite coordinate");
      }
      loop.push_back(merger.Add(p, &mesh.vertices));
    } else if (keyword == "facet") {
      if (in_facet) Fail(path, LinePrefix(lines.number()) + "'facet' inside a facet");
      in_facet = true;
      ++facet;
    } else if (keyword == "outer") {
      if (!in_facet || in_loop) Fail(path, LinePrefix(lines.number()) + "unexpected 'outer loop'");
      in_loop = true;
      loop.clear();
    } else if (keyword == "endloop") {
      if (!in_loop) Fail(path, LinePrefix(lines.number()) + "'endloop' without 'outer loop'");
      if (loop.size() < 3) {
        Fail(path, LinePrefix(lines.number()) + "facet has " + std::to_string(loop.size()) +
                       " vertices (need 3)");
      }
      AddFan(loop.data(), loop.size(), &mesh.triangles);
      in_loop = false;
    } else if (keyword == "endfacet") {
      if (!in_facet || in_loop) Fail(path, LinePrefix(lines.number()) + "unexpected 'endfacet'");
      in_facet = false;
    } else if (keyword == "solid" || keyword == "endsolid") {
      if (in_facet) {
        Fail(path, LinePrefix(lines.number()) + "'" + std::string(keyword) + "' inside a facet");
      }
    } else {
      Fail(path, LinePrefix(lines.number()) + "unexpected '" + std::string(keyword) +
                     "' in an ASCII STL");
    }
  }
  if (in_facet) {
    Fail(path, "file is truncated: facet " + std::to_string(facet) + " is not finished");
  }
  return mesh;
}

}  // namespace

TriangleMesh LoadStl(const std::string& path, const std::string& data) {
  const std::uint64_t size = data.size();
  std::uint32_t count = 0;
  if (size >= 84) {
    unsigned char b[4];
    std::memcpy(b, data.data() + 80, 4);
    count = static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
            (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
    if (84 + 50 * static_cast<std::uint64_t>(count) == size) {
      return LoadBinaryStl(path, data, count);
    }
  }
  if (LooksLikeAsciiStl(data)) return LoadAsciiStl(path, data);
  if (size < 84) {
    Fail(path, "not an STL file: " + std::to_string(size) +
                   " bytes is too short for a binary STL (84-byte header) and it does not start "
                   "with 'solid'");
  }
  const std::uint64_t found = (size - 84) / 50;
  if (found < count) {
    Fail(path, "file is truncated: header says " + std::to_string(count) +
                   " triangles, found bytes for " + std::to_string(found));
  }
  // Some exporters append bytes after the triangles; read what the header declares.
  return LoadBinaryStl(path, data, count);
}

// ---------------------------------------------------------------------------
// ViSP .cao

namespace {

// The .cao body as numbers with their line numbers: comments (# to the end of
// the line) and attributes (tokens with '=', e.g. name=side) left out.
class CaoTokens {
 public:
  CaoTokens(const std::string& path, const std::string& data) : path_(path) {
    Lines lines(data);
    const char* begin = nullptr;
    const char* end = nullptr;
    while (lines.Next(&begin, &end)) {
      const char* hash =
          static_cast<const char*>(std::memchr(begin, '#', static_cast<std::size_t>(end - begin)));
      LineTokens tokens(begin, hash ? hash : end);
      std::string_view token;
      while (tokens.Next(&token)) {
        if (token.find('=') != std::string_view::npos) continue;
        tokens_.emplace_back(std::string(token), lines.number());
      }
    }
  }

  bool Done() const { return next_ >= tokens_.size(); }
  std::size_t Line() const {
    return next_ < tokens_.size() ? tokens_[next_].second
                                  : (tokens_.empty() ? 1 : tokens_.back().second);
  }
  const std::string& Peek() const { return tokens_.at(next_).first; }
  void Skip() { ++next_; }

  double Number(const char* what) {
    if (Done()) Fail(path_, "file is truncated: expected " + std::string(what));
    const auto& [text, line] = tokens_[next_];
    double value = 0.0;
    const char* end = text.data() + text.size();
    if (ParseDouble(text.data(), end, &value) != end || !std::isfinite(value)) {
      Fail(path_, LinePrefix(line) + "expected " + std::string(what) + ", found '" + text + "'");
    }
    ++next_;
    return value;
  }

  std::int64_t Integer(const char* what, std::int64_t min, std::int64_t max) {
    const std::size_t line = Line();
    const double value = Number(what);
    if (value != std::floor(value) || value < static_cast<double>(min) ||
        value > static_cast<double>(max)) {
      Fail(path_, LinePrefix(line) + "expected " + std::string(what) + " in [" +
                      std::to_string(min) + ", " + std::to_string(max) + "], found " +
                      FormatNumber(value));
    }
    return static_cast<std::int64_t>(value);
  }

 private:
  std::string path_;
  std::vector<std::pair<std::string, std::size_t>> tokens_;
  std::size_t next_ = 0;
};

}  // namespace

TriangleMesh LoadCao(const std::string& path, const std::string& data) {
  CaoTokens tokens(path, data);
  if (tokens.Done() || tokens.Peek() != "V1") {
    if (!tokens.Done() && tokens.Peek().rfind("load(", 0) == 0) {
      Fail(path, LinePrefix(tokens.Line()) +
                     "load(...) includes another .cao file, which import does not follow: "
                     "merge the files into one");
    }
    Fail(path, "not a ViSP .cao file (it does not start with 'V1')");
  }
  tokens.Skip();
  constexpr std::int64_t kMaxCount = 50000000;
  TriangleMesh mesh;
  const std::int64_t points = tokens.Integer("the number of 3D points", 0, kMaxCount);
  for (std::int64_t i = 0; i < points; ++i) {
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = tokens.Number("a point coordinate");
    mesh.vertices.push_back(p);
  }
  const std::int64_t last_point = points - 1;
  // 3D lines: point pairs; a line is kept only as a side of a face.
  const std::int64_t line_count = tokens.Integer("the number of 3D lines", 0, kMaxCount);
  std::vector<std::array<int, 2>> lines;
  std::vector<std::size_t> line_at;  // the file line of each, for messages
  for (std::int64_t i = 0; i < line_count; ++i) {
    line_at.push_back(tokens.Line());
    const auto a = static_cast<int>(tokens.Integer("a 3D line's first point", 0, last_point));
    const auto b = static_cast<int>(tokens.Integer("a 3D line's second point", 0, last_point));
    lines.push_back({a, b});
  }
  std::vector<char> line_used(lines.size(), 0);
  std::vector<int> polygon;
  const std::int64_t faces_from_lines =
      tokens.Integer("the number of faces from 3D lines", 0, kMaxCount);
  for (std::int64_t f = 0; f < faces_from_lines; ++f) {
    const std::size_t at = tokens.Line();
    const std::int64_t n = tokens.Integer("a face's number of lines", 3, kMaxCount);
    std::vector<std::array<int, 2>> sides;
    for (std::int64_t k = 0; k < n; ++k) {
      const auto l = static_cast<std::size_t>(
          tokens.Integer("a 3D line index", 0, static_cast<std::int64_t>(lines.size()) - 1));
      line_used[l] = 1;
      sides.push_back(lines[l]);
    }
    // Chain the sides into one closed polygon.
    polygon.assign({sides[0][0], sides[0][1]});
    sides.erase(sides.begin());
    while (!sides.empty()) {
      const auto next = std::find_if(sides.begin(), sides.end(), [&](const auto& side) {
        return side[0] == polygon.back() || side[1] == polygon.back();
      });
      if (next == sides.end()) {
        Fail(path, LinePrefix(at) + "face " + std::to_string(f) +
                       " from 3D lines: its lines do not form one closed loop");
      }
      polygon.push_back((*next)[0] == polygon.back() ? (*next)[1] : (*next)[0]);
      sides.erase(next);
    }
    if (polygon.back() != polygon.front()) {
      Fail(path, LinePrefix(at) + "face " + std::to_string(f) +
                     " from 3D lines: its lines do not form one closed loop");
    }
    polygon.pop_back();
    AddFan(polygon.data(), polygon.size(), &mesh.triangles);
  }
  for (std::size_t l = 0; l < lines.size(); ++l) {
    if (!line_used[l]) {
      Fail(path, LinePrefix(line_at[l]) + "3D line " + std::to_string(l) +
                     " bounds no face: a line alone has no surface to grasp or to see in "
                     "depth; give the object as polygon faces");
    }
  }
  const std::int64_t faces_from_points =
      tokens.Integer("the number of faces from 3D points", 0, kMaxCount);
  for (std::int64_t f = 0; f < faces_from_points; ++f) {
    const std::int64_t n = tokens.Integer("a face's number of points", 3, kMaxCount);
    polygon.clear();
    for (std::int64_t k = 0; k < n; ++k) {
      polygon.push_back(static_cast<int>(tokens.Integer("a point index", 0, last_point)));
    }
    AddFan(polygon.data(), polygon.size(), &mesh.triangles);
  }
  // Cylinders and circles (optional sections at the end): no polygon faces.
  const char* primitives[] = {"3D cylinder", "3D circle"};
  for (const char* primitive : primitives) {
    if (tokens.Done()) break;
    const std::int64_t count = tokens.Integer(primitive, 0, kMaxCount);
    if (count > 0) {
      // Named by the line of the first one.
      Fail(path, LinePrefix(tokens.Line()) + "a " + primitive + " (" + std::to_string(count) +
                     " in the file): cylinders and circles are not polygon faces; model the "
                     "part as a polygon mesh (e.g. export it as STL or PLY) and import that");
    }
  }
  if (!tokens.Done()) {
    Fail(path,
         LinePrefix(tokens.Line()) + "unexpected '" + tokens.Peek() + "' after the last section");
  }
  return mesh;
}

// ---------------------------------------------------------------------------
// PLY writer

void SavePly(const TriangleMesh& mesh, const std::string& path) {
  const bool has_color = !mesh.colors.empty();
  if (has_color && mesh.colors.size() != mesh.vertices.size()) {
    Fail(path, "cannot save: the mesh has " + std::to_string(mesh.colors.size()) + " colours for " +
                   std::to_string(mesh.vertices.size()) + " vertices");
  }
  const auto n = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int index = mesh.triangles[t][k];
      if (index < 0 || index >= n) {
        Fail(path, "cannot save: triangle " + std::to_string(t) + " refers to vertex " +
                       std::to_string(index) + " but the mesh has " + std::to_string(n) +
                       " vertices");
      }
    }
  }
  std::string out;
  out += "ply\nformat binary_little_endian 1.0\ncomment written by aerograsp, metres\n";
  out += "element vertex " + std::to_string(mesh.vertices.size()) + "\n";
  // Doubles, so that a save and a load give back exactly the same coordinates.
  out += "property double x\nproperty double y\nproperty double z\n";
  if (has_color) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "element face " + std::to_string(mesh.triangles.size()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";

  const bool swap = !HostIsLittleEndian();
  const auto append = [&out, swap](const auto& value) {
    char bytes[sizeof(value)];
    std::memcpy(bytes, &value, sizeof(value));
    if (swap) std::reverse(bytes, bytes + sizeof(value));
    out.append(bytes, sizeof(value));
  };
  out.reserve(out.size() + mesh.vertices.size() * (has_color ? 27 : 24) +
              mesh.triangles.size() * 13);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    for (int a = 0; a < 3; ++a) append(mesh.vertices[i][a]);
    if (has_color) out.append(reinterpret_cast<const char*>(mesh.colors[i].data()), 3);
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    out.push_back(3);
    for (int k = 0; k < 3; ++k) append(static_cast<std::int32_t>(t[k]));
  }

  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) Fail(path, "cannot open file for writing");
  file.write(out.data(), static_cast<std::streamsize>(out.size()));
  file.close();
  if (!file) Fail(path, "write failed (disk full?)");
}

}  // namespace aerograsp::mesh_formats
