// Pass 2 of the cloth-loop bake: do the two ends of a seam look alike? The garment is drawn at
// both frames by the deterministic rasterizer from `views` cameras around it (one orthographic
// framing shared by both frames, so images line up), shaded by |normal . view| so folds show as
// well as the outline; OpenCV's Canny turns each image into edges, and the distance between
// the two edge images is the symmetric mean edge (chamfer) distance, through
// cv::distanceTransform: the mean, over the edge pixels of each image, of the distance to the
// nearest edge pixel of the other, averaged both ways. In pixels, per view; the views' sum
// ranks the candidates.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace crowd {

struct EdgeMatchOptions {
  uint32_t views = 5; // --views: cameras evenly around the garment, 15 degrees above it
  int pixels = 160;   // image side; the garment's bounding sphere fills it
  // Canny's hysteresis thresholds on the 8-bit shading (Sobel 3x3 gradient). The shading of
  // adjacent folds differs by about 0.15 in |n . v|, 38 grey levels, a gradient near 150 across
  // a fold: 100 keeps folds and the outline, 40 continues them through shallower stretches
  // (Canny's advice: high = 2 to 3 x low), and flat-shaded facets of one smooth surface (under
  // 0.05 apart, 13 levels) stay below both.
  double cannyLow = 40.0, cannyHigh = 100.0;
  int threads = 0;
  void validate() const;
};

// Per view, the symmetric mean edge distance in pixels between the mesh at positions `a` and
// at `b` (same vertex order, triangles `indices`). An image with no edges is `pixels` away from
// one with some (0 when neither has any).
std::vector<double> edgeDistances(const std::vector<glm::vec3> &a, const std::vector<glm::vec3> &b,
                                  const std::vector<uint32_t> &indices,
                                  const EdgeMatchOptions &options);

} // namespace crowd
