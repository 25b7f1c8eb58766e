// The exit codes of the aerograsp command: whether it did what it was asked.
// CLI11 uses its own codes (100 and above) for a command line it refuses.
#pragma once

namespace aerograsp {

constexpr int kExitOk = 0;     ///< done as asked
constexpr int kExitError = 1;  ///< an error: bad input, a device failing, a file not written
constexpr int kExitMissionFailed = 3;  ///< a mission flew but did not succeed (any of --runs)
constexpr int kExitStoppedEarly = 4;   ///< a run stopped before its end; its report says why

}  // namespace aerograsp
