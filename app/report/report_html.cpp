#include "app/report/report_html.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace aerograsp {
namespace {

constexpr const char* kStyle =
    "body{font-family:sans-serif;margin:2em;max-width:1500px}"
    "table{border-collapse:collapse;margin:0.5em 0 1.5em}"
    "th,td{border:1px solid #bbb;padding:0.25em 0.6em;text-align:left}"
    "th{background:#eee}img{max-width:100%;border:1px solid #ddd}"
    "figure{margin:0 0 1.5em}figcaption{color:#444;font-size:0.9em}.missing{color:#888}"
    // Interactive charts (app/report/report_charts.h); their PNGs replace them in print.
    ".chart{position:relative;margin:0.3em 0}.joints{display:grid;"
    "grid-template-columns:repeat(auto-fit,minmax(420px,1fr));gap:0 1.5em}"
    ".zoombar{position:sticky;top:0;z-index:1;background:#f4f6fa;border:1px solid #ccd;"
    "padding:0.3em 0.6em;margin:0 0 1em;font-size:0.85em}img.print{display:none}"
    "@media print{.has-png .chart,.zoombar{display:none}img.print{display:block}}";

}  // namespace

std::string EscapeHtml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void WriteHtmlTable(const std::vector<std::string>& header,
                    const std::vector<std::vector<std::string>>& rows, std::ostream& html) {
  html << "<table>\n<tr>";
  for (const std::string& cell : header) html << "<th>" << EscapeHtml(cell) << "</th>";
  html << "</tr>\n";
  for (const std::vector<std::string>& row : rows) {
    html << "<tr>";
    for (const std::string& cell : row) html << "<td>" << EscapeHtml(cell) << "</td>";
    html << "</tr>\n";
  }
  html << "</table>\n";
}

void WriteHtmlFigure(bool written, const std::string& image, const std::string& caption,
                     const std::string& missing, std::ostream& html) {
  if (!written) {
    html << "<p class=\"missing\">" << EscapeHtml(missing) << "</p>\n";
    return;
  }
  html << "<figure><img src=\"" << EscapeHtml(image) << "\" alt=\"" << EscapeHtml(caption) << "\">"
       << "<figcaption>" << EscapeHtml(caption) << "</figcaption></figure>\n";
}

void BeginHtmlPage(const std::string& title, std::ostream& html) {
  const std::string escaped = EscapeHtml(title);
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>"
       << escaped << "</title>\n<style>" << kStyle << "</style>\n</head>\n<body>\n<h1>" << escaped
       << "</h1>\n";
}

void WriteHtmlPage(const std::string& page, const std::string& out_dir) {
  const std::string path = (std::filesystem::path(out_dir) / "index.html").string();
  std::ofstream file(path, std::ios::binary);
  file << page << "</body>\n</html>\n";
  file.close();
  if (!file) throw std::runtime_error(path + ": cannot be written");
}

}  // namespace aerograsp
