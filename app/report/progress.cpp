#include "app/report/progress.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace aerograsp {

Progress::Progress(std::ostream& out, std::string label, std::int64_t total, std::string unit)
    : out_(out),
      label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      terminal_(&out == &std::cerr ? isatty(STDERR_FILENO)
                                   : (&out == &std::cout && isatty(STDOUT_FILENO))),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

void Progress::Update(std::int64_t done) {
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double rate = elapsed > 0.0 ? done / elapsed : 0.0;
  const double fraction = total_ > 0 ? static_cast<double>(done) / total_ : 1.0;
  char line[160];
  if (terminal_) {
    if (done < total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
    last_draw_ = now;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, ' ');
    std::snprintf(line, sizeof(line), "\r%s [%s] %lld/%lld %s  %.1f %s/s ", label_.c_str(),
                  bar.c_str(), static_cast<long long>(done), static_cast<long long>(total_),
                  unit_.c_str(), rate, unit_.c_str());
    out_ << line << std::flush;
    return;
  }
  const int decile = static_cast<int>(fraction * 10.0);
  if (decile == last_decile_) return;
  last_decile_ = decile;
  std::snprintf(line, sizeof(line), "%s: %lld/%lld %s (%d %%), %.1f %s/s\n", label_.c_str(),
                static_cast<long long>(done), static_cast<long long>(total_), unit_.c_str(),
                decile * 10, rate, unit_.c_str());
  out_ << line << std::flush;
}

void Progress::Finish() {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (terminal_) out_ << "\n";
  char line[160];
  std::snprintf(line, sizeof(line), "%s: done in %.1f s\n", label_.c_str(), elapsed);
  out_ << line << std::flush;
}

}  // namespace aerograsp
