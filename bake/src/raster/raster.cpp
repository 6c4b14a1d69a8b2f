#include "crowd/bake/raster.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "crowd/bake/parallel.h"

namespace crowd::raster {

Camera orthographic(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, double halfWidth,
                    double halfHeight, double near, double far) {
  return {glm::lookAt(eye, target, up),
          glm::ortho(-halfWidth, halfWidth, -halfHeight, halfHeight, near, far)};
}

Camera perspective(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, double fovY, double aspect,
                   double near, double far) {
  return {glm::lookAt(eye, target, up), glm::perspective(fovY, aspect, near, far)};
}

namespace {

struct ScreenVertex {
  double x, y, z, invW;
  bool valid;
};

// Top-left rule for a counter-clockwise triangle in a y-down image: an edge owns the pixels
// exactly on it when it is a top edge (horizontal, going left) or a left edge (going down).
bool ownsEdge(double ax, double ay, double bx, double by) {
  double dx = bx - ax, dy = by - ay;
  return (dy == 0 && dx < 0) || dy > 0;
}

} // namespace

Image rasterize(const std::vector<glm::vec3> &positions, const std::vector<uint32_t> &indices,
                const Camera &camera, int width, int height, const Options &options) {
  Image img;
  img.width = width;
  img.height = height;
  size_t n = size_t(width) * size_t(height);
  img.depth.assign(n, std::numeric_limits<float>::infinity());
  img.triangle.assign(n, -1);
  img.barycentric.assign(n, glm::vec3(0));

  const glm::dmat4 m = camera.projection * camera.view;
  std::vector<ScreenVertex> sv(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) {
    glm::dvec4 c = m * glm::dvec4(glm::dvec3(positions[v]), 1.0);
    bool valid = c.w > 0 && c.z >= -c.w;
    double iw = valid ? 1.0 / c.w : 0;
    sv[v] = {(c.x * iw * 0.5 + 0.5) * width, (0.5 - c.y * iw * 0.5) * height, c.z * iw, iw, valid};
  }

  const int band = 16;
  const size_t bands = size_t((height + band - 1) / band);
  parallelFor(bands, options.threads, [&](size_t bi) {
    const int y0 = int(bi) * band, y1 = std::min(height, y0 + band);
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
      const ScreenVertex *p[3] = {&sv[indices[t]], &sv[indices[t + 1]], &sv[indices[t + 2]]};
      if (!p[0]->valid || !p[1]->valid || !p[2]->valid)
        continue;
      // Signed area in a y-down image: positive for clockwise-on-screen (back faces).
      double area =
          (p[1]->x - p[0]->x) * (p[2]->y - p[0]->y) - (p[2]->x - p[0]->x) * (p[1]->y - p[0]->y);
      if (area == 0 || (options.cullBackFaces && area > 0))
        continue;
      int order[3] = {0, 1, 2};
      if (area > 0)
        std::swap(order[1], order[2]), area = -area;
      const ScreenVertex *a = p[order[0]];
      const ScreenVertex *b = p[order[1]];
      const ScreenVertex *c = p[order[2]];
      double minY = std::min({a->y, b->y, c->y}), maxY = std::max({a->y, b->y, c->y});
      double minX = std::min({a->x, b->x, c->x}), maxX = std::max({a->x, b->x, c->x});
      int ys = std::max(y0, int(std::ceil(minY - 0.5))),
          ye = std::min(y1 - 1, int(std::floor(maxY - 0.5)));
      int xs = std::max(0, int(std::ceil(minX - 0.5))),
          xe = std::min(width - 1, int(std::floor(maxX - 0.5)));
      if (ys > ye || xs > xe)
        continue;
      const ScreenVertex *e0[2] = {b, c}; // edge opposite a
      const ScreenVertex *e1[2] = {c, a};
      const ScreenVertex *e2[2] = {a, b};
      const ScreenVertex *const *edges[3] = {e0, e1, e2};
      bool owns[3];
      for (int k = 0; k < 3; ++k)
        owns[k] = ownsEdge(edges[k][0]->x, edges[k][0]->y, edges[k][1]->x, edges[k][1]->y);
      for (int y = ys; y <= ye; ++y) {
        double py = y + 0.5;
        for (int x = xs; x <= xe; ++x) {
          double px = x + 0.5;
          double w[3];
          bool inside = true;
          for (int k = 0; k < 3 && inside; ++k) {
            // The edge function from the edge's lower endpoint (x, then y) whichever triangle
            // asks, so that two triangles sharing the edge get exactly opposite values and the
            // fill rule, not rounding, decides a pixel on it.
            const ScreenVertex *u = edges[k][0], *v = edges[k][1];
            const bool swapped = u->x > v->x || (u->x == v->x && u->y > v->y);
            if (swapped)
              std::swap(u, v);
            const double e = (v->x - u->x) * (py - u->y) - (v->y - u->y) * (px - u->x);
            // Negative inside for our (counter-clockwise on screen) winding: flip the sign.
            w[k] = swapped ? e : -e;
            inside = w[k] > 0 || (w[k] == 0 && owns[k]);
          }
          if (!inside)
            continue;
          double l[3] = {w[0] / -area, w[1] / -area, w[2] / -area};
          float z = float(l[0] * a->z + l[1] * b->z + l[2] * c->z);
          size_t i = img.index(x, y);
          if (z > 1 || z < -1)
            continue;
          if (z > img.depth[i] || (z == img.depth[i] && int32_t(t / 3) > img.triangle[i]))
            continue;
          double pw[3] = {l[0] * a->invW, l[1] * b->invW, l[2] * c->invW};
          double sum = pw[0] + pw[1] + pw[2];
          glm::vec3 bary;
          for (int k = 0; k < 3; ++k)
            bary[order[k]] = float(pw[k] / sum);
          img.depth[i] = z;
          img.triangle[i] = int32_t(t / 3);
          img.barycentric[i] = bary;
        }
      }
    }
  });
  return img;
}

} // namespace crowd::raster
