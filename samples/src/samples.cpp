#include "crowd/samples/samples.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <tiny_gltf.h>

#include "crowd/formats/container.h"
#include "crowd/formats/error.h"
#include "crowd/support/images.h"
#include "rig.h"
#include "village.h"

namespace crowd::samples {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct JointDef {
  const char *name;
  int parent;
  glm::vec3 head; // bind-pose position, model space (metres, Y up, facing +Z)
};

// Arms hang at the sides so that walk swings are rotations about X.
const JointDef kJoints[] = {
    {"root", -1, {0, 0, 0}},
    {"hips", 0, {0, 0.95f, 0}},
    {"spine", 1, {0, 1.07f, 0}},
    {"chest", 2, {0, 1.25f, 0}},
    {"neck", 3, {0, 1.45f, 0}},
    {"head", 4, {0, 1.55f, 0}},
    {"shoulder_l", 3, {0.10f, 1.40f, 0}},
    {"upperarm_l", 6, {0.235f, 1.40f, 0}},
    {"forearm_l", 7, {0.235f, 1.12f, 0}},
    {"hand_l", 8, {0.235f, 0.86f, 0}},
    {"shoulder_r", 3, {-0.10f, 1.40f, 0}},
    {"upperarm_r", 10, {-0.235f, 1.40f, 0}},
    {"forearm_r", 11, {-0.235f, 1.12f, 0}},
    {"hand_r", 12, {-0.235f, 0.86f, 0}},
    {"thigh_l", 1, {0.095f, 0.92f, 0}},
    {"shin_l", 14, {0.095f, 0.50f, 0}},
    {"foot_l", 15, {0.095f, 0.09f, 0}},
    {"toe_l", 16, {0.095f, 0.03f, 0.12f}},
    {"thigh_r", 1, {-0.095f, 0.92f, 0}},
    {"shin_r", 18, {-0.095f, 0.50f, 0}},
    {"foot_r", 19, {-0.095f, 0.09f, 0}},
    {"toe_r", 20, {-0.095f, 0.03f, 0.12f}},
};
constexpr int kJointCount = int(sizeof(kJoints) / sizeof(kJoints[0]));
enum J {
  Root,
  Hips,
  Spine,
  Chest,
  Neck,
  Head,
  ShL,
  UaL,
  FaL,
  HaL,
  ShR,
  UaR,
  FaR,
  HaR,
  ThL,
  ShinL,
  FtL,
  ToL,
  ThR,
  ShinR,
  FtR,
  ToR
};

struct Vertex {
  glm::vec3 p, n;
  glm::vec2 uv;
  glm::u16vec4 j{0};
  glm::vec4 w{0};
};

struct Part {
  std::string material;
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
};

// Skinning along a part: joints[i] owns s in [bounds[i-1], bounds[i]); weights blend linearly
// over +-blend around each boundary.
struct Bones {
  std::vector<int> joints;
  std::vector<float> bounds;
  float blend = 0.06f;
  void weigh(float s, Vertex &v) const {
    size_t seg = 0;
    while (seg < bounds.size() && s >= bounds[seg])
      ++seg;
    v.j = glm::u16vec4(uint16_t(joints[seg]), 0, 0, 0);
    v.w = glm::vec4(1, 0, 0, 0);
    for (size_t b = 0; b < bounds.size(); ++b) {
      float d = s - bounds[b];
      if (std::abs(d) < blend) {
        float t = (d + blend) / (2 * blend);
        v.j = glm::u16vec4(uint16_t(joints[b]), uint16_t(joints[b + 1]), 0, 0);
        v.w = glm::vec4(1 - t, t, 0, 0);
      }
    }
  }
};

// A tube along a straight axis from `a` to `b` with an elliptic section of radii
// radius(s) = (rx, rz) in the (side, front) directions; closed by a cap fan at each end for body
// parts, open for garments. UVs wrap around (a seam where u goes from 1 back to 0) into the
// atlas cell `cell`.
void addTube(Part &part, glm::vec3 a, glm::vec3 b, glm::vec3 side, int rings, int segments,
             const std::function<glm::vec2(float)> &radius, const Bones &bones, glm::vec4 cell,
             bool caps = true) {
  glm::vec3 axis = glm::normalize(b - a);
  glm::vec3 front = glm::normalize(glm::cross(side, axis));
  side = glm::normalize(glm::cross(axis, front));
  uint32_t base = uint32_t(part.vertices.size());
  for (int r = 0; r < rings; ++r) {
    float s = float(r) / float(rings - 1);
    glm::vec2 rad = radius(s);
    glm::vec3 c = a + (b - a) * s;
    for (int k = 0; k <= segments; ++k) {
      float ang = float(2 * kPi * k / segments);
      glm::vec3 dir = std::cos(ang) * side * rad.x + std::sin(ang) * front * rad.y;
      Vertex v;
      v.p = c + dir;
      glm::vec3 nrm = std::cos(ang) * side / std::max(rad.x, 1e-4f) +
                      std::sin(ang) * front / std::max(rad.y, 1e-4f);
      v.n = glm::normalize(nrm);
      v.uv = glm::vec2(cell.x + cell.z * float(k) / float(segments), cell.y + cell.w * s);
      bones.weigh(s, v);
      part.vertices.push_back(v);
    }
  }
  int row = segments + 1;
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      uint32_t i0 = base + uint32_t(r * row + k), i1 = i0 + 1, i2 = i0 + uint32_t(row), i3 = i2 + 1;
      part.indices.insert(part.indices.end(), {i0, i2, i1, i1, i2, i3});
    }
  // Caps: a centre vertex with its own normal; shares no vertex with the wall (a normal seam).
  for (int end = 0; end < 2 && caps; ++end) {
    float s = float(end);
    glm::vec2 rad = radius(s);
    if (rad.x < 1e-4f)
      continue;
    glm::vec3 c = end ? b : a, n = end ? axis : -axis;
    uint32_t centre = uint32_t(part.vertices.size());
    Vertex cv;
    cv.p = c;
    cv.n = n;
    cv.uv = glm::vec2(cell.x + cell.z * 0.5f, cell.y + cell.w * s);
    bones.weigh(s, cv);
    part.vertices.push_back(cv);
    for (int k = 0; k <= segments; ++k) {
      Vertex v = part.vertices[base + uint32_t((end ? rings - 1 : 0) * row + k)];
      v.n = n;
      part.vertices.push_back(v);
    }
    for (int k = 0; k < segments; ++k) {
      uint32_t p0 = centre + 1 + uint32_t(k), p1 = p0 + 1;
      if (end)
        part.indices.insert(part.indices.end(), {centre, p0, p1});
      else
        part.indices.insert(part.indices.end(), {centre, p1, p0});
    }
  }
}

