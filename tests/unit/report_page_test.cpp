// crowdbake report's page and charts: what is drawn, what is left out and said, what is escaped,
// and the reports it refuses.
#include <gtest/gtest.h>

#include "crowd/bake/report_page.h"
#include "crowd/bake/svg_chart.h"
#include "crowd/formats/error.h"

using namespace crowd;

namespace {

size_t count(const std::string &text, const std::string &what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

} // namespace

TEST(SvgChart, ALogAxisLeavesOutWhatItCannotDrawAndTextIsEscaped) {
  Chart chart("error <against> bytes", "bytes", "mm");
  chart.logY = true;
  chart.series.push_back({"a&b", {{1, 10}, {2, 0}, {3, -1}, {4, 0.01}}});
  chart.yMark = 1;
  chart.yMarkLabel = "budget";
  const std::string svg = chartSvg(chart);
  EXPECT_EQ(count(svg, "<circle"), 2u); // 0 and -1 have no place on a log axis
  EXPECT_NE(svg.find("error &lt;against&gt; bytes"), std::string::npos);
  EXPECT_NE(svg.find(">a&amp;b<"), std::string::npos);
  EXPECT_NE(svg.find("budget"), std::string::npos);
  EXPECT_NE(svg.find(">0.01<"), std::string::npos); // a power-of-ten tick

  Chart empty("nothing", "x", "y");
  empty.logX = true;
  empty.series.push_back({"zeros", {{0, 1}}});
  EXPECT_NE(chartSvg(empty).find("no data to draw"), std::string::npos);
}

TEST(ReportPage, ABuildReportGivesEachCharacterItsJobsAndCharts) {
  const auto build = nlohmann::json::parse(R"({
    "input": "library.json", "time_s": 12.5, "baker_version": "crowdbake test",
    "jobs": {"total": 4, "run": 3, "cached": 1, "failed": 0},
    "characters": [
      {"name": "walker", "status": "ok", "pack": "out/walker.crowdpack", "pack_bytes": 900000,
       "jobs": [
         {"kind": "mesh", "label": "walker: mesh", "seconds": 6.5, "cached": false,
          "failed": false, "figures": {"triangles": 6584, "precision": "qts-half",
            "error_budget_mm": 1.0,
            "clips": [{"name": "walk", "fps": 30, "max_error_any_time_mm": 0.43,
              "options_tried": [
                {"fps": 10, "precision": "qts", "bytes": 7744, "max_error_any_time_mm": 45.5},
                {"fps": 30, "precision": "qts", "bytes": 21000, "max_error_any_time_mm": 0.4}]}],
            "lod": {"levels": [{"triangles": 3293, "quadric_error": 1e-10},
                               {"triangles": 659, "quadric_error": 5e-6}]}}},
         {"kind": "impostor", "label": "walker: impostor walk", "seconds": 0.5,
          "cached": true, "failed": false, "figures": {}},
         {"kind": "cloth", "label": "walker: cloth", "seconds": 0, "cached": true,
          "failed": false, "figures": {"garment": "dress", "clip": "walk", "bytes": 750000,
            "time_s": 0.1,
            "verdict": "a hard cut", "pass1": {"by_cycles": [{"cycles": 1, "distance": 2e-6}]},
            "candidates": [{"start": 99, "cycles": 4, "pass1_rank": 0, "pass2_edge_px": 0.58}]}}]},
      {"name": "broken", "status": "failed", "error": "broken.glb: not <glTF>", "jobs": []}]})");
  const std::string page = reportPages({{"out/build.report.json", build}}, "d").page;
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.find("<h2>walker</h2>"), std::string::npos);
  EXPECT_NE(page.find("<h2>broken</h2>"), std::string::npos);
  EXPECT_NE(page.find("broken.glb: not &lt;glTF&gt;"), std::string::npos);
  EXPECT_NE(page.find("Animation &#39;walk&#39;: error against bytes"), std::string::npos);
  EXPECT_NE(page.find("LOD: error against triangles"), std::string::npos);
  EXPECT_NE(page.find("pass 1, the best seam per loop length"), std::string::npos);
  EXPECT_NE(page.find("(no figures in the cache)"), std::string::npos);
  EXPECT_NE(page.find("cached (0.10 s when baked)"), std::string::npos);
  EXPECT_NE(page.find("0.43 mm at any time (clip walk), qts-half"), std::string::npos);
  EXPECT_EQ(count(page, "<svg"), 3u); // animation, LOD, cloth; the cached impostor has no figures
  EXPECT_EQ(page.find("<script"), std::string::npos);
}

