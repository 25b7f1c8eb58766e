// Loads a report page in Debian's Chromium, headless, for the tests of the
// reports' charts: the page's DOM after its scripts ran, what it printed to the
// console, and a screenshot.
#pragma once

#include <string>
#include <vector>

namespace aerograsp {

/// The chromium program on PATH; empty when there is none.
std::string FindChromium();

struct BrowserPage {
  std::string dom;                   ///< the DOM after the scripts ran (--dump-dom)
  std::vector<std::string> console;  ///< every console message and uncaught error, one a line
};

/// Opens `html_path` (a file) in headless Chromium with a window of width x height pixels,
/// with no network and a fresh profile in `profile_dir`, and writes the screenshot to
/// `screenshot_path`. @throws std::runtime_error when chromium fails to run.
BrowserPage LoadInChromium(const std::string& chromium, const std::string& html_path,
                           const std::string& screenshot_path, const std::string& profile_dir,
                           int width_px = 1400, int height_px = 3000);

/// Where the tests keep their screenshots: build/report_screenshots/`name` (the folder made).
std::string ScreenshotPath(const std::string& name);

/// The charts in a report page (app/report/report_charts.h): their JSON blocks.
int CountCharts(const std::string& html);

/// The value of attribute `name` of <body> in `dom`, empty when it has none.
std::string BodyAttribute(const std::string& dom, const std::string& name);

}  // namespace aerograsp
