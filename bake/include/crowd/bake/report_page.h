// crowdbake report: build reports (crowdbake build's build.report.json) and bake reports (any
// bake's --report) as one HTML page a person reads: per build and character, each job's time,
// bytes and error, and the charts that set speed and size against accuracy (the animation's
// error against bytes for every option tried, LOD error against triangles, impostor accuracy
// against memory, the cloth loop's seam search). Self-contained: SVG inline, no scripts, no
// network.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace crowd {

struct ReportSource {
  std::string path; // shown on the page
  nlohmann::json json;
};

struct ReportPages {
  std::string page; // the page itself
  // A build of more than kInlineCharacters characters: the page holds its summary and one row
  // per character (the failed first), each linking to the character's own page, written into
  // the folder `details` beside it: (file name in that folder, its HTML). A farm's report of a
  // thousand characters opens as fast as one of ten, and each character's charts on demand.
  std::vector<std::pair<std::string, std::string>> characterPages;
  static constexpr size_t kInlineCharacters = 20;
};

// Throws Error naming the source when a JSON is neither a build report nor a bake report.
// `details`: the folder name (relative to the page) that characterPages are written into.
ReportPages reportPages(const std::vector<ReportSource> &sources, const std::string &details);

} // namespace crowd
