// Where the shipped models live (robots, objects, camera, config).
#pragma once

#include <string>

namespace aerograsp {

/// The data folder: $AEROGRASP_DATA_DIR when set, else the source tree's data/
/// folder compiled in at configure time.
std::string DataDir();

/// DataDir() / relative.
std::string DataPath(const std::string& relative);

}  // namespace aerograsp
