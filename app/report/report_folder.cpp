#include "app/report/report_folder.h"

#include <unistd.h>

#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "core/config.h"

namespace aerograsp {
namespace {

namespace fs = std::filesystem;

fs::path Beside(const fs::path& dir, const std::string& what) {
  return dir.parent_path() /
         ("." + dir.filename().string() + "." + what + "-" + std::to_string(::getpid()));
}

}  // namespace

ReportFolder::ReportFolder(const std::string& dir, bool overwrite, const std::string& signature) {
  if (dir.empty()) throw ConfigError("--out: no folder given");
  fs::path d = fs::absolute(dir).lexically_normal();
  if (!d.has_filename()) d = d.parent_path();  // "out/" -> "out"
  dir_ = d.string();
  shown_ = dir;
  while (shown_.size() > 1 && shown_.back() == '/') shown_.pop_back();
  std::error_code ec;
  if (fs::exists(d, ec)) {
    if (!fs::is_directory(d, ec)) throw ConfigError(dir + ": is a file, not a report folder");
    if (!fs::is_empty(d, ec)) {
      if (!fs::exists(d / signature, ec)) {
        throw ConfigError(dir + ": is not empty and holds no report (no " + signature +
                          "); choose another folder");
      }
      if (!overwrite) throw ConfigError(dir + ": holds an earlier report; --overwrite replaces it");
    }
  }
  const fs::path work = Beside(d, "partial");
  fs::remove_all(work, ec);
  fs::create_directories(work, ec);
  if (ec) throw std::runtime_error(work.string() + ": cannot be made: " + ec.message());
  work_ = work.string();
}

ReportFolder::~ReportFolder() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(work_, ec);
}

std::string ReportFolder::Final(const std::string& written) const {
  std::string text;
  std::size_t from = 0;
  for (std::size_t at = written.find(work_); at != std::string::npos;
       at = written.find(work_, at + 1)) {
    const std::size_t end = at + work_.size();
    const auto name_char = [&written](std::size_t i) {
      return i < written.size() && (std::isalnum(static_cast<unsigned char>(written[i])) ||
                                    written[i] == '_' || written[i] == '-');
    };
    // Another folder whose name starts with ours is not ours (a full stop may end a sentence).
    if (name_char(end) || (end < written.size() && written[end] == '.' && name_char(end + 1)))
      continue;
    text += written.substr(from, at - from) + shown_;
    from = end;
  }
  return text + written.substr(from);
}

const std::string& ReportFolder::Commit() {
  if (committed_) return shown_;
  const fs::path d(dir_);
  const fs::path old = Beside(d, "replaced");
  std::error_code ec;
  fs::remove_all(old, ec);
  if (fs::exists(d, ec)) {
    fs::rename(d, old, ec);
    if (ec)
      throw std::runtime_error(dir_ + ": the earlier report cannot be moved: " + ec.message());
  }
  fs::rename(work_, d, ec);
  if (ec) {
    std::error_code back;
    if (fs::exists(old, back)) fs::rename(old, d, back);
    throw std::runtime_error(dir_ + ": the report cannot be moved into place: " + ec.message());
  }
  committed_ = true;
  fs::remove_all(old, ec);
  return shown_;
}

}  // namespace aerograsp
