// A tag board as a textured quad for the simulator's renderer (calib knows
// boards, hardware/sim knows meshes; the app joins them).
#pragma once

#include "calib/tag_board.h"
#include "hardware/sim/rgbd_renderer.h"

namespace aerograsp {

/// The board's printed face in its frame t (z = 0, facing -z), textured at
/// `px_per_m` (2,000 px/m resolves a 3 cm tag's cells by 7 px).
RenderMesh MakeBoardRenderMesh(const TagBoardConfig& board, double px_per_m = 2000.0);

}  // namespace aerograsp