glm::vec3 jp(int j) { return kJoints[j].head; }

// Atlas cells (u0, v0, du, dv) of the diffuse texture, one per body region.
const glm::vec4 kCells[6] = {{0, 0, 0.5f, 0.33f},     {0.5f, 0, 0.5f, 0.33f},
                             {0, 0.33f, 0.5f, 0.33f}, {0.5f, 0.33f, 0.5f, 0.33f},
                             {0, 0.66f, 0.5f, 0.34f}, {0.5f, 0.66f, 0.5f, 0.34f}};
const glm::vec3 kX(1, 0, 0);

// Torso section at height y: the body's, and the base every top garment is inflated from.
constexpr float kTorsoBottom = 0.86f, kTorsoTop = 1.45f;
glm::vec2 torsoRadius(float y, float inflate = 0) {
  float s = (y - kTorsoBottom) / (kTorsoTop - kTorsoBottom);
  float r = 0.15f + 0.02f * std::sin(float(kPi) * s) - (s > 0.85f ? (s - 0.85f) * 0.5f : 0);
  return glm::vec2(r + inflate, r * 0.65f + inflate);
}

std::vector<Part> humanoidParts() {
  std::vector<Part> parts(6);
  parts[0].material = "head";
  addTube(
      parts[0], {0, 1.43f, 0}, {0, 1.78f, 0}, kX, 18, 28,
      [](float s) {
        float r = s < 0.25f ? 0.055f : 0.055f + 0.055f * std::sin(float(kPi) * (s - 0.25f) / 0.75f);
        if (s > 0.98f)
          r = 0.0f;
        return glm::vec2(r, r * 1.1f);
      },
      {{Neck, Head}, {0.3f}}, kCells[0]);
  parts[1].material = "torso";
  addTube(
      parts[1], {0, kTorsoBottom, 0}, {0, kTorsoTop, 0}, kX, 24, 32,
      [](float s) { return torsoRadius(kTorsoBottom + s * (kTorsoTop - kTorsoBottom)); },
      {{Hips, Spine, Chest, Neck}, {0.22f, 0.62f, 0.95f}}, kCells[1]);
  parts[2].material = "arms";
  parts[3].material = "hands";
  parts[4].material = "legs";
  parts[5].material = "feet";
  for (int side = 0; side < 2; ++side) {
    int ua = side ? UaR : UaL, fa = side ? FaR : FaL, ha = side ? HaR : HaL;
    int th = side ? ThR : ThL, sh = side ? ShinR : ShinL, ft = side ? FtR : FtL,
        to = side ? ToR : ToL;
    glm::vec3 top = jp(ua) + glm::vec3(0, 0.04f, 0);
    addTube(
        parts[2], top, jp(ha), kX, 20, 16, [](float s) { return glm::vec2(0.045f - 0.012f * s); },
        {{ua, fa}, {0.5f}}, kCells[2]);
    addTube(
        parts[3], jp(ha), jp(ha) - glm::vec3(0, 0.15f, 0), kX, 8, 12,
        [](float s) { return glm::vec2(0.035f * (1 - 0.5f * s * s), 0.02f); }, {{ha}, {}},
        kCells[3]);
    addTube(
        parts[4], jp(th) + glm::vec3(0, 0.02f, 0), jp(ft), kX, 26, 18,
        [](float s) { return glm::vec2(0.075f - 0.035f * s); }, {{th, sh}, {0.5f}}, kCells[4]);
    glm::vec3 heel = jp(ft) + glm::vec3(0, -0.05f, -0.06f);
    addTube(
        parts[5], heel, jp(to) + glm::vec3(0, -0.01f, 0.06f), kX, 10, 14,
        [](float s) { return glm::vec2(0.045f, 0.035f * (1 - 0.3f * s)); }, {{ft, to}, {0.6f}},
        kCells[5]);
  }
  return parts;
}

