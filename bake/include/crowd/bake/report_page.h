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

// Throws Error naming the source when a JSON is neither a build report nor a bake report.
std::string reportPage(const std::vector<ReportSource> &sources);

} // namespace crowd
