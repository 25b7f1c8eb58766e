// Keeps what a library writes to standard output (ViSP reports progress
// there, through std::cout and printf) out of our output for as long as the
// object lives. Not thread-safe: it redirects the process's stdout.
#pragma once

#include <string>

namespace aerograsp {

class StdoutCapture {
 public:
  StdoutCapture();
  ~StdoutCapture();
  StdoutCapture(const StdoutCapture&) = delete;
  StdoutCapture& operator=(const StdoutCapture&) = delete;
  /// What was written to std::cout so far (printf output is discarded).
  std::string text() const;

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace aerograsp
