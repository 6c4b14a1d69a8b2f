#include "village.h"

#include <algorithm>
#include <array>

namespace crowd::samples {

namespace {

constexpr float kHalf = 40; // the ground spans x and z in [-40, 40]

// The ground's height: flat (0) within the square, rising at 8% east of x = 12.
float groundHeight(float x, float) { return std::max(0.0f, x - 12) * 0.08f; }

void quad(VillagePart &p, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
  const glm::vec3 n = glm::normalize(glm::cross(b - a, d - a)); // a b c d counter-clockwise
  const uint32_t first = uint32_t(p.positions.size());
  for (const auto &v : {a, b, c, d}) {
    p.positions.push_back(v);
    p.normals.push_back(n);
  }
  for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u})
    p.indices.push_back(first + i);
}

// A box from `lo` to `hi`: its top and four sides (the ground hides the bottom).
void box(VillagePart &p, glm::vec3 lo, glm::vec3 hi) {
  quad(p, {lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z}); // top
  quad(p, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}); // +z
  quad(p, {hi.x, lo.y, lo.z}, {lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}); // -z
  quad(p, {hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}); // +x
  quad(p, {lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z}); // -x
}

} // namespace

std::vector<VillagePart> villageParts() {
  VillagePart ground{"ground", {0.42f, 0.55f, 0.30f, 1}, {}, {}, {}};
  VillagePart paving{"paving", {0.62f, 0.60f, 0.56f, 1}, {}, {}, {}};
  VillagePart walls{"walls", {0.85f, 0.78f, 0.62f, 1}, {}, {}, {}};
  VillagePart roofs{"roofs", {0.55f, 0.22f, 0.16f, 1}, {}, {}, {}};
  VillagePart furniture{"bus_stop", {0.20f, 0.35f, 0.55f, 1}, {}, {}, {}};

  // Ground: 2 m quads, the square's paving separate (both follow groundHeight).
  for (float z = -kHalf; z < kHalf; z += 2)
    for (float x = -kHalf; x < kHalf; x += 2) {
      const bool square = x >= -12 && x + 2 <= 12 && z >= -12 && z + 2 <= 12;
      auto at = [](float px, float pz) { return glm::vec3(px, groundHeight(px, pz), pz); };
      quad(square ? paving : ground, at(x, z), at(x, z + 2), at(x + 2, z + 2), at(x + 2, z));
    }
  // The terrace to the north (z < -26), 0.45 m up, and 0.15 m steps up to it.
  box(paving, {-10, -0.2f, -40}, {10, 0.45f, -26});
  for (int s = 0; s < 2; ++s)
    box(paving, {-4, -0.2f, -25 - float(s)}, {4, 0.15f * float(s + 1), -24 - float(s)});
  // A planter in the square, 1 m high: nobody steps onto it.
  box(paving, {3, -0.2f, 3}, {6, 1.0f, 6});
  // Buildings around the square: walls, and a flat roof slab above each.
  const glm::vec4 houses[6] = {{-24, -20, 8, 6}, {-24, 0, 8, 9}, {-24, 18, 8, 7},
                               {16, -22, 10, 8}, {18, 4, 8, 10}, {-6, 18, 10, 6}};
  for (const auto &h : houses) { // x, z of the corner, side, height above the ground there
    const float base = groundHeight(h.x, h.y), top = base + h.w; // the lower side's ground
    box(walls, {h.x, base - 1, h.y}, {h.x + h.z, top, h.y + h.z});
    box(roofs, {h.x - 0.3f, top, h.y - 0.3f}, {h.x + h.z + 0.3f, top + 0.3f, h.y + h.z + 0.3f});
  }
  // The bus stop on the square's south edge: a bench, a back panel and a sign post.
  box(furniture, {-3, 0, 9}, {1, 0.45f, 9.6f});
  box(furniture, {-3, 0, 9.8f}, {1, 2.2f, 9.9f});
  box(furniture, {1.5f, 0, 9.3f}, {1.6f, 2.6f, 9.4f});
  return {ground, paving, walls, roofs, furniture};
}

namespace {

// Paints `rgba` over the cells whose centres lie in [x0, x1) x [z0, z1) (metres).
void paint(std::vector<uint8_t> &image, float x0, float z0, float x1, float z1,
           std::array<uint8_t, 4> rgba) {
  const float cell = 2 * kHalf / float(kVillageCells);
  for (uint32_t z = 0; z < kVillageCells; ++z)
    for (uint32_t x = 0; x < kVillageCells; ++x) {
      const float cx = -kHalf + (float(x) + 0.5f) * cell, cz = -kHalf + (float(z) + 0.5f) * cell;
      if (cx >= x0 && cx < x1 && cz >= z0 && cz < z1)
        std::copy(rgba.begin(), rgba.end(), &image[4 * (size_t(z) * kVillageCells + x)]);
    }
}

} // namespace

std::vector<uint8_t> villageBehaviours() {
  std::vector<uint8_t> image(size_t(kVillageCells) * kVillageCells * 4);
  paint(image, -kHalf, -kHalf, kHalf, kHalf, {0, 255, 0, 255}); // wander
  paint(image, -12, 2, 12, 8, {0, 0, 255, 255});                // to the bus stop
  paint(image, -6, -36, 6, -30, {255, 0, 0, 255});              // the market: wait
  paint(image, 36, -kHalf, kHalf, kHalf, {255, 255, 0, 255});   // the east edge: turn
  return image;
}

std::vector<uint8_t> villageCallbacks() {
  std::vector<uint8_t> image(size_t(kVillageCells) * kVillageCells * 4, 0);
  const uint8_t *c = kVillageBusStopColour;
  paint(image, -3, 8, 1, 8.9f, {c[0], c[1], c[2], 255}); // the queue in front of the bench
  return image;
}

} // namespace crowd::samples
