#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include <OpenImageIO/imageio.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <gtest/gtest.h>

#include "crowd/bake/evaluate.h"
#include "crowd/bake/import.h"
#include "crowd/bake/lod_bake.h"
#include "crowd/formats/error.h"
#include "gltf_writer.h"
#include "skip.h"

using namespace crowd;
using crowd::test::GltfBuilder;

namespace {

Character load(const GltfBuilder &b, const std::string &name, Reporter *reporter = nullptr,
               bool external = false) {
  std::string dir = test::tempDir("import_" + name);
  Reporter local;
  local.quiet = true;
  return importGltf(b.write(dir, name, external), {}, reporter ? *reporter : local);
}

glm::dvec3 nodePosition(const Character &c, const std::string &name, double t) {
  auto g = nodeGlobals(c, c.clips.empty() ? nullptr : &c.clips[0], t);
  for (size_t i = 0; i < c.nodes.size(); ++i)
    if (c.nodes[i].name == name)
      return glm::dvec3(g[i][3]);
  ADD_FAILURE() << "no node " << name;
  return {};
}

TEST(Import, LinearTranslationInAClipThatStartsLate) {
  GltfBuilder b;
  b.skinnedQuad();
  b.animation("lift", 1, "translation", {1, 3}, {0, 0.5f, 0, 0, 1.5f, 0});
  Character c = load(b, "linear");
  ASSERT_EQ(c.clips.size(), 1u);
  EXPECT_DOUBLE_EQ(c.clips[0].start, 1.0);
  EXPECT_DOUBLE_EQ(c.clips[0].end, 3.0);
  EXPECT_NEAR(nodePosition(c, "b", 2.0).y, 1.0, 1e-12);
  EXPECT_NEAR(nodePosition(c, "b", 0.0).y, 0.5, 1e-12); // before the first key: first value
  EXPECT_NEAR(nodePosition(c, "b", 9.0).y, 1.5, 1e-12); // after the last key: last value
}

TEST(Import, StepHoldsTheEarlierKey) {
  GltfBuilder b;
  b.skinnedQuad();
  b.animation("step", 1, "translation", {0, 1}, {0, 0.5f, 0, 0, 1.5f, 0}, "STEP");
  Character c = load(b, "step");
  EXPECT_NEAR(nodePosition(c, "b", 0.99).y, 0.5, 1e-12);
  EXPECT_NEAR(nodePosition(c, "b", 1.0).y, 1.5, 1e-12);
}

// One target animated twice in one animation, which the specification forbids: readers differ
// (three.js blends the two), so the first channel is kept and the second named in a warning.
TEST(Import, ASecondChannelOnOneTargetIsIgnoredWithAWarning) {
  GltfBuilder b;
  b.skinnedQuad();
  const int anim = b.animation("twice", 1, "translation", {0, 1}, {0, 0.5f, 0, 0, 1.5f, 0});
  b.channel(anim, 1, "translation", {0, 1}, {0, 9, 0, 0, 9, 0});
  b.channel(anim, 1, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, 0, 1}); // another path: kept
  Reporter r;
  r.quiet = true;
  Character c = load(b, "twice", &r);
  ASSERT_EQ(c.clips.size(), 1u);
  EXPECT_EQ(c.clips[0].channels.size(), 2u);
  EXPECT_NEAR(nodePosition(c, "b", 0.5).y, 1.0, 1e-12);
  size_t warned = 0;
  for (const auto &w : r.warnings())
    warned += w.code == "duplicate_channel_targets";
  EXPECT_EQ(warned, 1u);
}

TEST(Import, CubicSplineUsesScaledTangents) {
  GltfBuilder b;
  b.skinnedQuad();
  // Keys: (in, value, out). Value 0 -> 1 over 2 s, out-tangent 2 at key 0, in-tangent 0 at key 1:
  // p(0.5) = 0.5*0 + 0.125*2*2 + 0.5*1 - 0.125*2*0 = 1.0
  b.animation("cubic", 1, "translation", {0, 2},
              {0, 0, 0, 0, 0, 0, 0, 2, 0, /* key 1 */ 0, 0, 0, 0, 1, 0, 0, 0, 0}, "CUBICSPLINE");
  Character c = load(b, "cubic");
  EXPECT_NEAR(nodePosition(c, "b", 1.0).y, 1.0, 1e-12);
  EXPECT_NEAR(nodePosition(c, "b", 2.0).y, 1.0, 1e-12);
}

TEST(Import, RotationsSlerpAlongTheShortArc) {
  GltfBuilder b;
  b.skinnedQuad();
  float s = float(std::sqrt(0.5));
  // Identity to 90 degrees about z, the second key given with flipped sign (same rotation).
  b.animation("turn", 0, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, -s, -s});
  Character c = load(b, "slerp");
  auto g = nodeGlobals(c, &c.clips[0], 0.5);
  glm::dvec3 x = glm::normalize(glm::dvec3(g[0][0]));
  EXPECT_NEAR(std::atan2(x.y, x.x), glm::radians(45.0), 1e-7); // keys are single precision
}