// Garments: inflated tubes over the body, skinned with the same bones.
std::vector<Part> outfitParts(int kind) {
  std::vector<Part> parts;
  // An open garment tube around the torso from height y0 to y1.
  auto top = [](Part &p, float y0, float y1, float inflate, const Bones &bones) {
    addTube(
        p, {0, y0, 0}, {0, y1, 0}, kX, 16, 32,
        [=](float s) { return torsoRadius(y0 + s * (y1 - y0), inflate); }, bones, kCells[1], false);
  };
  auto skirt = [&](Part &p, float bottom, float flare) {
    addTube(
        p, {0, 0.98f, 0}, {0, bottom, 0}, kX, 14, 36,
        [=](float s) { return glm::vec2(0.175f + flare * s, 0.125f + flare * s); }, {{Hips}, {}},
        kCells[4], false);
  };
  auto sleeves = [&](Part &p, float length) {
    for (int side = 0; side < 2; ++side) {
      int ua = side ? UaR : UaL, fa = side ? FaR : FaL, ha = side ? HaR : HaL;
      glm::vec3 top = jp(ua) + glm::vec3(0, 0.05f, 0);
      glm::vec3 end = top + (jp(ha) - top) * length;
      addTube(
          p, top, end, kX, 12, 16, [](float) { return glm::vec2(0.06f); },
          {{ua, fa}, {0.5f / length}}, kCells[2], false);
    }
  };
  if (kind == 0) { // dress: bodice and a long flared skirt
    parts.resize(1);
    parts[0].material = "dress";
    top(parts[0], 0.95f, 1.40f, 0.02f, {{Hips, Spine, Chest}, {0.2f, 0.55f}});
    skirt(parts[0], 0.40f, 0.16f);
  } else if (kind == 1) { // jumper with a skirt
    parts.resize(2);
    parts[0].material = "jumper";
    top(parts[0], 0.90f, 1.41f, 0.025f, {{Hips, Spine, Chest}, {0.2f, 0.6f}});
    sleeves(parts[0], 0.95f);
    parts[1].material = "skirt";
    skirt(parts[1], 0.62f, 0.08f);
  } else { // shirt with trousers
    parts.resize(2);
    parts[0].material = "shirt";
    top(parts[0], 0.92f, 1.41f, 0.02f, {{Hips, Spine, Chest}, {0.2f, 0.6f}});
    sleeves(parts[0], 0.4f);
    parts[1].material = "trousers";
    addTube(
        parts[1], {0, 0.86f, 0}, {0, 1.0f, 0}, kX, 6, 32,
        [](float) { return glm::vec2(0.185f, 0.125f); }, {{Hips}, {}}, kCells[4], false);
    for (int side = 0; side < 2; ++side) {
      int th = side ? ThR : ThL, sh = side ? ShinR : ShinL;
      addTube(
          parts[1], jp(th) + glm::vec3(0, 0.04f, 0), jp(side ? FtR : FtL) + glm::vec3(0, 0.05f, 0),
          kX, 22, 18, [](float s) { return glm::vec2(0.095f - 0.035f * s); }, {{th, sh}, {0.5f}},
          kCells[4], false);
    }
  }
  return parts;
}

