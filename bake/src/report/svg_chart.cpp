#include "crowd/bake/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace crowd {

namespace {

constexpr double kWidth = 640, kHeight = 360;
constexpr double kLeft = 70, kRight = 180, kTop = 36, kBottom = 48; // margins
constexpr const char *kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                    "#9467bd", "#8c564b", "#e377c2", "#17becf"};

std::string number(double v, const char *format = "%.4g") {
  char b[32];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

// One axis: the range of the data (in log10 where log) and its ticks.
struct Axis {
  bool log = false;
  double lo = 0, hi = 1;
  double map(double v) const { return log ? std::log10(v) : v; }
  bool drawable(double v) const { return std::isfinite(v) && (!log || v > 0); }

  void fit(const std::vector<double> &values) {
    lo = std::numeric_limits<double>::max();
    hi = std::numeric_limits<double>::lowest();
    for (double v : values) {
      lo = std::min(lo, map(v));
      hi = std::max(hi, map(v));
    }
    if (log) {
      lo = std::floor(lo);
      hi = std::max(std::ceil(hi), lo + 1);
    } else {
      lo = std::min(lo, 0.0);
      if (hi <= lo)
        hi = lo + 1;
      hi += (hi - lo) * 0.05;
    }
  }

  // Powers of ten on a log axis; on a linear one about six 1-2-5 steps.
  std::vector<double> ticks() const {
    std::vector<double> t;
    if (log) {
      const double step = std::max(1.0, std::ceil((hi - lo) / 8));
      for (double e = lo; e <= hi + 1e-9; e += step)
        t.push_back(std::pow(10.0, e));
      return t;
    }
    const double raw = (hi - lo) / 6, mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2 * mag : 5 * mag;
    for (double v = std::ceil(lo / step) * step; v <= hi + step * 1e-9; v += step)
      t.push_back(std::abs(v) < step * 1e-9 ? 0 : v);
    return t;
  }
};

} // namespace

std::string escapeXml(const std::string &text) {
  std::string out;
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

std::string chartSvg(const Chart &chart) {
  Axis x, y;
  x.log = chart.logX;
  y.log = chart.logY;
  std::vector<double> xs, ys;
  for (const auto &s : chart.series)
    for (const auto &[px, py] : s.points)
      if (x.drawable(px) && y.drawable(py)) {
        xs.push_back(px);
        ys.push_back(py);
      }
  if (chart.yMark && y.drawable(*chart.yMark))
    ys.push_back(*chart.yMark);
  const bool empty = xs.empty();
  if (!empty) {
    x.fit(xs);
    y.fit(ys);
  }
  const double plotW = kWidth - kLeft - kRight, plotH = kHeight - kTop - kBottom;
  auto sx = [&](double v) { return kLeft + (x.map(v) - x.lo) / (x.hi - x.lo) * plotW; };
  auto sy = [&](double v) { return kHeight - kBottom - (y.map(v) - y.lo) / (y.hi - y.lo) * plotH; };

  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + number(kWidth) +
                  "\" height=\"" + number(kHeight) +
                  "\" font-family=\"sans-serif\" font-size=\"11\" role=\"img\">\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += "<text x=\"" + number(kWidth / 2) + "\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">" +
       escapeXml(chart.title) + "</text>\n";
  const std::string x0 = number(kLeft), x1 = number(kLeft + plotW), y0 = number(kTop),
                    y1 = number(kTop + plotH);
  s +=
      "<path d=\"M" + x0 + " " + y0 + "V" + y1 + "H" + x1 + "\" fill=\"none\" stroke=\"black\"/>\n";
  s += "<text x=\"" + number(kLeft + plotW / 2) + "\" y=\"" + number(kHeight - 10) +
       "\" text-anchor=\"middle\">" + escapeXml(chart.xLabel) + "</text>\n";
  s += "<text transform=\"translate(16 " + number(kTop + plotH / 2) +
       ") rotate(-90)\" text-anchor=\"middle\">" + escapeXml(chart.yLabel) + "</text>\n";
  if (empty) {
    s += "<text x=\"" + number(kLeft + plotW / 2) + "\" y=\"" + number(kTop + plotH / 2) +
         "\" text-anchor=\"middle\">no data to draw</text>\n</svg>\n";
    return s;
  }
  for (double t : x.ticks()) {
    const std::string px = number(sx(t));
    s += "<line x1=\"" + px + "\" y1=\"" + y1 + "\" x2=\"" + px + "\" y2=\"" + y0 +
         "\" stroke=\"#ddd\"/><text x=\"" + px + "\" y=\"" + number(kTop + plotH + 14) +
         "\" text-anchor=\"middle\">" + number(t, "%.6g") + "</text>\n";
  }
  for (double t : y.ticks()) {
    const std::string py = number(sy(t));
    s += "<line x1=\"" + x0 + "\" y1=\"" + py + "\" x2=\"" + x1 + "\" y2=\"" + py +
         "\" stroke=\"#ddd\"/><text x=\"" + number(kLeft - 4) + "\" y=\"" + number(sy(t) + 4) +
         "\" text-anchor=\"end\">" + number(t, "%.6g") + "</text>\n";
  }
  if (chart.yMark && y.drawable(*chart.yMark)) {
    const std::string py = number(sy(*chart.yMark));
    s += "<line x1=\"" + x0 + "\" y1=\"" + py + "\" x2=\"" + x1 + "\" y2=\"" + py +
         "\" stroke=\"#555\" stroke-dasharray=\"5 4\"/><text x=\"" + number(kLeft + plotW - 4) +
         "\" y=\"" + number(sy(*chart.yMark) - 4) + "\" text-anchor=\"end\">" +
         escapeXml(chart.yMarkLabel) + "</text>\n";
  }
  for (size_t i = 0; i < chart.series.size(); ++i) {
    const auto &series = chart.series[i];
    const std::string colour = kColours[i % std::size(kColours)];
    std::string path;
    for (const auto &[px, py] : series.points) {
      if (!x.drawable(px) || !y.drawable(py))
        continue;
      path += path.empty() ? 'M' : 'L';
      path += number(sx(px)) + " " + number(sy(py));
      s += "<circle cx=\"" + number(sx(px)) + "\" cy=\"" + number(sy(py)) + "\" r=\"3\" fill=\"" +
           colour + "\"><title>" + escapeXml(series.name) + ": " + number(px) + ", " + number(py) +
           "</title></circle>\n";
    }
    if (series.line && !path.empty())
      s += "<path d=\"" + path + "\" fill=\"none\" stroke=\"" + colour + "\"/>\n";
    const double ly = kTop + 8 + 16 * double(i);
    s += "<rect x=\"" + number(kLeft + plotW + 12) + "\" y=\"" + number(ly - 8) +
         "\" width=\"10\" height=\"10\" fill=\"" + colour + "\"/><text x=\"" +
         number(kLeft + plotW + 26) + "\" y=\"" + number(ly + 1) + "\">" + escapeXml(series.name) +
         "</text>\n";
  }
  return s + "</svg>\n";
}

} // namespace crowd