// Quantized rotation keys (gltfpack's 16-bit) are off unit length: slerp between them as they
// are turns the wrong amount (here 54.5 degrees, not 45, for keys 1.5 long); they are normalized.
TEST(Import, RotationKeysOffUnitLengthAreNormalized) {
  GltfBuilder b;
  b.skinnedQuad();
  float s = 1.5f * float(std::sqrt(0.5));
  b.animation("turn", 0, "rotation", {0, 1}, {0, 0, 0, 1.5f, 0, 0, s, s});
  Character c = load(b, "long_keys");
  auto g = nodeGlobals(c, &c.clips[0], 0.5);
  glm::dvec3 x = glm::normalize(glm::dvec3(g[0][0]));
  EXPECT_NEAR(std::atan2(x.y, x.x), glm::radians(45.0), 1e-7);
}

TEST(Import, ChannelsOfDifferentLengthsSpanTheLongest) {
  GltfBuilder b;
  b.skinnedQuad();
  b.animation("two", 1, "translation", {0, 1}, {0, 0.5f, 0, 0, 1, 0});
  int in = b.floats({0, 4}, "SCALAR");
  int out = b.floats({0, 0, 0, 2, 0, 0}, "VEC3");
  b.j["animations"][0]["samplers"].push_back({{"input", in}, {"output", out}});
  b.j["animations"][0]["channels"].push_back(
      {{"sampler", 1}, {"target", {{"node", 0}, {"path", "translation"}}}});
  Character c = load(b, "lengths");
  EXPECT_DOUBLE_EQ(c.clips[0].end, 4.0);
  glm::dvec3 p = nodePosition(c, "b", 2.0);
  EXPECT_NEAR(p.x, 1.0, 1e-12);
  EXPECT_NEAR(p.y, 1.0, 1e-12);
}

