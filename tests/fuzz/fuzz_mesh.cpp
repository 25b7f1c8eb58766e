// libFuzzer target for the mesh readers (PLY ASCII/binary, OBJ, STL
// ASCII/binary, ViSP .cao) through LoadMesh and CheckMesh. The first byte ('0'
// PLY, '1' OBJ, '2' STL, '3' .cao) picks the file's extension, the rest is the
// file. Built and run by scripts/run_fuzz.sh.
#include <cstddef>
#include <cstdint>

#include "core/mesh.h"
#include "tests/fuzz/fuzz_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".ply", ".obj", ".stl", ".cao"};
  const char* extension = kExtensions[static_cast<std::uint8_t>(data[0] - '0') % 4];
  const std::string path = aerograsp::fuzz::WriteFile(
      aerograsp::fuzz::ScratchData() / (std::string("mesh") + extension), data + 1, size - 1);
  try {
    const aerograsp::TriangleMesh mesh = aerograsp::LoadMesh(path);
    (void)aerograsp::CheckMesh(mesh);
  } catch (const aerograsp::MeshError&) {
  }
  return 0;
}
