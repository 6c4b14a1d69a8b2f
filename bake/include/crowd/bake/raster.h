// Deterministic CPU rasterizer shared by the outfit and impostor bakes and the tests:
// orthographic or perspective camera, depth test, per-pixel triangle id and perspective-correct
// barycentrics. Ties in depth go to the lower triangle id, so the image is the same whatever
// order or thread count the triangles are drawn with. Pixel centres sit at (x + 0.5, y + 0.5);
// row 0 is the top of the image; edges follow the top-left fill rule, so triangles sharing an
// edge cover each pixel exactly once.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace crowd::raster {

struct Camera {
  glm::dmat4 view{1.0};
  glm::dmat4 projection{1.0};
};

Camera orthographic(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, double halfWidth,
                    double halfHeight, double near, double far);
Camera perspective(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, double fovYRadians,
                   double aspect, double near, double far);

struct Image {
  int width = 0, height = 0;
  std::vector<float> depth;           // NDC z in [-1, 1]; +inf where empty
  std::vector<int32_t> triangle;      // triangle index, -1 where empty
  std::vector<glm::vec3> barycentric; // weights of the triangle's three vertices
  size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
};

struct Options {
  bool cullBackFaces = false; // drop triangles wound clockwise on screen
  int threads = 0;            // 0: all cores; the image never depends on it
};

// Triangles with a vertex behind the camera's near plane are skipped (no clipping): the bakes
// frame whole characters, so nothing crosses the near plane.
Image rasterize(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                const Camera &camera, int width, int height, const Options &options = {});

// Attribute of the visible surface at pixel i, interpolated with its barycentrics.
template <class T>
T interpolate(const Image &image, size_t i, const std::vector<T> &attribute,
              const std::vector<uint32_t> &indices) {
  const glm::vec3 b = image.barycentric[i];
  const size_t t = size_t(image.triangle[i]) * 3;
  return attribute[indices[t]] * b.x + attribute[indices[t + 1]] * b.y +
         attribute[indices[t + 2]] * b.z;
}

} // namespace crowd::raster
