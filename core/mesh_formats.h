// Internal to core/mesh.cpp and core/mesh_formats.cpp: the per-format mesh
// readers and writer, and the error helpers they share. Not part of the API.
#pragma once

#include <string>

#include "core/mesh.h"

namespace aerograsp::mesh_formats {

/// Throws MeshError("<path>: <what>").
[[noreturn]] void Fail(const std::string& path, const std::string& what);

/// A number for a message, to 6 significant digits.
std::string FormatNumber(double value);

/// Parse a whole file's bytes. They throw MeshError naming the path for a
/// malformed or truncated file, a non-finite coordinate or an index out of
/// range; the shared checks (no triangles, extent) are LoadMesh's.
TriangleMesh LoadPly(const std::string& path, const std::string& data);  // ASCII or binary
TriangleMesh LoadObj(const std::string& path, const std::string& data);
TriangleMesh LoadStl(const std::string& path, const std::string& data);  // ASCII or binary
/// ViSP's .cao (V1): faces from points and faces from lines, fan-triangulated;
/// cylinders, circles and lines that bound no face are refused by line.
TriangleMesh LoadCao(const std::string& path, const std::string& data);

/// SaveMeshPly: binary little-endian PLY, double coordinates, colours if any.
void SavePly(const TriangleMesh& mesh, const std::string& path);

}  // namespace aerograsp::mesh_formats
