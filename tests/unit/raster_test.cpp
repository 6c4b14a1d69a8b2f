#include <algorithm>
#include <gtest/gtest.h>

#include "crowd/bake/raster.h"

using namespace crowd::raster;

namespace {

// A camera looking down -z at the unit square [0,1]^2 that maps it to the whole image.
Camera squareCamera() {
  return orthographic({0.5, 0.5, 5}, {0.5, 0.5, 0}, {0, 1, 0}, 0.5, 0.5, 0.1, 10);
}

TEST(Raster, TwoTrianglesSharingAnEdgeCoverEveryPixelOnce) {
  // The shared diagonal passes through pixel centres at even sizes: the top-left rule must give
  // each of them to exactly one triangle, so drawing the two alone covers every pixel once.
  std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  for (int size : {8, 16, 33}) {
    Image a = rasterize(p, {0, 1, 2}, squareCamera(), size, size);
    Image b = rasterize(p, {2, 1, 3}, squareCamera(), size, size);
    for (size_t i = 0; i < a.triangle.size(); ++i)
      ASSERT_EQ((a.triangle[i] >= 0) + (b.triangle[i] >= 0), 1)
          << "size " << size << " pixel " << i;
  }
}

TEST(Raster, AGridOfQuadsLeavesNoCrackOnItsDiagonals) {
  // A sloping 80 m ground of 2 m quads seen from above at 0.25 m pixels (the terrain bake's
  // view): every pixel centre of the diagonals lies on an edge two triangles share, with screen
  // coordinates that round differently from either side. Each pixel must still be covered.
  std::vector<glm::vec3> p;
  std::vector<uint32_t> idx;
  for (int z = -40; z < 40; z += 2)
    for (int x = -40; x < 40; x += 2) {
      const uint32_t first = uint32_t(p.size());
      for (auto [px, pz] : {std::pair{x, z}, {x, z + 2}, {x + 2, z + 2}, {x + 2, z}})
        p.push_back({float(px), 0.08f * float(px + 40), float(pz)});
      for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u})
        idx.push_back(first + i);
    }
  const Camera above = orthographic({0, 10, 0}, {0, -1, 0}, {0, 0, -1}, 40, 40, 0.5, 12);
  const Image img = rasterize(p, idx, above, 320, 320);
  EXPECT_EQ(std::count(img.triangle.begin(), img.triangle.end(), -1), 0);
}

TEST(Raster, DepthTestKeepsTheNearerTriangle) {
  std::vector<glm::vec3> p = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  Image img = rasterize(p, {0, 1, 2, 3, 4, 5}, squareCamera(), 10, 10);
  EXPECT_EQ(img.triangle[img.index(1, 8)], 1); // z = 1 is nearer the camera at z = 5
  Image swapped = rasterize(p, {3, 4, 5, 0, 1, 2}, squareCamera(), 10, 10);
  EXPECT_EQ(swapped.triangle[swapped.index(1, 8)], 0);
}

TEST(Raster, OrthographicBarycentricsInterpolateLinearly) {
  std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  std::vector<uint32_t> idx = {0, 1, 2};
  Image img = rasterize(p, idx, squareCamera(), 20, 20);
  std::vector<glm::vec2> uv = {{0, 0}, {1, 0}, {0, 1}};
  size_t i = img.index(3, 20 - 1 - 5); // pixel centre (3.5, 5.5)/20 in square units
  ASSERT_EQ(img.triangle[i], 0);
  glm::vec2 got = interpolate(img, i, uv, idx);
  EXPECT_NEAR(got.x, 3.5f / 20, 1e-6);
  EXPECT_NEAR(got.y, 5.5f / 20, 1e-6);
}

TEST(Raster, PerspectiveBarycentricsAreCorrectedByDepth) {
  // A floor plane receding from the camera: the interpolated world z must match the ray's hit.
  std::vector<glm::vec3> p = {{-1, 0, 0}, {1, 0, 0}, {-1, 0, -10}, {1, 0, -10}};
  std::vector<uint32_t> idx = {0, 1, 2, 2, 1, 3};
  Camera cam = perspective({0, 1, 1}, {0, 0, -3}, {0, 1, 0}, glm::radians(60.0), 1.0, 0.1, 100);
  Image img = rasterize(p, idx, cam, 64, 64);
  glm::dmat4 inv = glm::inverse(cam.projection * cam.view);
  int checked = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; x += 7) {
      size_t i = img.index(x, y);
      if (img.triangle[i] < 0)
        continue;
      glm::vec3 world = interpolate(img, i, p, idx);
      // Unproject the pixel centre at the stored depth.
      glm::dvec4 ndc((x + 0.5) / 32.0 - 1, 1 - (y + 0.5) / 32.0, img.depth[i], 1);
      glm::dvec4 w = inv * ndc;
      EXPECT_NEAR(world.z, w.z / w.w, 2e-3 * std::abs(world.z) + 1e-4);
      EXPECT_NEAR(world.y, 0.0, 1e-5);
      ++checked;
    }
  EXPECT_GT(checked, 50);
}

TEST(Raster, IdenticalAtAnyThreadCount) {
  std::vector<glm::vec3> p;
  std::vector<uint32_t> idx;
  for (int k = 0; k < 200; ++k) {
    float a = float(k) * 0.37f, r = 0.1f + float(k % 7) * 0.05f, z = float(k % 5) * 0.1f - 0.2f;
    glm::vec3 c(0.5f + 0.3f * std::cos(a), 0.5f + 0.3f * std::sin(a), z);
    uint32_t b = uint32_t(p.size());
    p.insert(p.end(), {c, c + glm::vec3(r, 0.02f, 0), c + glm::vec3(0.01f, r, 0.05f)});
    idx.insert(idx.end(), {b, b + 1, b + 2});
  }
  Image one = rasterize(p, idx, squareCamera(), 97, 61, {false, 1});
  for (int t : {2, 3, 8}) {
    Image many = rasterize(p, idx, squareCamera(), 97, 61, {false, t});
    EXPECT_EQ(one.triangle, many.triangle);
    EXPECT_EQ(one.depth, many.depth);
    EXPECT_EQ(one.barycentric, many.barycentric);
  }
}

TEST(Raster, BackFacesCanBeCulled) {
  std::vector<glm::vec3> p = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}; // clockwise seen from +z
  Image kept = rasterize(p, {0, 1, 2}, squareCamera(), 8, 8);
  Image culled = rasterize(p, {0, 1, 2}, squareCamera(), 8, 8, {true, 1});
  EXPECT_GE(kept.triangle[kept.index(1, 6)], 0);
  EXPECT_EQ(culled.triangle[culled.index(1, 6)], -1);
}

} // namespace
