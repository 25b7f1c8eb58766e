// A progress line for long work: a bar redrawn in place on a terminal, a line
// every 10 % otherwise (logs, CI).
#pragma once

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>

namespace aerograsp {

class Progress {
 public:
  /// `out` is usually std::cerr; `unit` names what is counted ("frames").
  Progress(std::ostream& out, std::string label, std::int64_t total, std::string unit);
  /// Reports `done` items finished (monotonic).
  void Update(std::int64_t done);
  /// Final line with the total time.
  void Finish();

 private:
  std::ostream& out_;
  std::string label_, unit_;
  std::int64_t total_;
  bool terminal_;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace aerograsp
