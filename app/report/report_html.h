// The pieces of the commands' HTML reports (app/report/mission_report.h, the bench):
// escaping, tables, figures, the page's head and foot and writing it. The
// pages open in a browser with no network: images sit next to index.html.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace aerograsp {

std::string EscapeHtml(const std::string& text);

/// A table with the given header cells; every cell is escaped.
void WriteHtmlTable(const std::vector<std::string>& header,
                    const std::vector<std::vector<std::string>>& rows, std::ostream& html);

/// The figure of `image` (relative path) when it was written, `missing` (a sentence) otherwise.
void WriteHtmlFigure(bool written, const std::string& image, const std::string& caption,
                     const std::string& missing, std::ostream& html);

/// <!DOCTYPE html> ... <body><h1>title</h1> with the reports' style sheet.
void BeginHtmlPage(const std::string& title, std::ostream& html);

/// Closes `page` (begun by BeginHtmlPage) and writes it to out_dir/index.html.
/// @throws std::runtime_error "<path>: cannot be written".
void WriteHtmlPage(const std::string& page, const std::string& out_dir);

}  // namespace aerograsp