// --- animation ---------------------------------------------------------------------------

struct Pose {
  glm::quat rot[kJointCount];
  glm::vec3 hips;
};

glm::quat rx(float deg) { return glm::angleAxis(glm::radians(deg), glm::vec3(1, 0, 0)); }
glm::quat ry(float deg) { return glm::angleAxis(glm::radians(deg), glm::vec3(0, 1, 0)); }
glm::quat rz(float deg) { return glm::angleAxis(glm::radians(deg), glm::vec3(0, 0, 1)); }

// phase in [0, 1): one gait cycle. amp 1 = walk, larger = run.
Pose gait(float phase, float amp, float lean) {
  Pose p;
  for (auto &q : p.rot)
    q = glm::quat(1, 0, 0, 0);
  float s = std::sin(float(2 * kPi) * phase), c = std::cos(float(2 * kPi) * phase);
  p.rot[ThL] = rx(-25 * amp * s);
  p.rot[ThR] = rx(25 * amp * s);
  p.rot[ShinL] = rx(30 * amp * std::max(0.0f, c));
  p.rot[ShinR] = rx(30 * amp * std::max(0.0f, -c));
  p.rot[UaL] = rx(20 * amp * s) * rz(3);
  p.rot[UaR] = rx(-20 * amp * s) * rz(-3);
  p.rot[FaL] = rx(-15 * amp);
  p.rot[FaR] = rx(-15 * amp);
  p.rot[Spine] = ry(5 * amp * s) * rx(lean);
  p.rot[FtL] = rx(10 * amp * s);
  p.rot[FtR] = rx(-10 * amp * s);
  p.hips = jp(Hips) + glm::vec3(0, 0.02f * amp * std::cos(float(4 * kPi) * phase) - 0.02f * amp, 0);
  return p;
}

