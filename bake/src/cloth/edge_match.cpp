#include "crowd/bake/edge_match.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <opencv2/imgproc.hpp>

#include "crowd/bake/parallel.h"
#include "crowd/bake/raster.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {

// The mesh drawn by `camera`, shaded |n . v| with smooth normals (area-weighted at each vertex
// of this pose; cloth is seen from both sides), 8-bit, black where empty. Smooth shading keeps
// the facets of a coarse garment from showing as edges: only folds and the outline do.
cv::Mat shaded(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
               const raster::Camera &camera, glm::dvec3 toEye, int side) {
  std::vector<glm::vec3> normals(positions.size(), glm::vec3(0));
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::vec3 &a = positions[indices[t]], &b = positions[indices[t + 1]],
                    &c = positions[indices[t + 2]];
    const glm::vec3 n = glm::cross(b - a, c - a);
    for (size_t k = 0; k < 3; ++k)
      normals[indices[t + k]] += n;
  }
  raster::Options ro;
  ro.threads = 1; // the views run in parallel already
  const raster::Image image = raster::rasterize(positions, indices, camera, side, side, ro);
  cv::Mat out(side, side, CV_8U, cv::Scalar(0));
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const size_t i = image.index(x, y);
      if (image.triangle[i] < 0)
        continue;
      const glm::dvec3 n = raster::interpolate(image, i, normals, indices);
      const double len = glm::length(n);
      const double lit = len > 0 ? std::abs(glm::dot(n / len, toEye)) : 0.0;
      out.at<uint8_t>(y, x) = uint8_t(std::lround(55.0 + 200.0 * lit)); // never 0: the outline
    }
  return out;
}

// Mean over the edge pixels of `edges` of `distance` (to the other image's edges).
double meanOver(const cv::Mat &edges, const cv::Mat &distance, double &count) {
  double sum = 0.0;
  count = 0.0;
  for (int y = 0; y < edges.rows; ++y)
    for (int x = 0; x < edges.cols; ++x)
      if (edges.at<uint8_t>(y, x)) {
        sum += distance.at<float>(y, x);
        count += 1.0;
      }
  return count > 0 ? sum / count : 0.0;
}

} // namespace

std::vector<double> edgeDistances(const std::vector<glm::vec3> &a, const std::vector<glm::vec3> &b,
                                  const std::vector<uint32_t> &indices,
                                  const EdgeMatchOptions &options) {
  options.validate();
  if (a.size() != b.size() || a.empty())
    throw Error("edge match: the two frames need the same, non-zero vertex count");
  // One bounding sphere for both frames: the cameras see the two the same way.
  glm::dvec3 lo(a[0]), hi(a[0]);
  for (const auto *frame : {&a, &b})
    for (const auto &p : *frame) {
      lo = glm::min(lo, glm::dvec3(p));
      hi = glm::max(hi, glm::dvec3(p));
    }
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
  std::vector<double> out(options.views);
  parallelFor(options.views, options.threads, [&](size_t v) {
    const double azimuth = 2.0 * std::numbers::pi * double(v) / options.views,
                 elevation = std::numbers::pi / 12;
    const glm::dvec3 toEye(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                           std::cos(elevation) * std::cos(azimuth));
    const raster::Camera camera = raster::orthographic(
        centre + 3.0 * radius * toEye, centre, {0, 1, 0}, radius, radius, radius, 5.0 * radius);
    cv::Mat edges[2], distance[2];
    int i = 0;
    for (const auto *frame : {&a, &b}) {
      cv::Canny(shaded(*frame, indices, camera, toEye, options.pixels), edges[i], options.cannyLow,
                options.cannyHigh);
      cv::Mat background; // distanceTransform measures to the nearest zero pixel: the edges
      cv::threshold(edges[i], background, 0, 255, cv::THRESH_BINARY_INV);
      cv::distanceTransform(background, distance[i], cv::DIST_L2, cv::DIST_MASK_PRECISE);
      ++i;
    }
    double countA = 0, countB = 0;
    const double ab = meanOver(edges[0], distance[1], countA);
    const double ba = meanOver(edges[1], distance[0], countB);
    if (countA == 0 && countB == 0)
      out[v] = 0.0;
    else if (countA == 0 || countB == 0)
      out[v] = options.pixels;
    else
      out[v] = 0.5 * (ab + ba);
  });
  return out;
}

} // namespace crowd
