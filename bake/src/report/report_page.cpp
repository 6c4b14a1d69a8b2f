#include "crowd/bake/report_page.h"

#include <algorithm>
#include <cstdio>

#include "crowd/bake/svg_chart.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

using nlohmann::json;

std::string num(double v, const char *format = "%.3g") {
  char b[48];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

std::string bytesText(double b) {
  if (b >= 1e6)
    return num(b / 1e6, "%.2f") + " MB";
  if (b >= 1e3)
    return num(b / 1e3, "%.1f") + " kB";
  return num(b, "%.0f") + " B";
}

// Reports may come from another version or be edited: a missing or mistyped field reads as
// null, 0 or "".
const json &field(const json &j, const char *key) {
  static const json none;
  return j.is_object() && j.contains(key) ? j[key] : none;
}
double number(const json &j, const char *key, double fallback = 0) {
  const json &v = field(j, key);
  return v.is_number() ? v.get<double>() : fallback;
}
std::string text(const json &j, const char *key) {
  const json &v = field(j, key);
  return v.is_string() ? v.get<std::string>() : "";
}

// What an animation pack stores: joint tracks, or the texture's precision.
std::string stored(const json &f) {
  return text(f, "store") == "tracks" ? "joint tracks" : text(f, "precision");
}

// One job as both report kinds give it: crowdbake build's jobs, or a bake's own report.
struct JobView {
  std::string kind, label;
  double seconds = 0;
  bool cached = false, failed = false;
  std::string error;
  json figures;
};

std::string row(const std::vector<std::string> &cells, const char *tag = "td") {
  std::string r = "<tr>";
  for (const auto &c : cells)
    r += std::string("<") + tag + ">" + c + "</" + tag + ">";
  return r + "</tr>\n";
}

// The job's size and accuracy in a phrase for the jobs table.
std::pair<std::string, std::string> bytesAndError(const JobView &job) {
  const json &f = job.figures;
  if (f.empty())
    return {"", ""};
  if (job.kind == "mesh") {
    double worst = 0;
    std::string clip;
    if (f.contains("clips"))
      for (const auto &c : f["clips"])
        if (number(c, "max_error_any_time_mm") >= worst) {
          worst = number(c, "max_error_any_time_mm");
          clip = text(c, "name");
        }
    const std::string error = clip.empty() ? ""
                                           : num(worst) + " mm at any time (clip " +
                                                 escapeXml(clip) + "), " + escapeXml(stored(f));
    return {num(number(f, "triangles"), "%.0f") + " triangles", error};
  }
  if (job.kind == "impostor") {
    const double iou = f.contains("accuracy")
                           ? number(field(field(f, "accuracy"), "between_views"), "iou_mean")
                           : number(f, "mirror_iou_mean");
    return {bytesText(number(f, "bytes_per_frame")) + " a frame",
            "IoU " + num(iou) + (f.contains("accuracy") ? " between views" : " mirrored")};
  }
  if (job.kind == "cloth")
    return {bytesText(number(f, "bytes")),
            "seam " + num(number(f, "seam_position_jump_ratio")) + " x the mean motion, " +
                num(number(field(f, "quantisation"), "max_mm")) + " mm quantised"};
  if (job.kind == "terrain") {
    const json &t = field(f, "terrain");
    return {num(number(t, "walkable_cells"), "%.0f") + " walkable cells of " +
                num(number(t, "cell")) + " model units",
            num(number(t, "walkable_cells_in_shadow"), "%.0f") + " in shadow, " +
                num(number(t, "unreachable_cells"), "%.0f") + " flat but unreachable"};
  }
  if (job.kind == "link")
    return {bytesText(number(f, "pack_bytes")), ""};
  return {"", ""};
}

std::string animationCharts(const json &f) {
  std::string out;
  for (const auto &clip : f.value("clips", json::array())) {
    if (!clip.contains("options_tried"))
      continue;
    Chart chart{"Animation '" + text(clip, "name") + "': error against bytes",
                "bytes (every frame of the clip)", "max error at any time (mm at 1.8 m)"};
    chart.logX = chart.logY = true;
    for (const auto &o : clip["options_tried"]) {
      const std::string precision = text(o, "precision");
      auto it = std::find_if(chart.series.begin(), chart.series.end(),
                             [&](const ChartSeries &s) { return s.name == precision; });
      if (it == chart.series.end())
        it = chart.series.insert(chart.series.end(), ChartSeries{precision, {}});
      it->points.emplace_back(number(o, "bytes"), number(o, "max_error_any_time_mm"));
    }
    chart.yMark = number(f, "error_budget_mm", 1);
    chart.yMarkLabel = "budget";
    out += "<figure>" + chartSvg(chart) + "<figcaption>chosen: " + num(number(clip, "fps")) +
           " fps, " + escapeXml(text(f, "precision")) + ", " +
           num(number(clip, "max_error_any_time_mm")) + " mm</figcaption></figure>\n";
  }
  return out;
}

std::string lodChart(const json &f) {
  if (!f.contains("lod") || !f["lod"].contains("levels"))
    return "";
  Chart chart{"LOD: error against triangles", "triangles", "quadric error (model units²)"};
  chart.logY = true;
  ChartSeries s{"collapse order", {}};
  for (const auto &l : f["lod"]["levels"])
    s.points.emplace_back(number(l, "triangles"), number(l, "quadric_error"));
  chart.series.push_back(s);
  return "<figure>" + chartSvg(chart) + "</figure>\n";
}

std::string outfitTable(const json &f) {
  if (!f.contains("outfits"))
    return "";
  std::string t =
      "<table>" + row({"outfit", "garment faces", "body faces hidden", "visibility s"}, "th");
  for (const auto &o : f["outfits"])
    t += row({escapeXml(text(o, "name")), num(number(o, "garment_faces"), "%.0f"),
              num(number(o, "hidden_faces"), "%.0f"), num(number(o, "visibility_s"))});
  return t + "</table>\n";
}

std::string impostorChart(const std::vector<const JobView *> &impostors) {
  if (impostors.empty())
    return "";
  Chart chart{"Impostors: accuracy against memory", "bytes a frame", "silhouette IoU"};
  chart.logX = true;
  for (const JobView *j : impostors) {
    const json &f = j->figures;
    const bool measured = f.contains("accuracy");
    const double iou = measured ? number(field(field(f, "accuracy"), "between_views"), "iou_mean")
                                : number(f, "mirror_iou_mean");
    std::string name = text(f, "clip");
    if (!text(f, "outfit").empty())
      name += "/" + text(f, "outfit");
    name += measured ? " (between views)" : " (mirrored)";
    chart.series.push_back({name, {{number(f, "bytes_per_frame"), iou}}, false});
  }
  return "<figure>" + chartSvg(chart) + "</figure>\n";
}

std::string clothSection(const JobView &job) {
  const json &f = job.figures;
  std::string out = "<p>" + escapeXml(text(f, "verdict")) + "</p>\n";
  if (f.contains("pass1") && f["pass1"].contains("by_cycles")) {
    Chart chart{"Cloth " + text(f, "garment") + " over " + text(f, "clip") +
                    ": pass 1, the best seam per loop length",
                "loop length (clip cycles)", "seam distance (pass 1)"};
    ChartSeries s{"best start", {}};
    for (const auto &c : f["pass1"]["by_cycles"])
      s.points.emplace_back(number(c, "cycles"), number(c, "distance"));
    chart.series.push_back(s);
    out += "<figure>" + chartSvg(chart) + "</figure>\n";
  }
  if (f.contains("candidates")) {
    out += "<table>" + row({"start", "cycles", "pass-1 rank", "pass-1 distance",
                            "pass-2 edge distance (px)", "position jump (mm)"},
                           "th");
    for (const auto &c : f["candidates"])
      out += row({num(number(c, "start"), "%.0f"), num(number(c, "cycles"), "%.0f"),
                  num(number(c, "pass1_rank"), "%.0f"), num(number(c, "pass1_distance")),
                  num(number(c, "pass2_edge_px")), num(number(c, "position_jump_mm"))});
    out += "</table>\n";
  }
  return out;
}

// A character's (or one bake's) jobs: the table, then the charts.
std::string jobsSection(const std::vector<JobView> &jobs) {
  std::string out = "<table>" + row({"job", "kind", "seconds", "size", "accuracy"}, "th");
  for (const auto &j : jobs) {
    const auto [size, error] = bytesAndError(j);
    const double baked = number(j.figures, "time_s", -1); // when the part was baked
    const std::string seconds = !j.cached    ? num(j.seconds, "%.2f")
                                : baked >= 0 ? "cached (" + num(baked, "%.2f") + " s when baked)"
                                             : "cached";
    const std::string accuracy = j.failed ? "<b>failed:</b> " + escapeXml(j.error)
                                 : j.cached && j.figures.empty() ? "(no figures in the cache)"
                                                                 : error;
    out += row({escapeXml(j.label), escapeXml(j.kind), seconds, size, accuracy});
  }
  out += "</table>\n";
  std::vector<const JobView *> impostors;
  for (const auto &j : jobs) {
    if (j.kind == "mesh")
      out += outfitTable(j.figures) + animationCharts(j.figures) + lodChart(j.figures);
    else if (j.kind == "cloth")
      out += clothSection(j);
    else if (j.kind == "impostor" && !j.figures.empty())
      impostors.push_back(&j);
  }
  return out + impostorChart(impostors);
}

// One character's section: its status, its jobs' table and charts.
std::string characterSection(const json &c) {
  std::string out = "<section><h2>" + escapeXml(text(c, "name")) + "</h2>\n<p>" +
                    escapeXml(text(c, "status")) + ", pack " + escapeXml(text(c, "pack")) + ", " +
                    bytesText(number(c, "pack_bytes")) + ", baked in " +
                    num(number(c, "bake_s"), "%.2f") + " s</p>\n";
  if (!text(c, "error").empty())
    out += "<p class=\"error\">" + escapeXml(text(c, "error")) + "</p>\n";
  std::vector<JobView> views;
  for (const auto &j : c.value("jobs", json::array()))
    views.push_back({text(j, "kind"), text(j, "label"), number(j, "seconds"),
                     j.value("cached", false), j.value("failed", false), text(j, "error"),
                     j.value("figures", json::object())});
  return out + jobsSection(views) + "</section>\n";
}

std::string page(const std::string &title, const std::string &body);

// A large build: a row per character, the failed first, linking to its page in `details`.
std::string characterTable(const json &characters, const std::string &details,
                           const std::string &prefix, ReportPages &pages) {
  std::vector<const json *> order;
  for (const auto &c : characters)
    order.push_back(&c);
  std::stable_partition(order.begin(), order.end(),
                        [](const json *c) { return text(*c, "status") != "ok"; });
  std::string out = "<table>" + row({"character", "status", "jobs run", "cached", "failed",
                                     "bake seconds", "pack", "error"},
                                    "th");
  for (const json *c : order) {
    const std::string name = text(*c, "name"), file = prefix + name + ".html";
    pages.characterPages.emplace_back(file,
                                      page("crowdbake report: " + name, characterSection(*c)));
    out += row({"<a href=\"" + escapeXml(details + "/" + file) + "\">" + escapeXml(name) + "</a>",
                escapeXml(text(*c, "status")), num(number(*c, "jobs_run"), "%.0f"),
                num(number(*c, "jobs_cached"), "%.0f"), num(number(*c, "jobs_failed"), "%.0f"),
                num(number(*c, "bake_s"), "%.2f"), bytesText(number(*c, "pack_bytes")),
                "<span class=\"error\">" + escapeXml(text(*c, "error")) + "</span>"});
  }
  return out + "</table>\n";
}

std::string buildSection(const ReportSource &src, const std::string &details,
                         const std::string &prefix, ReportPages &pages) {
  const json &r = src.json;
  const json &jobs = r.value("jobs", json::object());
  std::string out =
      "<h1>Build of " + escapeXml(text(r, "input")) + "</h1>\n<p>" + escapeXml(src.path) + ": " +
      num(number(r, "time_s"), "%.1f") + " s, " + num(number(jobs, "total"), "%.0f") + " jobs (" +
      num(number(jobs, "run"), "%.0f") + " run, " + num(number(jobs, "cached"), "%.0f") +
      " cached, " + num(number(jobs, "failed"), "%.0f") + " failed), " +
      escapeXml(text(r, "baker_version")) + "</p>\n";
  const json &characters = r["characters"];
  if (characters.size() > ReportPages::kInlineCharacters)
    return out + "<p>" + num(double(characters.size()), "%.0f") + " characters, " +
           num(number(r, "characters_failed"), "%.0f") +
           " failed; each name opens its jobs and charts.</p>\n" +
           characterTable(characters, details, prefix, pages);
  for (const auto &c : characters)
    out += characterSection(c);
  return out;
}

std::string bakeSection(const ReportSource &src) {
  const json &r = src.json;
  const std::string command = text(r, "command");
  const std::string kind =
      command == "impostor" || command == "cloth" || command == "terrain" ? command : "mesh";
  std::string out = "<h1>crowdbake " + escapeXml(command) + " of " + escapeXml(text(r, "input")) +
                    "</h1>\n<p>" + escapeXml(src.path) + ": " + escapeXml(text(r, "output")) +
                    ", " + bytesText(number(r, "pack_bytes")) + "</p>\n";
  return out + "<section>" +
         jobsSection(
             {{kind, command + " " + text(r, "input"), number(r, "time_s"), false, false, "", r}}) +
         "</section>\n";
}

constexpr const char *kStyle = R"(<style>
body { font-family: sans-serif; margin: 2em; color: #222; }
table { border-collapse: collapse; margin: 1em 0; }
td, th { border: 1px solid #ccc; padding: 3px 8px; text-align: left; font-size: 13px; }
th { background: #f2f2f2; }
figure { display: inline-block; margin: 0.5em; }
figcaption { font-size: 12px; text-align: center; }
.error { color: #b00; }
section { border-top: 1px solid #ddd; margin-top: 1.5em; }
</style>
)";

std::string page(const std::string &title, const std::string &body) {
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" +
         escapeXml(title) + "</title>\n" + std::string(kStyle) + "</head><body>\n" + body +
         "</body></html>\n";
}

} // namespace

ReportPages reportPages(const std::vector<ReportSource> &sources, const std::string &details) {
  ReportPages pages;
  std::string body;
  for (size_t i = 0; i < sources.size(); ++i) {
    const ReportSource &src = sources[i];
    const json &r = src.json;
    // Two builds of characters of the same name: each source's pages apart.
    const std::string prefix = sources.size() > 1 ? std::to_string(i + 1) + "-" : "";
    try {
      if (r.is_object() && r.contains("characters") && r["characters"].is_array())
        body += buildSection(src, details, prefix, pages);
      else if (r.is_object() && r.contains("command") && r["command"].is_string())
        body += bakeSection(src);
      else
        throw Error(src.path + ": neither a build report (no \"characters\") nor a bake report (no "
                               "\"command\")");
    } catch (const nlohmann::json::exception &e) {
      throw Error(src.path + ": not a report crowdbake wrote (" + e.what() + ")");
    }
  }
  pages.page = page("crowdbake report", body);
  return pages;
}

} // namespace crowd