Pose idle(float phase) {
  Pose p;
  for (auto &q : p.rot)
    q = glm::quat(1, 0, 0, 0);
  float s = std::sin(float(2 * kPi) * phase);
  p.rot[Chest] = rx(2 * s);
  p.rot[Head] = ry(12 * s);
  p.rot[UaL] = rz(2 + 2 * s);
  p.rot[UaR] = rz(-2 - 2 * s);
  p.hips = jp(Hips) + glm::vec3(0, 0.004f * s, 0);
  return p;
}

struct ClipDef {
  std::string name;
  float period;
  int keys;
  std::function<Pose(float)> pose;
};

// --- glTF assembly -------------------------------------------------------------------------

class Builder {
public:
  tinygltf::Model m;

  Builder() {
    m.asset.version = "2.0";
    m.asset.generator = "crowdbake samples";
    m.buffers.emplace_back();
  }

  int view(const void *data, size_t bytes, int target) {
    auto &buf = m.buffers[0].data;
    while (buf.size() % 4)
      buf.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = buf.size();
    v.byteLength = bytes;
    v.target = target;
    buf.insert(buf.end(), static_cast<const uint8_t *>(data),
               static_cast<const uint8_t *>(data) + bytes);
    m.bufferViews.push_back(v);
    return int(m.bufferViews.size() - 1);
  }

  template <class T>
  int accessor(const std::vector<T> &values, int componentType, int type, int comps, int target,
               bool minMax, bool normalized = false) {
    tinygltf::Accessor a;
    a.bufferView = view(values.data(), values.size() * sizeof(T), target);
    a.componentType = componentType;
    a.type = type;
    a.count = values.size() / size_t(comps);
    a.normalized = normalized;
    if (minMax) {
      a.minValues.assign(size_t(comps), INFINITY);
      a.maxValues.assign(size_t(comps), -INFINITY);
      for (size_t i = 0; i < values.size(); ++i) {
        double v = double(values[i]);
        a.minValues[i % size_t(comps)] = std::min(a.minValues[i % size_t(comps)], v);
        a.maxValues[i % size_t(comps)] = std::max(a.maxValues[i % size_t(comps)], v);
      }
    }
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
  }

  void skeleton() {
    for (int j = 0; j < kJointCount; ++j) {
      tinygltf::Node n;
      n.name = kJoints[j].name;
      glm::vec3 local = kJoints[j].head -
                        (kJoints[j].parent >= 0 ? kJoints[kJoints[j].parent].head : glm::vec3(0));
      if (glm::length(local) > 0)
        n.translation = {local.x, local.y, local.z};
      m.nodes.push_back(n);
    }
    for (int j = 1; j < kJointCount; ++j)
      m.nodes[size_t(kJoints[j].parent)].children.push_back(j);
    tinygltf::Skin skin;
    skin.name = "humanoid";
    skin.skeleton = Root;
    std::vector<float> ibm;
    for (int j = 0; j < kJointCount; ++j) {
      skin.joints.push_back(j);
      glm::vec3 h = kJoints[j].head;
      float mtx[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -h.x, -h.y, -h.z, 1};
      ibm.insert(ibm.end(), mtx, mtx + 16);
    }
    skin.inverseBindMatrices =
        accessor(ibm, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4, 16, 0, false);
    m.skins.push_back(skin);
  }

  void material(const std::string &name, glm::vec4 colour, int texture) {
    tinygltf::Material mat;
    mat.name = name;
    mat.pbrMetallicRoughness.baseColorFactor = {colour.r, colour.g, colour.b, colour.a};
    mat.pbrMetallicRoughness.metallicFactor = 0;
    mat.pbrMetallicRoughness.roughnessFactor = 0.8;
    mat.pbrMetallicRoughness.baseColorTexture.index = texture;
    m.materials.push_back(mat);
  }