TEST(Import, MatrixNodesAndMissingInverseBindMatrices) {
  GltfBuilder b;
  b.skinnedQuad();
  b.j["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 0, 0, 1};
  b.j["skins"][0].erase("inverseBindMatrices");
  Character c = load(b, "matrix");
  auto joints = jointMatrices(c, nullptr, 0);
  EXPECT_EQ(joints[0][3], glm::dvec4(2, 0, 0, 1));
  EXPECT_EQ(joints[1][3], glm::dvec4(2, 0.5, 0, 1)); // identity inverse bind
}

TEST(Import, SkinnedMeshNodeTransformIsIgnored) {
  GltfBuilder b;
  int node = b.skinnedQuad();
  b.j["nodes"][size_t(node)]["translation"] = {10, 0, 0};
  Character c = load(b, "meshnode");
  auto p = posedPositions(c, nullptr, 0);
  EXPECT_NEAR(p[1].x, 1.0, 1e-12); // bind pose: the file's positions, without the +10
}

TEST(Import, FiveInfluencesKeepTheLargestFourAndWarn) {
  GltfBuilder b;
  b.skinnedQuad();
  int j0 = b.accessor(std::vector<uint8_t>{0, 1, 0, 1, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, 5121,
                      "VEC4");
  int w0 =
      b.floats({0.3f, 0.3f, 0.2f, 0.1f, 2, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.25f, 0.75f, 0, 0}, "VEC4");
  int j1 = b.accessor(std::vector<uint8_t>{1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, 5121,
                      "VEC4");
  int w1 = b.floats({0.05f, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC4");
  auto &attrs = b.j["meshes"][0]["primitives"][0]["attributes"];
  attrs["JOINTS_0"] = j0;
  attrs["WEIGHTS_0"] = w0;
  attrs["JOINTS_1"] = j1;
  attrs["WEIGHTS_1"] = w1;
  Reporter r;
  r.quiet = true;
  Character c = load(b, "five", &r);
  std::map<std::string, size_t> counts;
  for (const auto &w : r.warnings())
    counts[w.code] = w.count;
  EXPECT_EQ(counts["more_than_4_influences"], 1u);
  // Vertex 0 (its five sum to 0.95) and vertex 1 (2): a vertex whose influences sum to 1 before
  // the cut is counted under more_than_4_influences only (the 8-influence Blender crawler had 795
  // vertices in both warnings).
  EXPECT_EQ(counts["weights_renormalised"], 2u);
  EXPECT_EQ(counts["normals_computed"], 1u);
  glm::vec4 w = c.mesh.weights[0];
  EXPECT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-6f);
  EXPECT_NEAR(w.w, 0.1f / 0.9f, 1e-6f); // 0.05 dropped, the rest renormalised
  EXPECT_EQ(c.mesh.weights[1], glm::vec4(1, 0, 0, 0));
}

// A vertex no joint weighs (an unpainted button) takes the nearest weighted vertex's influences,
// with a warning, instead of failing the character: vertex 3, moved to (1, 0.9), is nearest vertex
// 1 (1, 0), which only joint "b" weighs.
TEST(Import, AnUnweightedVertexTakesItsNearestWeightedNeighboursInfluences) {
  GltfBuilder b;
  b.skinnedQuad();
  auto &attrs = b.j["meshes"][0]["primitives"][0]["attributes"];
  attrs["POSITION"] = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0.9f, 0}, "VEC3");
  b.j["accessors"][size_t(int(attrs["POSITION"]))]["min"] = {0, 0, 0};
  b.j["accessors"][size_t(int(attrs["POSITION"]))]["max"] = {1, 1, 0};
  attrs["WEIGHTS_0"] = b.floats({1, 0, 0, 0, 0, 1, 0, 0, 0.5f, 0.5f, 0, 0, 0, 0, 0, 0}, "VEC4");
  Reporter r;
  r.quiet = true;
  const Character c = load(b, "unweighted", &r);
  EXPECT_EQ(c.mesh.weights[3], glm::vec4(1, 0, 0, 0));
  EXPECT_EQ(c.jointName(c.mesh.joints[3][0]), "b");
  size_t repaired = 0;
  for (const auto &w : r.warnings())
    if (w.code == "unweighted_vertices")
      repaired = w.count;
  EXPECT_EQ(repaired, 1u);
}

TEST(Import, NormalizedByteWeights) {
  GltfBuilder b;
  b.skinnedQuad();
  int w =
      b.accessor(std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 128, 127, 0, 0, 64, 191, 0, 0},
                 5121, "VEC4", true);
  b.j["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = w;
  Character c = load(b, "u8");
  EXPECT_NEAR(c.mesh.weights[2].x, 128.0f / 255, 1e-6f);
  EXPECT_NEAR(c.mesh.weights[3].x, 191.0f / 255, 1e-6f); // influences sorted, largest first
  EXPECT_EQ(c.mesh.joints[3][0], 0);
}

TEST(Import, MeshRigidlyParentedToAJointBecomesOneInfluenceSkinning) {
  GltfBuilder b;
  b.skinnedQuad();
  nlohmann::json prim = b.j["meshes"][0]["primitives"][0];
  prim["attributes"].erase("JOINTS_0");
  prim["attributes"].erase("WEIGHTS_0");
  b.j["meshes"].push_back({{"name", "prop"}, {"primitives", {prim}}});
  b.j["nodes"].push_back({{"name", "prop"}, {"mesh", 1}, {"translation", {0, 0, 1}}});
  b.j["nodes"][1]["children"] = {3};
  b.animation("lift", 1, "translation", {0, 1}, {0, 0.5f, 0, 0, 1.5f, 0});
  Character c = load(b, "rigid");
  ASSERT_EQ(c.jointCount(), 3u);
  EXPECT_EQ(c.mesh.vertexCount(), 8u);
  auto p = posedPositions(c, &c.clips[0], 1.0);
  EXPECT_NEAR(p[4 + 3].y, 1.0 + 1.5, 1e-12); // vertex (1,1,0) of the prop under b at y = 1.5
  EXPECT_NEAR(p[4 + 3].z, 1.0, 1e-12);
}

TEST(Import, ExternalBufferAndGlbGiveTheSameCharacter) {
  GltfBuilder b;
  b.skinnedQuad();
  Character ext = load(b, "external", nullptr, true);
  std::string dir = test::tempDir("import_glb");
  Reporter r;
  Character glb = importGltf(b.writeGlb(dir, "q"), {}, r);
  EXPECT_EQ(ext.mesh.positions, glb.mesh.positions);
  ASSERT_EQ(ext.sourceFiles.size(), 2u); // provenance hashes the .bin too
  EXPECT_EQ(std::filesystem::path(ext.sourceFiles[1]).filename(), "external.bin");
  EXPECT_EQ(glb.sourceFiles.size(), 1u);
  EXPECT_EQ(ext.mesh.indices, glb.mesh.indices);
}

// A closed cube with no normals (flat-shaded, by the spec) under nodes that mirror it or not:
// glTF winds a mirrored node's triangles clockwise, so the importer turns them round. As drawn at
// rest every face then faces out, as do the normals computed from the file's winding (in the
// node's own frame), outwardSides says every face's outward side is its winding's, and a
// flat-shaded copy (a normal per corner) still welds into 8 vertices.
TEST(Import, AMirroringNodesTrianglesFaceOutAsDrawn) {
  const std::vector<float> corner = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                     -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
  const std::vector<uint16_t> cube = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                      2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};
  const nlohmann::json plain = nlohmann::json::object(), flip = {{"scale", {-1, 1, 1}}},
                       matrix = {{"matrix", {1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}};
  struct Case {
    const char *name;
    nlohmann::json parent, part;
    bool mirrored;
  };
  for (const Case &k : {Case{"plain", plain, plain, false}, Case{"scaled", plain, flip, true},
                        Case{"matrix", plain, matrix, true}, Case{"twice", flip, matrix, false}}) {
    SCOPED_TRACE(k.name);
    GltfBuilder b;
    const int pos = b.floats(corner, "VEC3");
    b.j["accessors"][size_t(pos)]["min"] = {-1, -1, -1};
    b.j["accessors"][size_t(pos)]["max"] = {1, 1, 1};
    const int idx = b.accessor(cube, 5123, "SCALAR");
    const nlohmann::json prim = {{"attributes", {{"POSITION", pos}}}, {"indices", idx}};
    b.j["meshes"] =
        nlohmann::json::array({{{"name", "cube"}, {"primitives", nlohmann::json::array({prim})}}});
    nlohmann::json parent = k.parent, part = k.part;
    parent["name"] = "parent", parent["children"] = {1};
    part["name"] = "part", part["mesh"] = 0, part["translation"] = {3, 0, 0};
    b.j["nodes"] = {parent, part};
    b.j["scenes"][0]["nodes"] = {0};
    Reporter r;
    r.quiet = true;
    const Character c = load(b, std::string("mirror_") + k.name, &r);
    size_t said = 0;
    for (const auto &w : r.warnings())
      said += w.code == "mirrored_winding";
    EXPECT_EQ(said, k.mirrored ? 1u : 0u);
    const std::vector<glm::dvec3> drawn = posedPositions(c, nullptr, 0);
    const auto &m = c.mesh;
    glm::dvec3 centre(0.0);
    for (const auto &p : drawn)
      centre += p / double(drawn.size());
    for (size_t t = 0; t < m.indices.size(); t += 3) {
      const glm::dvec3 a = drawn[m.indices[t]], b1 = drawn[m.indices[t + 1]],
                       c1 = drawn[m.indices[t + 2]];
      EXPECT_GT(glm::dot(glm::cross(b1 - a, c1 - a), (a + b1 + c1) / 3.0 - centre), 0) << t / 3;
    }
    for (size_t v = 0; v < m.vertexCount(); ++v) // the node's frame: centred on 0
      EXPECT_GT(glm::dot(glm::dvec3(m.normals[v]), glm::dvec3(m.positions[v])), 0) << v;
    // In the node's frame, where the normals are stored, a mirrored face's winding disagrees
    // with them; outwardSides (what the outfit and cloth bakes take a face's outward side from)
    // counts that, and has every face of the cube facing out as drawn.
    const std::vector<double> sides = outwardSides(c);
    for (size_t t = 0; t < m.indices.size(); t += 3) {
      const glm::dvec3 a(m.positions[m.indices[t]]), b1(m.positions[m.indices[t + 1]]),
          c1(m.positions[m.indices[t + 2]]);
      const bool disagree =
          glm::dot(glm::cross(b1 - a, c1 - a), glm::dvec3(m.normals[m.indices[t]])) < 0;
      EXPECT_EQ(disagree, k.mirrored) << t / 3;
      EXPECT_EQ(sides[t / 3], 1.0) << t / 3;
    }

    // Flat-shaded: each triangle's corners their own vertices, with the face's normal.
    GltfBuilder f = b;
    std::vector<float> p, n;
    for (size_t t = 0; t < cube.size(); t += 3) {
      glm::vec3 q[3];
      for (int i = 0; i < 3; ++i)
        q[i] = glm::make_vec3(&corner[3 * cube[t + size_t(i)]]);
      const glm::vec3 face = glm::normalize(glm::cross(q[1] - q[0], q[2] - q[0]));
      for (const glm::vec3 &x : q)
        p.insert(p.end(), {x.x, x.y, x.z}), n.insert(n.end(), {face.x, face.y, face.z});
    }
    const int fp = f.floats(p, "VEC3"), fn = f.floats(n, "VEC3");
    f.j["accessors"][size_t(fp)]["min"] = {-1, -1, -1};
    f.j["accessors"][size_t(fp)]["max"] = {1, 1, 1};
    f.j["meshes"][0]["primitives"][0] = {{"attributes", {{"POSITION", fp}, {"NORMAL", fn}}}};
    Character flat = load(f, std::string("mirror_flat_") + k.name);
    weldFlatShading(flat.mesh, r);
    EXPECT_EQ(flat.mesh.vertexCount(), 8u);
  }
}

// Blender's export of a left leg mirrored from the right (tests/data/blender/mirrored.glb: its
// node scaled [-1, -1, -1], with a rotation): as drawn, every face of both legs is wound the way
// its normals point (the left leg's were all wound inward but for its flat boot, whose face normals
// came out inward).
TEST(Import, BlendersMirroredLegIsWoundAsDrawn) {
  Reporter r;
  r.quiet = true;
  const Character c =
      importGltf(std::string(CROWD_SOURCE_DIR) + "/tests/data/blender/mirrored.glb", {}, r);
  const std::vector<glm::dvec3> drawn = posedPositions(c, nullptr, 0);
  const std::vector<glm::dmat4> joints = jointMatrices(c, nullptr, 0);
  const auto &m = c.mesh;
  auto normal = [&](uint32_t v) { // rigid parts: one joint, a rotation and a mirror at most
    return glm::dmat3(joints[m.joints[v][0]]) * glm::dvec3(m.normals[v]);
  };
  size_t against = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const uint32_t *v = &m.indices[t];
    const glm::dvec3 face = glm::cross(drawn[v[1]] - drawn[v[0]], drawn[v[2]] - drawn[v[0]]);
    against += glm::dot(face, normal(v[0]) + normal(v[1]) + normal(v[2])) <= 0;
  }
  EXPECT_EQ(against, 0u) << "of " << m.indices.size() / 3 << " faces";
}

// A quad drawn as a strip or a fan: two triangles covering it, each facing +z as the spec winds
// them (a strip's second triangle turns round). Also as two strips joined into one by degenerate
// triangles, as exporters join them: those draw nothing and are left out.
TEST(Import, StripsAndFansBecomeTriangleListsWoundAsTheSpecDrawsThem) {
  for (const auto &[mode, order] : std::vector<std::pair<int, std::vector<uint16_t>>>{
           {5, {0, 1, 2, 3}}, {6, {0, 1, 3, 2}}, {5, {0, 1, 2, 2, 2, 2, 2, 1, 3}}}) {
    GltfBuilder b;
    b.skinnedQuad();
    auto &prim = b.j["meshes"][0]["primitives"][0];
    prim["indices"] = b.accessor(order, 5123, "SCALAR");
    prim["mode"] = mode;
    const Character c = load(b, "mode" + std::to_string(mode));
    const auto &m = c.mesh;
    ASSERT_EQ(m.indices.size(), 6u) << "mode " << mode;
    float area = 0;
    for (size_t t = 0; t < 6; t += 3) {
      const glm::vec3 a = m.positions[m.indices[t]];
      const glm::vec3 n =
          glm::cross(m.positions[m.indices[t + 1]] - a, m.positions[m.indices[t + 2]] - a);
      EXPECT_GT(n.z, 0.0f) << "mode " << mode << ", triangle " << t / 3;
      area += 0.5f * glm::length(n);
    }
    EXPECT_FLOAT_EQ(area, 1.0f) << "mode " << mode;
  }
}

// Points and lines (an exporter's hair guides, a rig's helper lines) draw no surface: skipped
// with a warning; a mesh of nothing else is a clear error, as is a mode glTF does not define.
TEST(Import, PointsAndLinesAreSkippedWithAWarning) {
  GltfBuilder b;
  b.skinnedQuad();
  auto prims = b.j["meshes"][0]["primitives"];
  nlohmann::json line = prims[0];
  line["indices"] = b.accessor(std::vector<uint16_t>{0, 1, 1, 3}, 5123, "SCALAR");
  line["mode"] = 1;
  nlohmann::json points = prims[0];
  points.erase("indices");
  points["mode"] = 0;
  b.j["meshes"][0]["primitives"] = {line, prims[0], points};
  Reporter r;
  r.quiet = true;
  const Character c = load(b, "lines", &r);
  EXPECT_EQ(c.mesh.indices.size(), 6u);
  size_t skipped = 0;
  for (const auto &w : r.warnings())
    if (w.code == "points_or_lines_skipped")
      skipped = w.count;
  EXPECT_EQ(skipped, 2u);

  const auto failure = [](GltfBuilder g, const std::string &name) {
    try {
      load(g, name);
    } catch (const Error &e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  b.j["meshes"][0]["primitives"] = {line, points};
  EXPECT_NE(failure(b, "only_lines").find("no triangles: its primitives draw points or lines"),
            std::string::npos);
  line["mode"] = 7;
  b.j["meshes"][0]["primitives"] = {line, prims[0]};
  EXPECT_NE(failure(b, "mode7").find("mode 7 is not a glTF primitive mode"), std::string::npos);
}

// Joints are matched by name (an outfit to its body) and clips chosen by name: a name repeated
// (two armatures' default bone names, a clip exported twice) is made unique, the same way every
// time, and said; "b_2" taken already goes on to "b_3".
TEST(Import, RepeatedNodeAndClipNamesAreMadeUnique) {
  GltfBuilder b;
  b.skinnedQuad();
  b.j["nodes"][0]["name"] = "b";
  b.j["nodes"][2]["name"] = "b_2";
  b.animation("walk", 1, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, 0.7071f, 0.7071f});
  b.animation("walk", 1, "rotation", {0, 2}, {0, 0, 0, 1, 0, 0, 0.7071f, 0.7071f});
  Reporter r;
  r.quiet = true;
  const Character c = load(b, "names", &r);
  EXPECT_EQ(c.nodes[0].name, "b");
  EXPECT_EQ(c.nodes[1].name, "b_3");
  EXPECT_EQ(c.nodes[2].name, "b_2");
  ASSERT_EQ(c.clips.size(), 2u);
  EXPECT_EQ(c.clips[0].name, "walk");
  EXPECT_EQ(c.clips[1].name, "walk_2");
  EXPECT_EQ(c.clips[1].end, 2.0);
  std::map<std::string, size_t> counts;
  for (const auto &w : r.warnings())
    counts[w.code] = w.count;
  EXPECT_EQ(counts["duplicate_node_names"], 1u);
  EXPECT_EQ(counts["duplicate_clip_names"], 1u);
}

TEST(Import, MeshByNameAndAClearErrorForAnUnknownOne) {
  GltfBuilder b;
  b.skinnedQuad();
  std::string path = b.write(test::tempDir("import_byname"), "n");
  Reporter r;
  ImportOptions byName;
  byName.mesh = "quad";
  EXPECT_EQ(importGltf(path, byName, r).mesh.vertexCount(), 4u);
  byName.mesh = "nope";
  try {
    importGltf(path, byName, r);
    FAIL();
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("no mesh named 'nope'"), std::string::npos);
  }
}

TEST(Import, SharedAssetsWithOddities) {
  std::string dir = CROWD_SHARED_ASSETS;
  if (!std::filesystem::exists(dir))
    CROWD_SKIP("shared assets absent at " << dir);
  Reporter r;
  r.quiet = true;
  Character q = importGltf(dir + "/quad_skin/quad_skin.glb", {}, r);
  bool more = false;
  for (const auto &w : r.warnings())
    more |= w.code == "more_than_4_influences";
  EXPECT_TRUE(more) << "quad_skin has 10 influences per vertex";
  Reporter m;
  m.quiet = true;
  Character cube = importGltf(dir + "/AnimatedMorphCube/AnimatedMorphCube.glb", {}, m);
  EXPECT_EQ(cube.mesh.morphs.size(), 2u) << "its two morph targets are read, not dropped";
  EXPECT_TRUE(m.warnings().empty());
  Reporter s;
  Character simple = importGltf(dir + "/SimpleSkin/SimpleSkin.gltf", {}, s); // external buffers
  EXPECT_EQ(simple.mesh.vertexCount(), 10u);
}

} // namespace

