#include "crowd/bake/gltf_export.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "crowd/bake/glb.h"
#include "crowd/bake/provenance.h"
#include "crowd/formats/error.h"
#include "crowd/formats/joint_tracks.h"
#include "crowd/runtime/pack_joints.h"
#include "crowd/runtime/pose.h"
#include "crowd/runtime/region_colour.h"
#include "crowd/runtime/track_pose.h"
#include "crowd/support/images.h"

namespace crowd {

namespace {

using json = nlohmann::json;

constexpr int kFloat = 5126, kUnsignedShort = 5123, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// The GLB's one binary buffer and the JSON describing it.
class Glb {
public:
  json gltf = json::object();

  // A buffer view of `size` bytes (each starts 4-byte aligned, as accessors need).
  int view(const void *data, size_t size, int target = 0) {
    bin_.resize((bin_.size() + 3) / 4 * 4, 0);
    json v = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", size}};
    if (target)
      v["target"] = target;
    const auto *bytes = static_cast<const uint8_t *>(data);
    bin_.insert(bin_.end(), bytes, bytes + size);
    return push("bufferViews", v);
  }
  // An accessor over a new view of `values`, `width` components each ("VEC3" for 3);
  // `bounds`: with its min and max (positions and animation inputs must have them).
  template <class T>
  int accessor(const std::vector<T> &values, int componentType, const char *type, size_t width,
               bool bounds = false, int target = 0) {
    json a = {{"bufferView", view(values.data(), values.size() * sizeof(T), target)},
              {"componentType", componentType},
              {"count", values.size() / width},
              {"type", type}};
    if (bounds) {
      std::vector<T> lo(width, std::numeric_limits<T>::max()),
          hi(width, std::numeric_limits<T>::lowest());
      for (size_t i = 0; i < values.size(); ++i)
        lo[i % width] = std::min(lo[i % width], values[i]),
               hi[i % width] = std::max(hi[i % width], values[i]);
      a["min"] = lo, a["max"] = hi;
    }
    return push("accessors", a);
  }
  int push(const char *array, json value) {
    json &list = gltf[array];
    list.push_back(std::move(value));
    return int(list.size()) - 1;
  }
  std::vector<uint8_t> bytes() {
    bin_.resize((bin_.size() + 3) / 4 * 4, 0);
    gltf["buffers"] = json::array({{{"byteLength", bin_.size()}}});
    return glbBytes(gltf, bin_);
  }

private:
  std::vector<uint8_t> bin_;
};

struct Trs {
  glm::vec3 t{0}, s{1};
  glm::quat r{1, 0, 0, 0};
  bool sheared = false; // the matrix was not T R S: what it holds beyond that is dropped
};

Trs decompose(const glm::mat4 &m) {
  Trs x;
  x.t = glm::vec3(m[3]);
  glm::mat3 axes(m);
  for (int c = 0; c < 3; ++c)
    x.s[c] = glm::length(axes[c]);
  if (glm::determinant(axes) < 0)
    x.s.x = -x.s.x;
  for (int c = 0; c < 3; ++c)
    axes[c] /= x.s[c] != 0 ? x.s[c] : 1.0f;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      x.sheared |= std::abs(glm::dot(axes[a], axes[b])) > 1e-3f;
  x.r = glm::normalize(glm::quat_cast(axes));
  return x;
}

json nodeTrs(const Trs &x) {
  return {{"translation", {x.t.x, x.t.y, x.t.z}},
          {"rotation", {x.r.x, x.r.y, x.r.z, x.r.w}},
          {"scale", {x.s.x, x.s.y, x.s.z}}};
}

// One channel of `node`'s `path` over `input` (an accessor of times) with `values`.
void addChannel(Glb &glb, json &animation, int node, const char *path, int input,
                const std::vector<float> &values, const char *interpolation) {
  const bool rotation = std::string(path) == "rotation";
  const int output = glb.accessor(values, kFloat, rotation ? "VEC4" : "VEC3", rotation ? 4 : 3);
  animation["samplers"].push_back(
      {{"input", input}, {"output", output}, {"interpolation", interpolation}});
  animation["channels"].push_back({{"sampler", animation["samplers"].size() - 1},
                                   {"target", {{"node", node}, {"path", path}}}});
}

// Appends q, on the same hemisphere as the previous rotation appended (the shorter arc between
// keys is then the one every importer interpolates along).
void appendRotation(std::vector<float> &values, glm::quat q) {
  const size_t n = values.size();
  if (n >= 4 &&
      values[n - 4] * q.x + values[n - 3] * q.y + values[n - 2] * q.z + values[n - 1] * q.w < 0)
    q = -q;
  values.insert(values.end(), {q.x, q.y, q.z, q.w});
}

// The skeleton as nodes 0..J-1 (the pack's joints) and each clip from the animation texture:
// every frame's local transforms, from the joint matrices the player reads.
void textureAnimation(Glb &glb, const pack::AnimationPack &p, std::vector<int> &jointNodes,
                      Reporter &reporter) {
  const size_t J = p.skeleton.jointCount();
  std::vector<glm::mat4> bind(J);
  for (size_t j = 0; j < J; ++j)
    bind[j] = glm::inverse(glm::make_mat4(&p.skeleton.inverseBind[16 * j]));
  size_t sheared = 0;
  auto local = [&](const std::vector<glm::mat4> &global, size_t j) {
    const int parent = p.skeleton.parents[j];
    Trs x = decompose(parent < 0 ? global[j] : glm::inverse(global[size_t(parent)]) * global[j]);
    sheared += x.sheared;
    return x;
  };
  for (size_t j = 0; j < J; ++j) {
    json node = nodeTrs(local(bind, j));
    node["name"] = p.skeleton.names[j];
    jointNodes.push_back(glb.push("nodes", node));
  }
  for (size_t j = 0; j < J; ++j)
    if (const int parent = p.skeleton.parents[j]; parent >= 0)
      glb.gltf["nodes"][size_t(parent)]["children"].push_back(j);
  for (size_t c = 0; c < p.clips.size(); ++c) {
    const pack::Clip &clip = p.clips[c];
    std::vector<float> times;
    std::vector<std::vector<float>> t(J), r(J), s(J);
    for (uint32_t f = 0; f < clip.frameCount; ++f) {
      times.push_back(float(f) / clip.fps);
      const auto rows = runtime::sampleJoints(p, c, f, 0);
      std::vector<glm::mat4> global(J);
      for (size_t j = 0; j < J; ++j)
        global[j] = runtime::toMat4(rows[j]) * bind[j];
      for (size_t j = 0; j < J; ++j) {
        const Trs x = local(global, j);
        t[j].insert(t[j].end(), {x.t.x, x.t.y, x.t.z});
        appendRotation(r[j], x.r);
        s[j].insert(s[j].end(), {x.s.x, x.s.y, x.s.z});
      }
    }
    json animation = {
        {"name", clip.name}, {"samplers", json::array()}, {"channels", json::array()}};
    const int input = glb.accessor(times, kFloat, "SCALAR", 1, true);
    for (size_t j = 0; j < J; ++j) {
      addChannel(glb, animation, int(j), "translation", input, t[j], "LINEAR");
      addChannel(glb, animation, int(j), "rotation", input, r[j], "LINEAR");
      addChannel(glb, animation, int(j), "scale", input, s[j], "LINEAR");
    }
    glb.push("animations", animation);
  }
  if (sheared)
    reporter.warn("export_shear", std::to_string(sheared) +
                                      " joint transforms shear: glTF nodes hold translation, "
                                      "rotation and scale only, so the shear is dropped");
}

// The skeleton as the joint tracks' nodes (every ancestor of a joint too), each clip as its
// tracks: their own samples and interpolation, which is how the player decodes them.
void trackAnimation(Glb &glb, const pack::AnimationPack &p, std::vector<int> &jointNodes) {
  const pack::JointTracks &tracks = *p.tracks;
  const pack::TrackSkeleton &sk = tracks.skeleton;
  for (size_t n = 0; n < sk.nodeCount(); ++n) {
    const auto &v = sk.rest[n];
    json node;
    if (sk.restIsMatrix[n]) {
      glm::mat4 m(1);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
          m[c][r] = v[size_t(4 * r + c)];
      node = nodeTrs(decompose(m));
    } else {
      node = {{"rotation", {v[0], v[1], v[2], v[3]}},
              {"translation", {v[4], v[5], v[6]}},
              {"scale", {v[7], v[8], v[9]}}};
    }
    glb.push("nodes", node);
  }
  for (size_t n = 0; n < sk.nodeCount(); ++n)
    if (sk.parents[n] >= 0)
      glb.gltf["nodes"][size_t(sk.parents[n])]["children"].push_back(n);
  for (size_t j = 0; j < sk.jointNodes.size(); ++j) {
    jointNodes.push_back(int(sk.jointNodes[j]));
    glb.gltf["nodes"][sk.jointNodes[j]]["name"] = p.skeleton.names[j];
  }
  const char *paths[pack::kTracksPerNode] = {"rotation", "translation", "scale"};
  for (const pack::TrackClip &clip : tracks.clips) {
    json animation = {
        {"name", clip.name}, {"samplers", json::array()}, {"channels", json::array()}};
    // glTF's key times increase strictly: the second time of a cut moves to the next float.
    std::vector<float> times = clip.times;
    for (size_t k = 1; k < times.size(); ++k)
      times[k] = std::max(times[k], std::nextafter(times[k - 1], INFINITY));
    int input = -1, constantInput = -1;
    for (size_t t = 0; t < clip.tracks.size(); ++t) {
      const pack::Track &track = clip.tracks[t];
      const char *path = paths[t % pack::kTracksPerNode];
      const bool rotation = t % pack::kTracksPerNode == 0;
      std::vector<float> values;
      auto append = [&](const std::array<float, 3> &v) {
        if (rotation)
          // unit, as the player decodes it
          appendRotation(values, runtime::trackRotation(v, track.dropped));
        else
          values.insert(values.end(), v.begin(), v.end());
      };
      if (track.kind == pack::TrackKind::Default)
        continue; // the node's rest value
      if (track.kind == pack::TrackKind::Constant) {
        if (constantInput < 0)
          constantInput = glb.accessor(std::vector<float>{0}, kFloat, "SCALAR", 1, true);
        append(track.min);
        addChannel(glb, animation, int(t / pack::kTracksPerNode), path, constantInput, values,
                   "STEP");
        continue;
      }
      if (input < 0)
        input = glb.accessor(times, kFloat, "SCALAR", 1, true);
      for (uint32_t k = 0; k < times.size(); ++k)
        append(pack::trackSample(clip, track, k));
      addChannel(glb, animation, int(t / pack::kTracksPerNode), path, input, values,
                 track.step ? "STEP" : "LINEAR");
    }
    if (animation["channels"].empty()) { // a clip of rest poses: one key keeps it a clip
      const int only = glb.accessor(std::vector<float>{0}, kFloat, "SCALAR", 1, true);
      const auto &v = sk.rest[sk.jointNodes[0]];
      std::vector<float> rest = sk.restIsMatrix[sk.jointNodes[0]]
                                    ? std::vector<float>{0, 0, 0}
                                    : std::vector<float>{v[4], v[5], v[6]};
      addChannel(glb, animation, int(sk.jointNodes[0]), "translation", only, rest, "STEP");
    }
    glb.push("animations", animation);
  }
}

// The pack's morph targets as glTF targets of the drawn vertices (position and normal offsets;
// a vertex outside a target's range moves 0), or none.
json morphTargets(Glb &glb, const pack::AnimationPack &p, const std::vector<uint32_t> &vertices) {
  json targets = json::array();
  if (!p.morphs)
    return targets;
  for (const pack::Morphs::Target &t : p.morphs->targets) {
    std::vector<float> position(3 * vertices.size(), 0.0f), normal(3 * vertices.size(), 0.0f);
    for (size_t i = 0; i < vertices.size(); ++i)
      if (const uint32_t v = vertices[i]; v >= t.firstVertex && v < t.firstVertex + t.vertexCount) {
        const float *o = &p.morphs->offsets[t.firstOffset + 8 * size_t(v - t.firstVertex)];
        std::copy_n(o, 3, &position[3 * i]);
        std::copy_n(o + 4, 3, &normal[3 * i]);
      }
    targets.push_back({{"POSITION", glb.accessor(position, kFloat, "VEC3", 3, true, kArrayBuffer)},
                       {"NORMAL", glb.accessor(normal, kFloat, "VEC3", 3, false, kArrayBuffer)}});
  }
  return targets;
}

// Each clip's morph weights, a key per frame (the player blends a frame's slots with the next
// frame's, linearly), as a "weights" channel of `node` in the clip's animation.
void morphWeights(Glb &glb, const pack::AnimationPack &p, int node) {
  const pack::Morphs &m = *p.morphs;
  for (size_t c = 0; c < p.clips.size(); ++c) {
    const pack::Clip &clip = p.clips[c];
    std::vector<float> times, weights;
    for (uint32_t f = 0; f < clip.frameCount; ++f) {
      times.push_back(float(f) / clip.fps);
      std::vector<float> frame(m.targets.size(), 0.0f);
      for (uint32_t k = 0; k < pack::kMorphSlots; ++k) {
        const pack::Morphs::Slot &slot =
            m.slots[size_t(clip.firstFrame + f) * pack::kMorphSlots + k];
        if (slot.weight != 0)
          frame[size_t(slot.target)] += slot.weight;
      }
      weights.insert(weights.end(), frame.begin(), frame.end());
    }
    json &animation = glb.gltf["animations"][c];
    const int input = glb.accessor(times, kFloat, "SCALAR", 1, true);
    const int output = glb.accessor(weights, kFloat, "SCALAR", 1);
    animation["samplers"].push_back(
        {{"input", input}, {"output", output}, {"interpolation", "LINEAR"}});
    animation["channels"].push_back({{"sampler", animation["samplers"].size() - 1},
                                     {"target", {{"node", node}, {"path", "weights"}}}});
  }
}

// The drawn vertices' attributes: bind pose, unit normals (a flat-shaded vertex's, stored as
// zero, from its faces), UVs, 4 influences; the JSON "attributes" every primitive shares.
json vertexAttributes(Glb &glb, const pack::AnimationPack &p, const runtime::PoseMesh &drawn) {
  const size_t V = drawn.vertices.size();
  std::vector<glm::vec3> position(V), normal(V);
  std::vector<uint8_t> faceted(V, 0);
  for (size_t i = 0; i < V; ++i) {
    const uint32_t v = drawn.vertices[i];
    position[i] = glm::make_vec3(&p.mesh.positions[3 * v]);
    normal[i] = glm::make_vec3(&p.mesh.normals[3 * v]);
    faceted[i] = normal[i] == glm::vec3(0);
  }
  runtime::faceNormals(position, drawn.indices, faceted, normal);
  std::vector<float> positions, normals, uvs, weights;
  std::vector<uint16_t> joints;
  for (size_t i = 0; i < V; ++i) {
    const uint32_t v = drawn.vertices[i];
    const float length = glm::length(normal[i]);
    const glm::vec3 n =
        length > 0 && std::isfinite(length) ? normal[i] / length : glm::vec3(0, 1, 0);
    positions.insert(positions.end(), {position[i].x, position[i].y, position[i].z});
    normals.insert(normals.end(), {n.x, n.y, n.z});
    if (!p.mesh.uvs.empty())
      uvs.insert(uvs.end(), {p.mesh.uvs[2 * v], p.mesh.uvs[2 * v + 1]});
    const float *ids = &p.skin.texels[size_t(v) * 8], *w = ids + 4;
    const float sum = w[0] + w[1] + w[2] + w[3];
    for (int k = 0; k < 4; ++k) {
      joints.push_back(w[k] > 0 ? uint16_t(ids[k]) : 0); // an unused slot names joint 0
      weights.push_back(sum > 0 ? w[k] / sum : k == 0);
    }
  }
  json attributes = {
      {"POSITION", glb.accessor(positions, kFloat, "VEC3", 3, true, kArrayBuffer)},
      {"NORMAL", glb.accessor(normals, kFloat, "VEC3", 3, false, kArrayBuffer)},
      {"JOINTS_0", glb.accessor(joints, kUnsignedShort, "VEC4", 4, false, kArrayBuffer)},
      {"WEIGHTS_0", glb.accessor(weights, kFloat, "VEC4", 4, false, kArrayBuffer)}};
  if (!uvs.empty())
    attributes["TEXCOORD_0"] = glb.accessor(uvs, kFloat, "VEC2", 2, false, kArrayBuffer);
  return attributes;
}

// The diffuse texture as an embedded PNG, or -1 (none, or no UVs to map it).
int diffuseTexture(Glb &glb, const pack::AnimationPack &p) {
  if (!p.diffuse || p.mesh.uvs.empty())
    return -1;
  const pack::Image image{"diffuse", p.diffuse->width,       p.diffuse->height,
                          4,         pack::Image::Pixel::U8, p.diffuse->rgba};
  const std::vector<uint8_t> png = images::encodePng(image);
  const int view = glb.view(png.data(), png.size());
  glb.push("images", {{"bufferView", view}, {"mimeType", "image/png"}});
  glb.push("samplers", {{"magFilter", 9729}, {"minFilter", 9987}});
  return glb.push("textures", {{"source", 0}, {"sampler", 0}});
}

// A primitive and a material per drawn sub-mesh with triangles at the cut: its base colour (as
// the player starts from it) and the texture where it applies.
json primitives(Glb &glb, const pack::AnimationPack &p, const runtime::PoseMesh &drawn,
                const json &attributes, const json &targets, int texture) {
  json out = json::array();
  for (size_t k = 0; k < drawn.subMeshes.size(); ++k) {
    const uint32_t s = drawn.subMeshes[k], from = drawn.subMeshStarts[k],
                   to = drawn.subMeshStarts[k + 1];
    if (from == to)
      continue; // nothing of it left at this cut
    const std::vector<uint32_t> indices(drawn.indices.begin() + from, drawn.indices.begin() + to);
    const auto colour = runtime::regionColour(p, s, {});
    json pbr = {{"baseColorFactor", {colour[0], colour[1], colour[2], 1.0f}},
                {"metallicFactor", 0.0f},
                {"roughnessFactor", 1.0f}};
    if (texture >= 0 && colour[3] > 0.5f)
      pbr["baseColorTexture"] = {{"index", texture}};
    const int material =
        glb.push("materials", {{"name", p.mesh.subMeshes[s].name}, {"pbrMetallicRoughness", pbr}});
    out.push_back(
        {{"attributes", attributes},
         {"indices", glb.accessor(indices, kUnsignedInt, "SCALAR", 1, false, kElementArrayBuffer)},
         {"material", material}});
    if (!targets.empty())
      out.back()["targets"] = targets;
  }
  return out;
}

// The scene's root nodes: the skeleton's roots (under one common root where there are several,
// as a skin's joints need) and the mesh node.
json sceneRoots(Glb &glb, int meshNode) {
  const size_t skeletonNodes = size_t(meshNode);
  std::vector<uint8_t> child(skeletonNodes, 0);
  for (size_t n = 0; n < skeletonNodes; ++n)
    if (glb.gltf["nodes"][n].contains("children"))
      for (const auto &c : glb.gltf["nodes"][n]["children"])
        child[c.get<size_t>()] = 1;
  json roots = json::array();
  for (size_t n = 0; n < skeletonNodes; ++n)
    if (!child[n])
      roots.push_back(n);
  if (roots.size() > 1)
    roots = json::array({glb.push("nodes", {{"name", "skeleton"}, {"children", roots}})});
  roots.push_back(meshNode);
  return roots;
}

} // namespace

std::vector<uint8_t> exportGltf(const pack::AnimationPack &p, const GltfExportOptions &o,
                                Reporter &reporter) {
  runtime::PoseOptions po;
  po.outfit = o.outfit;
  po.lodVertices = o.lodVertices;
  const runtime::PoseMesh drawn = runtime::poseMesh(p, po);
  if (drawn.indices.empty())
    throw Error("export: the outfit draws no triangle at this cut");

  Glb glb;
  glb.gltf["asset"] = {{"version", "2.0"}, {"generator", kBakerVersion}};
  std::vector<int> jointNodes; // the skeleton's nodes come first, the animations with them
  if (p.hasTexture())
    textureAnimation(glb, p, jointNodes, reporter);
  else
    trackAnimation(glb, p, jointNodes);
  const json attributes = vertexAttributes(glb, p, drawn);
  const int texture = diffuseTexture(glb, p);
  const json targets = morphTargets(glb, p, drawn.vertices);
  json mesh = {{"name", drawn.outfit.empty() ? "character" : drawn.outfit},
               {"primitives", primitives(glb, p, drawn, attributes, targets, texture)}};
  if (!targets.empty()) {
    mesh["weights"] = std::vector<float>(targets.size(), 0.0f);
    json names = json::array();
    for (const auto &t : p.morphs->targets)
      names.push_back(t.name);
    mesh["extras"] = {{"targetNames", names}};
  }
  const std::vector<float> inverseBind(p.skeleton.inverseBind.begin(),
                                       p.skeleton.inverseBind.end());
  const int skin =
      glb.push("skins", {{"joints", jointNodes},
                         {"inverseBindMatrices", glb.accessor(inverseBind, kFloat, "MAT4", 16)}});
  const int meshNode =
      glb.push("nodes", {{"name", "mesh"}, {"mesh", glb.push("meshes", mesh)}, {"skin", skin}});
  if (!targets.empty())
    morphWeights(glb, p, meshNode);
  glb.gltf["scene"] = 0;
  glb.gltf["scenes"] = json::array({{{"nodes", sceneRoots(glb, meshNode)}}});
  return glb.bytes();
}

} // namespace crowd