  void mesh(const std::string &name, const std::vector<Part> &parts, int firstMaterial) {
    tinygltf::Mesh mesh;
    mesh.name = name;
    for (size_t pi = 0; pi < parts.size(); ++pi) {
      const Part &part = parts[pi];
      std::vector<float> pos, nrm, uv, w;
      std::vector<uint16_t> jnt;
      for (const auto &v : part.vertices) {
        pos.insert(pos.end(), {v.p.x, v.p.y, v.p.z});
        nrm.insert(nrm.end(), {v.n.x, v.n.y, v.n.z});
        uv.insert(uv.end(), {v.uv.x, v.uv.y});
        jnt.insert(jnt.end(), {v.j.x, v.j.y, v.j.z, v.j.w});
        w.insert(w.end(), {v.w.x, v.w.y, v.w.z, v.w.w});
      }
      tinygltf::Primitive prim;
      prim.mode = TINYGLTF_MODE_TRIANGLES;
      prim.material = firstMaterial + int(pi);
      const int ab = TINYGLTF_TARGET_ARRAY_BUFFER;
      prim.attributes["POSITION"] =
          accessor(pos, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3, ab, true);
      prim.attributes["NORMAL"] =
          accessor(nrm, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3, ab, false);
      prim.attributes["TEXCOORD_0"] =
          accessor(uv, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 2, ab, false);
      prim.attributes["JOINTS_0"] =
          accessor(jnt, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, 4, ab, false);
      prim.attributes["WEIGHTS_0"] =
          accessor(w, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 4, ab, false);
      prim.indices = accessor(part.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                              TINYGLTF_TYPE_SCALAR, 1, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
      mesh.primitives.push_back(prim);
    }
    m.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = name;
    node.mesh = int(m.meshes.size() - 1);
    node.skin = 0;
    m.nodes.push_back(node);
  }

  void animation(const ClipDef &clip) {
    tinygltf::Animation anim;
    anim.name = clip.name;
    std::vector<float> times;
    std::vector<Pose> poses;
    for (int k = 0; k <= clip.keys; ++k) {
      times.push_back(clip.period * float(k) / float(clip.keys));
      poses.push_back(clip.pose(float(k % clip.keys) / float(clip.keys)));
    }
    int input = accessor(times, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, 1, 0, true);
    auto channel = [&](int node, const std::string &path, int output) {
      tinygltf::AnimationSampler s;
      s.input = input;
      s.output = output;
      s.interpolation = "LINEAR";
      anim.samplers.push_back(s);
      tinygltf::AnimationChannel ch;
      ch.sampler = int(anim.samplers.size() - 1);
      ch.target_node = node;
      ch.target_path = path;
      anim.channels.push_back(ch);
    };
    for (int j = 0; j < kJointCount; ++j) {
      bool moves = false;
      std::vector<float> q;
      for (const auto &p : poses) {
        q.insert(q.end(), {p.rot[j].x, p.rot[j].y, p.rot[j].z, p.rot[j].w});
        moves = moves || p.rot[j] != glm::quat(1, 0, 0, 0);
      }
      if (moves)
        channel(j, "rotation",
                accessor(q, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, 4, 0, false));
    }
    std::vector<float> t;
    for (const auto &p : poses)
      t.insert(t.end(), {p.hips.x, p.hips.y, p.hips.z});
    channel(Hips, "translation",
            accessor(t, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3, 0, false));
    m.animations.push_back(anim);
  }

  // A 256x256 diffuse texture: one colour per atlas cell with stripes, so seams show.
  int texture() {
    const int size = 256;
    pack::Image texture{"diffuse", size, size, 3, pack::Image::Pixel::U8, {}};
    std::vector<uint8_t> &px = texture.bytes;
    px.resize(size_t(size * size * 3));
    const glm::vec3 cellColour[6] = {{0.93f, 0.76f, 0.62f}, {0.85f, 0.68f, 0.55f},
                                     {0.90f, 0.72f, 0.58f}, {0.95f, 0.80f, 0.66f},
                                     {0.80f, 0.64f, 0.52f}, {0.35f, 0.25f, 0.20f}};
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        float u = (float(x) + 0.5f) / size, v = (float(y) + 0.5f) / size;
        int cell = (v < 0.33f ? 0 : v < 0.66f ? 2 : 4) + (u < 0.5f ? 0 : 1);
        float stripe = ((x / 8 + y / 8) % 2) ? 1.0f : 0.92f;
        for (int k = 0; k < 3; ++k)
          px[size_t((y * size + x) * 3 + k)] = (unsigned char)(255 * cellColour[cell][k] * stripe);
      }
    const std::vector<uint8_t> png = images::encodePng(texture);
    tinygltf::Image image;
    image.name = "diffuse";
    image.mimeType = "image/png";
    image.bufferView = view(png.data(), png.size(), 0);
    m.images.push_back(image);
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    m.samplers.push_back(sampler);
    tinygltf::Texture tex;
    tex.source = 0;
    tex.sampler = 0;
    m.textures.push_back(tex);
    return 0;
  }