namespace {
TEST(Import, AnUndecodableTextureIsAWarningNotAFailure) {
  GltfBuilder b;
  b.skinnedQuad();
  int uv = b.floats({0, 0, 1, 0, 0, 1, 1, 1}, "VEC2");
  b.j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
  b.j["meshes"][0]["primitives"][0]["material"] = 0;
  b.j["materials"] = {
      {{"name", "skin"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  b.j["textures"] = {{{"source", 0}}};
  int bogus = b.accessor(std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}, 5121, "SCALAR");
  b.j["images"] = {
      {{"bufferView", b.j["accessors"][size_t(bogus)]["bufferView"]}, {"mimeType", "image/png"}}};
  Reporter r;
  r.quiet = true;
  Character c = load(b, "bogus_texture", &r);
  EXPECT_FALSE(c.diffuse.has_value());
  bool warned = false;
  for (const auto &w : r.warnings())
    warned |= w.code == "diffuse_texture_skipped";
  EXPECT_TRUE(warned);
}

// EXT_texture_webp, as web pipelines write textures: required, the WebP image named by the
// extension, with no PNG fallback in `source`: decoded as the diffuse texture (before, the file
// failed on the required extension).
TEST(Import, AWebpTextureIsTheDiffuseTexture) {
  const std::string file =
      (std::filesystem::temp_directory_path() / "crowd_import_test.webp").string();
  const uint8_t colour[3] = {200, 40, 90};
  {
    std::vector<uint8_t> pixels(8 * 8 * 3);
    for (size_t i = 0; i < pixels.size(); ++i)
      pixels[i] = colour[i % 3];
    auto out = OIIO::ImageOutput::create(file);
    ASSERT_TRUE(out && out->open(file, OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    out->close();
  }
  std::ifstream in(file, std::ios::binary);
  const std::vector<uint8_t> webp((std::istreambuf_iterator<char>(in)), {});
  std::filesystem::remove(file);
  GltfBuilder b;
  b.skinnedQuad();
  b.j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] =
      b.floats({0, 0, 1, 0, 0, 1, 1, 1}, "VEC2");
  b.j["meshes"][0]["primitives"][0]["material"] = 0;
  b.j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  b.j["textures"] = {{{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}}};
  const int bytes = b.accessor(webp, 5121, "SCALAR");
  b.j["images"] = {
      {{"bufferView", b.j["accessors"][size_t(bytes)]["bufferView"]}, {"mimeType", "image/webp"}}};
  b.j["extensionsUsed"] = {"EXT_texture_webp"};
  b.j["extensionsRequired"] = {"EXT_texture_webp"};
  const Character c = load(b, "webp_texture");
  ASSERT_TRUE(c.diffuse.has_value());
  ASSERT_EQ(c.diffuse->width, 8);
  ASSERT_EQ(c.diffuse->height, 8);
  for (size_t p = 0; p < 64; ++p) { // lossy WebP: within a few levels
    for (size_t k = 0; k < 3; ++k)
      EXPECT_NEAR(c.diffuse->rgba[4 * p + k], colour[k], 6) << "pixel " << p << ", channel " << k;
    EXPECT_EQ(c.diffuse->rgba[4 * p + 3], 255);
  }
}

// The base-colour texture's own coordinates: its texCoord set and KHR_texture_transform (offset,
// rotation, scale, as gltfpack writes to dequantize UVs) applied to the UVs the pack stores, which
// were the untransformed TEXCOORD_0 before.
TEST(Import, TheBaseColourTexturesSetAndTransformGiveTheUvs) {
  GltfBuilder b;
  b.skinnedQuad();
  auto &prim = b.j["meshes"][0]["primitives"][0];
  prim["attributes"]["TEXCOORD_0"] = b.floats({9, 9, 9, 9, 9, 9, 9, 9}, "VEC2");
  prim["attributes"]["TEXCOORD_1"] = b.floats({0, 0, 1, 0, 0, 1, 1, 1}, "VEC2");
  prim["material"] = 0;
  const nlohmann::json transform = {
      {"offset", {0.5, 0.25}}, {"rotation", M_PI / 2}, {"scale", {0.5, 0.5}}, {"texCoord", 1}};
  b.j["materials"] = {
      {{"pbrMetallicRoughness",
        {{"baseColorTexture",
          {{"index", 0}, {"extensions", {{"KHR_texture_transform", transform}}}}}}}}};
  b.j["extensionsUsed"] = {"KHR_texture_transform"};
  b.j["extensionsRequired"] = {"KHR_texture_transform"};
  b.j["textures"] = {{{"source", 0}}};
  int bogus = b.accessor(std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}, 5121, "SCALAR");
  b.j["images"] = {
      {{"bufferView", b.j["accessors"][size_t(bogus)]["bufferView"]}, {"mimeType", "image/png"}}};
  const Character c = load(b, "uv_transform");
  ASSERT_EQ(c.mesh.uvs.size(), 4u);
  // Scaled by 0.5, turned a quarter (u, v) -> (v, -u), moved by (0.5, 0.25).
  const glm::vec2 expected[4] = {{0.5f, 0.25f}, {0.5f, -0.25f}, {1.0f, 0.25f}, {1.0f, -0.25f}};
  for (size_t v = 0; v < 4; ++v) {
    EXPECT_NEAR(c.mesh.uvs[v].x, expected[v].x, 1e-6) << "vertex " << v;
    EXPECT_NEAR(c.mesh.uvs[v].y, expected[v].y, 1e-6) << "vertex " << v;
  }
}

// gltfpack's copy of the Blender trooper (tests/data/gltfpack) quantizes its UVs and undoes that
// with a texture transform of scale 16: every textured vertex keeps its UV within the 12-bit
// quantization (1/4096) of the original's at the same rest position (before, they were 16 times
// too small, the whole texture squeezed into one corner).
TEST(Import, AGltfpackCopyKeepsItsTextureCoordinates) {
  const std::string data = std::string(CROWD_SOURCE_DIR) + "/tests/data/";
  Reporter r;
  r.quiet = true;
  const Character original = importGltf(data + "blender/trooper_cm.glb", {}, r);
  const Character packed = importGltf(data + "gltfpack/trooper_cm_packed.glb", {}, r);
  const auto at = posedPositions(original, nullptr, 0),
             packedAt = posedPositions(packed, nullptr, 0);
  ASSERT_FALSE(packed.mesh.uvs.empty());
  size_t checked = 0;
  for (const auto &part : packed.mesh.parts)
    for (uint32_t k = part.firstIndex; part.textured && k < part.firstIndex + part.indexCount;
         ++k) {
      const uint32_t v = packed.mesh.indices[k];
      // The original's vertices within a centimetre (positions are quantized too; corners of
      // seams hold several UVs): the nearest UV among them.
      double nearest = 1e30;
      for (size_t w = 0; w < at.size(); ++w)
        if (glm::distance(at[w], packedAt[v]) < 0.01)
          nearest =
              std::min(nearest, double(glm::distance(original.mesh.uvs[w], packed.mesh.uvs[v])));
      ASSERT_LT(nearest, 1.0 / 2048) << "vertex " << v;
      ++checked;
    }
  EXPECT_GT(checked, 1000u);
}
} // namespace

namespace {
// tinygltf hands an image in a buffer view to its callback without checking the view against the
// buffer (a fuzzed Fox.glb read past the end): a clear error, never a read outside it.
TEST(Import, AnImageViewPastItsBufferIsAClearError) {
  GltfBuilder b;
  b.skinnedQuad();
  int bytes = b.accessor(std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7, 8}, 5121, "SCALAR");
  const auto view = b.j["accessors"][size_t(bytes)]["bufferView"];
  b.j["bufferViews"][size_t(view.get<int>())]["byteLength"] = 1 << 20;
  b.j["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}}};
  try {
    load(b, "image_past_buffer");
    FAIL() << "an image view past its buffer loaded";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("runs past the end of buffer"), std::string::npos)
        << e.what();
  }
}
} // namespace

namespace {
// Every skin a mesh node uses is baked, merged into one skeleton: the quad bound a second time by
// a skin of the same joints and matrices shares them; bound with other inverse bind matrices, its
// joints are entries of their own. Either way it is a second set of vertices (before, the largest
// skin alone was baked and the other meshes were dropped without a word).
TEST(Import, EverySkinAMeshUsesIsBakedIntoOneSkeleton) {
  for (bool sameBinding : {true, false}) {
    SCOPED_TRACE(sameBinding ? "same binding" : "another binding");
    GltfBuilder b;
    b.skinnedQuad();
    nlohmann::json skin1 = b.j["skins"][0];
    if (!sameBinding)
      skin1["inverseBindMatrices"] =
          b.floats({2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0,  0, 1, // twice the size
                    2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, -1, 0, 1},
                   "MAT4");
    b.j["skins"].push_back(skin1);
    b.j["nodes"].push_back({{"name", "quad2"}, {"mesh", 0}, {"skin", 1}});
    b.j["scenes"][0]["nodes"].push_back(b.j["nodes"].size() - 1);
    Reporter r;
    r.quiet = true;
    Character c = load(b, sameBinding ? "two_skins_same" : "two_skins_other", &r);
    EXPECT_EQ(c.jointCount(), sameBinding ? 2u : 4u);
    ASSERT_EQ(c.mesh.vertexCount(), 8u);
    // The second quad's vertices use the first's joints, or joints of their own.
    std::set<uint16_t> first, second;
    for (size_t v = 0; v < 8; ++v)
      for (int k = 0; k < 2; ++k)
        if (c.mesh.weights[v][k] > 0)
          (v < 4 ? first : second).insert(c.mesh.joints[v][size_t(k)]);
    EXPECT_EQ(first == second, sameBinding);
    EXPECT_EQ(first.size(), 2u);
    std::vector<uint16_t> both;
    std::set_intersection(first.begin(), first.end(), second.begin(), second.end(),
                          std::back_inserter(both));
    EXPECT_EQ(both.empty(), !sameBinding);
    // In the rest pose both quads lie where their skins put them: the same place, or twice the
    // size with the second binding.
    const auto rest = posedPositions(c, nullptr, 0);
    EXPECT_NEAR(rest[7].x, sameBinding ? 1.0 : 2.0, 1e-9);
    EXPECT_NEAR(rest[3].x, 1.0, 1e-9);
  }
}

TEST(Import, TheBlenderFileWithTwoArmaturesBakesBoth) {
  Reporter r;
  r.quiet = true;
  const Character c =
      importGltf(std::string(CROWD_SOURCE_DIR) + "/tests/data/blender/two_rigs.glb", {}, r);
  EXPECT_EQ(c.jointCount(), 4u);
  EXPECT_EQ(c.clips.size(), 2u);
  std::set<std::string> bound;
  for (size_t v = 0; v < c.mesh.vertexCount(); ++v)
    bound.insert(c.jointName(c.mesh.joints[v][0]).substr(0, 1));
  EXPECT_EQ(bound, (std::set<std::string>{"a", "b"})) << "both tubes, each on its own rig";
}

// Files a glTF names stay inside its folder (or --asset-root): a buffer one folder up, named
// "../", and the same through a link, are each one error, and the file is never read.
TEST(Import, BuffersOutsideTheAssetFolderAreRefused) {
  GltfBuilder b;
  b.skinnedQuad();
  const std::string dir = test::tempDir("import_outside");
  std::filesystem::create_directories(dir + "/assets");
  const std::string path = b.write(dir + "/assets", "quad", true);
  std::filesystem::rename(dir + "/assets/quad.bin", dir + "/quad.bin");
  auto json = nlohmann::json::parse(std::ifstream(path));
  json["buffers"][0]["uri"] = "../quad.bin";
  std::ofstream(path) << json.dump();
  Reporter r;
  r.quiet = true;
  try {
    importGltf(path, {}, r);
    ADD_FAILURE() << "a buffer outside the asset folder was read";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("'../quad.bin': leaves the asset folder"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::create_symlink("../quad.bin", dir + "/assets/link.bin");
  json["buffers"][0]["uri"] = "link.bin";
  std::ofstream(path) << json.dump();
  try {
    importGltf(path, {}, r);
    ADD_FAILURE() << "a buffer linked from outside the asset folder was read";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("outside the asset folder"), std::string::npos)
        << e.what();
  }
}
} // namespace

namespace {
// A farm's manifest names assets on a shared mount by absolute path: accepted inside the
// --asset-root given, refused outside it (saying so), and refused without one.
TEST(Import, AbsolutePathsResolveOnlyInsideTheAssetRoot) {
  GltfBuilder b;
  b.skinnedQuad();
  const std::string dir = std::filesystem::absolute(test::tempDir("import_absolute")).string();
  std::filesystem::create_directories(dir + "/mount/chars");
  std::filesystem::create_directories(dir + "/elsewhere");
  const std::string path = b.write(dir + "/mount/chars", "quad", true);
  auto json = nlohmann::json::parse(std::ifstream(path));
  json["buffers"][0]["uri"] = dir + "/mount/chars/quad.bin";
  std::ofstream(path) << json.dump();
  Reporter r;
  r.quiet = true;
  ImportOptions inRoot;
  inRoot.input.assetRoot = dir + "/mount";
  EXPECT_EQ(importGltf(path, inRoot, r).mesh.positions.size(), 4u);
  auto message = [&](const ImportOptions &o) -> std::string {
    try {
      importGltf(path, o, r);
    } catch (const Error &e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message({}).find("an absolute path is allowed only inside --asset-root"),
            std::string::npos)
      << message({});
  ImportOptions otherRoot;
  otherRoot.input.assetRoot = dir + "/elsewhere";
  EXPECT_NE(message(otherRoot).find("lies outside --asset-root " + dir + "/elsewhere"),
            std::string::npos)
      << message(otherRoot);
}
} // namespace
