#include "tests/app/headless_browser.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace aerograsp {
namespace {
namespace fs = std::filesystem;

std::string Quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string ReadFile(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace

std::string FindChromium() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / "chromium";
    std::error_code error;
    if (fs::is_regular_file(candidate, error)) return candidate.string();
  }
  return "";
}

BrowserPage LoadInChromium(const std::string& chromium, const std::string& html_path,
                           const std::string& screenshot_path, const std::string& profile_dir,
                           int width_px, int height_px) {
  const fs::path dom_path = fs::path(profile_dir) / "dom.html";
  const fs::path log_path = fs::path(profile_dir) / "chromium.log";
  fs::create_directories(profile_dir);
  // Root in containers and CI needs --no-sandbox; the proxy flags keep it off the network.
  const std::string command =
      "timeout 120 " + Quoted(chromium) +
      " --headless --no-sandbox --disable-gpu --no-first-run --disable-extensions"
      " --disable-background-networking --disable-sync --proxy-server=127.0.0.1:9"
      " --proxy-bypass-list='<-loopback>' --hide-scrollbars --enable-logging=stderr --v=0" +
      " --user-data-dir=" + Quoted(profile_dir) + " --window-size=" + std::to_string(width_px) +
      "," + std::to_string(height_px) + " --screenshot=" + Quoted(screenshot_path) +
      " --dump-dom " + Quoted("file://" + fs::absolute(html_path).string()) + " > " +
      Quoted(dom_path.string()) + " 2> " + Quoted(log_path.string());
  const int status = std::system(command.c_str());
  BrowserPage page;
  page.dom = ReadFile(dom_path);
  std::stringstream log(ReadFile(log_path));
  for (std::string line; std::getline(log, line);) {
    const std::size_t at = line.find(":CONSOLE");
    if (at == std::string::npos) continue;
    const std::size_t text = line.find("] ", at);
    page.console.push_back(text == std::string::npos ? line : line.substr(text + 2));
  }
  if (status != 0 || page.dom.empty()) {
    throw std::runtime_error(chromium + " failed on " + html_path + " (status " +
                             std::to_string(status) + "); see " + log_path.string());
  }
  return page;
}

std::string ScreenshotPath(const std::string& name) {
  const fs::path dir = fs::path(AEROGRASP_BUILD_DIR) / "report_screenshots";
  fs::create_directories(dir);
  return (dir / name).string();
}

int CountCharts(const std::string& html) {
  const std::string block = "<script type=\"application/json\" class=\"chart-data\">";
  int count = 0;
  for (std::size_t at = html.find(block); at != std::string::npos; at = html.find(block, at + 1))
    ++count;
  return count;
}

std::string BodyAttribute(const std::string& dom, const std::string& name) {
  const std::size_t body = dom.find("<body");
  if (body == std::string::npos) return "";
  const std::size_t end = dom.find('>', body);
  const std::string tag = dom.substr(body, end - body);
  const std::size_t at = tag.find(" " + name + "=\"");
  if (at == std::string::npos) return "";
  const std::size_t value = at + name.size() + 3;
  return tag.substr(value, tag.find('"', value) - value);
}

}  // namespace aerograsp
