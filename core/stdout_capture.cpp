#include "core/stdout_capture.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <sstream>

namespace aerograsp {

struct StdoutCapture::Impl {
  std::ostringstream buffer;
  std::streambuf* saved_buf = nullptr;
  int saved_fd = -1;
};

StdoutCapture::StdoutCapture() : impl_(new Impl) {
  impl_->saved_buf = std::cout.rdbuf(impl_->buffer.rdbuf());
  std::fflush(stdout);
  impl_->saved_fd = dup(STDOUT_FILENO);
  const int null_fd = open("/dev/null", O_WRONLY);
  if (null_fd >= 0) {
    dup2(null_fd, STDOUT_FILENO);
    close(null_fd);
  }
}

StdoutCapture::~StdoutCapture() {
  std::fflush(stdout);
  if (impl_->saved_fd >= 0) {
    dup2(impl_->saved_fd, STDOUT_FILENO);
    close(impl_->saved_fd);
  }
  std::cout.rdbuf(impl_->saved_buf);
  delete impl_;
}

std::string StdoutCapture::text() const { return impl_->buffer.str(); }

}  // namespace aerograsp
