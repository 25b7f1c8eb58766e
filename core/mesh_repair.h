// Repairs of a mesh that do not change its shape: duplicate vertices merged,
// repeated and collapsed triangles dropped, triangles oriented consistently and
// outwards. What cannot be repaired honestly (holes, edges shared by more than
// two triangles, a surface with no inside) is refused with where it is.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace aerograsp {

/// What RepairMesh changed (all zero: the mesh was already clean).
struct MeshRepairReport {
  std::size_t merged_vertices = 0;     ///< vertices merged into an earlier one at the same place
  std::size_t dropped_collapsed = 0;   ///< triangles with a repeated corner after merging
  std::size_t dropped_duplicates = 0;  ///< triangles repeating another's three corners
  std::size_t flipped_triangles = 0;   ///< turned to agree with their neighbours / face out
  std::size_t dropped_unused_vertices = 0;  ///< vertices no triangle uses
  std::size_t shells = 0;                   ///< closed surfaces (connected components)

  /// One line per change, e.g. "merged 24 duplicate vertices"; empty when none.
  std::vector<std::string> Lines() const;
};

/// Repairs `mesh` (in place). `merge_distance` (in the mesh's units): vertices
/// closer than this are one. `source` names the file in messages and
/// `unit_name` the unit coordinates are given in ("m", "mm", ...).
/// @throws MeshError "<source>: ..." naming the open or non-manifold edges (a
/// count, and where a few of them are), a surface that cannot be oriented, or
/// a mesh left with no triangles.
MeshRepairReport RepairMesh(TriangleMesh* mesh, double merge_distance, const std::string& source,
                            const std::string& unit_name);

}  // namespace aerograsp
