// Line and point charts as standalone SVG text, for pages with no scripts and no network
// (crowdbake report). Axes are linear or log10; ticks fall on 1-2-5 steps or powers of ten.
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace crowd {

struct ChartSeries {
  std::string name;
  std::vector<std::pair<double, double>> points; // (x, y), drawn in this order
  bool line = true;                              // false: points only
};

struct Chart {
  Chart(std::string title, std::string xLabel, std::string yLabel)
      : title(std::move(title)), xLabel(std::move(xLabel)), yLabel(std::move(yLabel)) {}
  std::string title, xLabel, yLabel;
  bool logX = false, logY = false; // a log axis leaves out points at or below 0
  std::vector<ChartSeries> series;
  std::optional<double> yMark; // a horizontal dashed line (a budget), labelled
  std::string yMarkLabel;
};

// An <svg> element (640 x 360) with its legend; text is escaped. A chart with no drawable
// point says so in its plot area.
std::string chartSvg(const Chart &chart);

// Text safe inside HTML or SVG elements and attributes.
std::string escapeXml(const std::string &text);

} // namespace crowd