  void scene() {
    tinygltf::Scene s;
    s.name = "scene";
    s.nodes.push_back(Root);
    for (size_t n = kJointCount; n < m.nodes.size(); ++n)
      s.nodes.push_back(int(n));
    m.scenes.push_back(s);
    m.defaultScene = 0;
    m.buffers[0].data.resize((m.buffers[0].data.size() + 3) / 4 * 4, 0);
  }

  void write(const std::string &path) {
    tinygltf::TinyGLTF writer;
    std::ostringstream os;
    if (!writer.WriteGltfSceneToStream(&m, os, false, true))
      throw Error(path + ": cannot serialise glTF");
    std::string tmp = path + ".tmp";
    {
      std::ofstream f(tmp, std::ios::binary);
      f << os.str();
      if (!f)
        throw Error(path + ": cannot write");
    }
    std::filesystem::rename(tmp, path);
  }
};

std::vector<ClipDef> clips() {
  return {{"walk", 1.0f, 30, [](float t) { return gait(t, 1.0f, 0.0f); }},
          {"run", 0.7f, 21, [](float t) { return gait(t, 1.8f, 12.0f); }},
          {"idle", 3.0f, 30, [](float t) { return idle(t); }}};
}

void addClips(Builder &b) {
  for (const auto &c : clips())
    b.animation(c);
}

} // namespace

namespace rig {

Garment dress() {
  const Part part = outfitParts(0)[0];
  Garment g;
  for (const auto &v : part.vertices) {
    g.bind.push_back(v.p);
    g.joints.push_back(v.j);
    g.weights.push_back(v.w);
  }
  g.indices = part.indices;
  g.pinned = 16 * 33 + 37; // the bodice tube (16 rings of 33) and the skirt's top ring
  return g;
}

double clipPeriod(const std::string &clip) {
  for (const auto &c : clips())
    if (c.name == clip)
      return c.period;
  throw Error("samples: no clip named " + clip);
}

int joint(const std::string &name) {
  for (int j = 0; j < kJointCount; ++j)
    if (name == kJoints[j].name)
      return j;
  throw Error("samples: no joint named " + name);
}

Pose pose(const std::string &clip, double seconds) {
  const double period = clipPeriod(clip);
  const double phase = seconds / period - std::floor(seconds / period);
  samples::Pose p;
  for (const auto &c : clips())
    if (c.name == clip)
      p = c.pose(float(phase));
  Pose out;
  for (int j = 0; j < kJointCount; ++j) {
    const int parent = kJoints[j].parent;
    const glm::vec3 local =
        j == Hips ? p.hips : kJoints[j].head - (parent >= 0 ? kJoints[parent].head : glm::vec3(0));
    glm::mat4 m = glm::mat4_cast(p.rot[j]);
    m[3] = glm::vec4(local, 1);
    out.world.push_back(parent >= 0 ? out.world[size_t(parent)] * m : m);
    glm::mat4 inverseBind(1);
    inverseBind[3] = glm::vec4(-kJoints[j].head, 1);
    out.skin.push_back(out.world.back() * inverseBind);
  }
  return out;
}

} // namespace rig

