#include "app/calibration/tag_board_mesh.h"

namespace aerograsp {

RenderMesh MakeBoardRenderMesh(const TagBoardConfig& board, double px_per_m) {
  RenderMesh quad;
  const Eigen::Vector2d half = 0.5 * board.Size();
  quad.mesh.vertices = {{-half.x(), -half.y(), 0.0},
                        {half.x(), -half.y(), 0.0},
                        {half.x(), half.y(), 0.0},
                        {-half.x(), half.y(), 0.0}};
  quad.mesh.triangles = {{0, 2, 1}, {0, 3, 2}};  // normal -z: towards the viewer
  quad.uv = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
  quad.material.texture = std::make_shared<ColorImage>(RenderBoardImage(board, px_per_m));
  return quad;
}

}  // namespace aerograsp
