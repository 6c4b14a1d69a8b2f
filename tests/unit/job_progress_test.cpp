// A job's progress: the lines a bake says as its long steps start reach the listener its
// context names (crowdbake's commands print them on a terminal), and listening changes nothing.
#include <memory>

#include <gtest/gtest.h>

#include "crowd/bake/import.h"
#include "crowd/bake/job.h"

using namespace crowd;

namespace {

TEST(JobProgress, AMeshJobSaysEachStepInOrderAndBakesTheSame) {
  auto m = std::make_shared<CharacterManifest>();
  m->name = "trooper";
  m->body = std::string(CROWD_SOURCE_DIR) + "/tests/data/blender/trooper_cm.glb";
  Job mesh;
  for (Job &j : planCharacter(m, 0))
    if (j.kind == "mesh")
      mesh = std::move(j);
  ASSERT_EQ(mesh.kind, "mesh");

  std::vector<std::string> lines;
  const Part heard = runJob(mesh, {}, {1, [&](const std::string &line) { lines.push_back(line); }});
  const Part silent = runJob(mesh, {}, {1, nullptr});

  Reporter quiet;
  quiet.quiet = true;
  const Character c = importGltf(m->body, {}, quiet);
  ASSERT_GE(c.clips.size(), 2u);
  std::vector<std::string> expected = {"LOD: collapse order of " +
                                       std::to_string(c.mesh.indices.size() / 3) + " triangles"};
  for (size_t k = 0; k < c.clips.size(); ++k) // the default store (auto): the tracks first
    expected.push_back("joint tracks: clip " + std::to_string(k + 1) + " of " +
                       std::to_string(c.clips.size()) + " (" + c.clips[k].name + ")");
  const size_t store = expected.size(); // they take fewer bytes than any texture: none searched
  expected.push_back("stores tracks: the tracks meet the budget in ");
  expected.push_back("crossfades between " + std::to_string(c.clips.size()) + " clips");
  ASSERT_EQ(lines.size(), expected.size());
  for (size_t k = 0; k < expected.size(); ++k)
    if (k == store) // followed by figures
      EXPECT_EQ(lines[k].rfind(expected[k], 0), 0u) << lines[k];
    else
      EXPECT_EQ(lines[k], expected[k]);

  ASSERT_EQ(heard.chunks.size(), silent.chunks.size());
  for (size_t k = 0; k < heard.chunks.size(); ++k)
    EXPECT_EQ(heard.chunks[k].payload, silent.chunks[k].payload) << "chunk " << k;
}

} // namespace