// The village as an unskinned glTF: one mesh, a primitive per material, one node at the origin.
void writeVillage(const std::string &path) {
  Builder b;
  tinygltf::Mesh mesh;
  mesh.name = "village";
  for (const auto &part : villageParts()) {
    b.material(part.material, part.colour, -1);
    std::vector<float> pos, nrm;
    for (size_t v = 0; v < part.positions.size(); ++v) {
      pos.insert(pos.end(), {part.positions[v].x, part.positions[v].y, part.positions[v].z});
      nrm.insert(nrm.end(), {part.normals[v].x, part.normals[v].y, part.normals[v].z});
    }
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.material = int(b.m.materials.size() - 1);
    const int ab = TINYGLTF_TARGET_ARRAY_BUFFER;
    prim.attributes["POSITION"] =
        b.accessor(pos, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3, ab, true);
    prim.attributes["NORMAL"] =
        b.accessor(nrm, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 3, ab, false);
    prim.indices = b.accessor(part.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                              TINYGLTF_TYPE_SCALAR, 1, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
    mesh.primitives.push_back(prim);
  }
  b.m.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = "village";
  node.mesh = 0;
  b.m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.name = "village";
  scene.nodes = {0};
  b.m.scenes.push_back(scene);
  b.m.defaultScene = 0;
  b.m.buffers[0].data.resize((b.m.buffers[0].data.size() + 3) / 4 * 4, 0);
  b.write(path);
}

// An RGBA8 image as PNG, atomically.
void writeRgbaPng(const std::string &path, uint32_t width, uint32_t height,
                  const std::vector<uint8_t> &rgba) {
  pack::Image image{"", width, height, 4, pack::Image::Pixel::U8, rgba};
  pack::writeFileAtomic(path, images::encodePng(image));
}

void writeSamples(const std::string &dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw Error(dir + ": cannot create directory: " + ec.message());
  {
    Builder b;
    b.skeleton();
    int tex = b.texture();
    const char *names[6] = {"head", "torso", "arms", "hands", "legs", "feet"};
    for (const char *n : names)
      b.material(n, glm::vec4(1), tex);
    b.mesh("body", humanoidParts(), 0);
    addClips(b);
    b.scene();
    b.write(dir + "/" + kFiles[0]);
  }
  const glm::vec4 colours[3][2] = {{{0.55f, 0.10f, 0.15f, 1}, {0, 0, 0, 1}},
                                   {{0.15f, 0.35f, 0.60f, 1}, {0.20f, 0.20f, 0.22f, 1}},
                                   {{0.90f, 0.90f, 0.85f, 1}, {0.25f, 0.22f, 0.18f, 1}}};
  for (int kind = 0; kind < 3; ++kind) {
    Builder b;
    b.skeleton();
    auto parts = outfitParts(kind);
    for (size_t p = 0; p < parts.size(); ++p)
      b.material(parts[p].material, colours[kind][p], -1);
    b.mesh(kind == 0 ? "dress" : kind == 1 ? "jumper_skirt" : "shirt_trousers", parts, 0);
    addClips(b);
    b.scene();
    b.write(dir + "/" + kFiles[size_t(kind) + 1]);
  }
  writeVillage(dir + "/" + kVillageFile);
  writeRgbaPng(dir + "/village_behaviour.png", kVillageCells, kVillageCells, villageBehaviours());
  writeRgbaPng(dir + "/village_callbacks.png", kVillageCells, kVillageCells, villageCallbacks());
}

} // namespace crowd::samples
