// The LOD's face lists (bake/src/lod/face_lists.h): each vertex's list, after any sequence of
// collapses that outgrows rooms, moves lists and packs the array, reads as a vector per vertex
// would: its live faces in the order they came.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "../../bake/src/lod/face_lists.h"

namespace {

TEST(FaceLists, HandOnKeepsEachListsLiveFacesInOrderThroughMovesAndPacks) {
  std::mt19937 random(29);
  const uint32_t vertices = 300, faces = 3000;
  std::vector<std::vector<uint32_t>> model(vertices);
  std::vector<uint32_t> room(vertices, 0);
  std::vector<uint32_t> owner(faces);
  for (uint32_t f = 0; f < faces; ++f)
    ++room[owner[f] = uint32_t(random() % vertices)];
  crowd::lod::FaceLists lists(room);
  for (uint32_t f = 0; f < faces; ++f)
    lists.push(owner[f], f), model[owner[f]].push_back(f);
  std::vector<uint8_t> alive(faces, 1);
  std::vector<uint32_t> left(vertices);
  for (uint32_t v = 0; v < vertices; ++v)
    left[v] = v;
  auto live = [&](uint32_t f) { return alive[f] != 0; };
  while (left.size() > 1) { // one vertex into another, a few faces dying each time
    const size_t i = random() % left.size();
    const uint32_t from = left[i];
    left.erase(left.begin() + std::ptrdiff_t(i));
    const uint32_t into = left[random() % left.size()];
    for (int k = 0; k < 2; ++k)
      alive[random() % faces] = 0;
    lists.handOn(from, into, live);
    std::vector<uint32_t> merged;
    for (uint32_t f : model[into])
      if (live(f))
        merged.push_back(f);
    for (uint32_t f : model[from])
      if (live(f))
        merged.push_back(f);
    model[into] = merged, model[from].clear();
    for (uint32_t v = 0; v < vertices; ++v) {
      const auto got = lists[v];
      ASSERT_TRUE(std::equal(got.begin(), got.end(), model[v].begin(), model[v].end()))
          << "vertex " << v << " after " << from << " went into " << into;
    }
  }
}

} // namespace