TEST(ReportPage, ATerrainBakeReportGivesItsMaps) {
  const auto report = nlohmann::json::parse(R"({"command": "terrain", "input": "village.glb",
    "output": "village.crowdpack", "pack_bytes": 1152704, "time_s": 0.2,
    "terrain": {"cells": [320, 320], "cell": 0.25, "walkable_cells": 94056,
      "unreachable_cells": 8344, "walkable_cells_in_shadow": 4959}})");
  const std::string page = reportPages({{"village.json", report}}, "d").page;
  EXPECT_NE(page.find("<h1>crowdbake terrain of village.glb</h1>"), std::string::npos);
  EXPECT_NE(page.find("94056 walkable cells of 0.25 model units"), std::string::npos) << page;
  EXPECT_NE(page.find("4959 in shadow, 8344 flat but unreachable"), std::string::npos);
}

TEST(ReportPage, ALargeBuildIsASummaryWithAPagePerCharacter) {
  nlohmann::json build = {{"input", "lib.json"}, {"characters", nlohmann::json::array()}};
  const size_t n = ReportPages::kInlineCharacters + 5;
  for (size_t i = 0; i < n; ++i)
    build["characters"].push_back(
        {{"name", std::string("c").append(std::to_string(i))},
         {"status", i == 7 ? "failed" : "ok"},
         {"error", i == 7 ? "c7: mesh: ran 9.0 s, over --job-max-seconds 8 s: killed" : ""},
         {"jobs", {{{"kind", "link"}, {"label", "c: link"}, {"seconds", 0.1}}}}});
  const ReportPages pages = reportPages({{"out/build.report.json", build}}, "r.characters");
  ASSERT_EQ(pages.characterPages.size(), n);
  EXPECT_EQ(pages.characterPages[0].first, "c7.html"); // the failed first
  const size_t link = pages.page.find("<a href=\"r.characters/c7.html\">c7</a>");
  EXPECT_NE(link, std::string::npos);
  EXPECT_LT(link, pages.page.find("r.characters/c0.html"));
  EXPECT_NE(pages.page.find("over --job-max-seconds 8 s"), std::string::npos);
  EXPECT_NE(pages.characterPages[3].second.find("<h2>c2</h2>"), std::string::npos);
  EXPECT_EQ(pages.page.find("<h2>"), std::string::npos); // no character's section inline
  while (build["characters"].size() > ReportPages::kInlineCharacters) // 20: one page, as before
    build["characters"].erase(build["characters"].size() - 1);
  EXPECT_TRUE(reportPages({{"b.json", build}}, "d").characterPages.empty());
}

TEST(ReportPage, WhatIsNotAReportIsAClearError) {
  try {
    reportPages({{"a.json", nlohmann::json::parse(R"({"name": "x"})")}}, "d");
    FAIL() << "accepted";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("a.json: neither a build report"), std::string::npos)
        << e.what();
  }
  const auto mistyped = nlohmann::json::parse(
      R"({"characters": [{"name": "a", "jobs": [{"kind": "mesh", "cached": "yes"}]}]})");
  EXPECT_THROW(reportPages({{"b.json", mistyped}}, "d").page, Error);
}
