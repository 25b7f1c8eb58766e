// Captures what a library writes to std::cout (ViSP reports progress there)
// for as long as the object lives, so that our own output stays clean.
#pragma once

#include <iostream>
#include <sstream>
#include <string>

namespace aerograsp {

class StdoutCapture {
 public:
  StdoutCapture() : saved_(std::cout.rdbuf(buffer_.rdbuf())) {}
  ~StdoutCapture() { std::cout.rdbuf(saved_); }
  StdoutCapture(const StdoutCapture&) = delete;
  StdoutCapture& operator=(const StdoutCapture&) = delete;
  /// What was written so far.
  std::string text() const { return buffer_.str(); }

 private:
  std::ostringstream buffer_;
  std::streambuf* saved_;
};

}  // namespace aerograsp
