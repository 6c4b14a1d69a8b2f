#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/limits.h"
#include "crowd/formats/registry.h"

namespace crowd::pack {

namespace {
constexpr uint32_t kMaxTextureSide = limits::kTextureSide;
constexpr uint64_t kMaxElements = limits::kChunkElements;

// Texture width and height, each in 1..maxSide.
void readSize(ByteReader &r, uint32_t &width, uint32_t &height, uint32_t maxSide) {
  width = r.get<uint32_t>("width");
  height = r.get<uint32_t>("height");
  if (width == 0 || height == 0 || width > maxSide || height > maxSide)
    r.fail("width/height", std::to_string(width) + "x" + std::to_string(height) +
                               " is out of range 1.." + std::to_string(maxSide));
}

void checkFinite(ByteReader &r, const std::vector<float> &v, const char *field) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      r.fail(field, "value " + std::to_string(i) + " is not finite");
}
} // namespace

const char *name(JointEncoding e) {
  switch (e) {
  case JointEncoding::Matrix3x4:
    return "matrix3x4";
  case JointEncoding::QuatTransScale:
    return "quat_trans_scale";
  case JointEncoding::QtsWithMatrices:
    return "quat_trans_scale_with_matrices";
  }
  return "?";
}
const char *name(TexelFormat f) { return f == TexelFormat::RGBA32F ? "rgba32f" : "rgba16f"; }
uint32_t texelsPerJoint(JointEncoding e) { return e == JointEncoding::Matrix3x4 ? 3 : 2; }
uint32_t bytesPerTexel(TexelFormat f) { return f == TexelFormat::RGBA32F ? 16 : 8; }

bool AnimationTexture::isMatrix(uint32_t joint) const {
  return encoding == JointEncoding::Matrix3x4 ||
         std::binary_search(matrixJoints.begin(), matrixJoints.end(), joint);
}

uint32_t AnimationTexture::frameTexels() const {
  return jointCount * texelsPerJoint(encoding) + uint32_t(matrixJoints.size());
}

std::pair<uint32_t, uint32_t> AnimationTexture::texelOf(uint32_t frame, uint32_t joint) const {
  if (framesPerRow == 0) // a pack of joint tracks alone: sample it through runtime/pack_joints.h
    throw Error("the pack has no animation texture (it stores joint tracks alone)");
  // Each matrix joint before `joint` takes one texel more than the encoding's.
  const auto before = std::lower_bound(matrixJoints.begin(), matrixJoints.end(), joint);
  return {(frame % framesPerRow) * frameTexels() + joint * texelsPerJoint(encoding) +
              uint32_t(before - matrixJoints.begin()),
          frame / framesPerRow};
}

std::array<float, 4> AnimationTexture::texel(uint32_t x, uint32_t y) const {
  std::array<float, 4> out{};
  size_t index = (size_t(y) * width + x) * 4;
  if (format == TexelFormat::RGBA32F) {
    std::memcpy(out.data(), texels.data() + index * 4, 16);
  } else {
    uint16_t h[4];
    std::memcpy(h, texels.data() + index * 2, 8);
    for (int i = 0; i < 4; ++i)
      out[i] = halfToFloat(h[i]);
  }
  return out;
}

std::vector<uint8_t> encode(const Provenance &p) {
  ByteWriter w;
  w.putString(p.bakerVersion);
  w.put<uint32_t>(uint32_t(p.settings.size()));
  for (const auto &[k, v] : p.settings) {
    w.putString(k);
    w.putString(v);
  }
  w.put<uint32_t>(uint32_t(p.inputs.size()));
  for (const auto &in : p.inputs) {
    w.putString(in.path);
    w.put<uint64_t>(in.size);
    w.putString(in.hash);
  }
  return w.take();
}

Provenance decodeProvenance(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Provenance p;
  p.bakerVersion = r.getString("baker version");
  uint32_t n = r.get<uint32_t>("settings count");
  for (uint32_t i = 0; i < n; ++i) {
    std::string k = r.getString("setting name");
    p.settings.emplace_back(k, r.getString("setting value"));
  }
  n = r.get<uint32_t>("input count");
  for (uint32_t i = 0; i < n; ++i) {
    InputFile in;
    in.path = r.getString("input path");
    in.size = r.get<uint64_t>("input size");
    in.hash = r.getString("input hash");
    p.inputs.push_back(in);
  }
  r.expectEnd();
  return p;
}

std::vector<uint8_t> encode(const Skeleton &s) {
  ByteWriter w;
  w.put<uint32_t>(uint32_t(s.names.size()));
  for (const auto &n : s.names)
    w.putString(n);
  w.putArray(s.parents);
  w.putArray(s.inverseBind);
  return w.take();
}

Skeleton decodeSkeleton(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Skeleton s;
  uint32_t n = r.get<uint32_t>("joint count");
  if (n == 0 || n > 65535)
    r.fail("joint count", std::to_string(n) + " is out of range 1..65535");
  for (uint32_t i = 0; i < n; ++i)
    s.names.push_back(r.getString("joint name"));
  s.parents = r.getArray<int32_t>("parents", n);
  s.inverseBind = r.getArray<float>("inverse bind matrices", uint64_t(n) * 16);
  if (s.parents.size() != n)
    r.fail("parents", "count differs from joint count");
  if (s.inverseBind.size() != size_t(n) * 16)
    r.fail("inverse bind matrices", "not 16 per joint");
  for (uint32_t i = 0; i < n; ++i)
    if (s.parents[i] < -1 || s.parents[i] >= int32_t(i))
      r.fail("parents", "joint " + std::to_string(i) + " has parent " +
                            std::to_string(s.parents[i]) + " (must be -1 or a lower index)");
  checkFinite(r, s.inverseBind, "inverse bind matrices");
  r.expectEnd();
  return s;
}

std::vector<uint8_t> encode(const std::vector<Clip> &clips) {
  ByteWriter w;
  w.put<uint32_t>(uint32_t(clips.size()));
  for (const auto &c : clips) {
    w.putString(c.name);
    w.put<float>(c.fps);
    w.put<float>(c.startTime);
    w.put<uint32_t>(c.firstFrame);
    w.put<uint32_t>(c.frameCount);
    w.put<uint8_t>(c.loop ? 1 : 0);
  }
  return w.take();
}

std::vector<Clip> decodeClips(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  uint32_t n = r.get<uint32_t>("clip count");
  if (n > 100000)
    r.fail("clip count", std::to_string(n) + " is absurd");
  std::vector<Clip> clips;
  for (uint32_t i = 0; i < n; ++i) {
    Clip c;
    c.name = r.getString("clip name");
    c.fps = r.get<float>("fps");
    c.startTime = r.get<float>("start time");
    c.firstFrame = r.get<uint32_t>("first frame");
    c.frameCount = r.get<uint32_t>("frame count");
    uint8_t loop = r.get<uint8_t>("loop");
    if (loop > 1)
      r.fail("loop", "flag is " + std::to_string(loop));
    c.loop = loop == 1;
    if (!(std::isfinite(c.fps) && c.fps > 0 && c.fps <= 10000))
      r.fail("fps", "clip '" + c.name + "' has fps " + std::to_string(c.fps));
    if (!std::isfinite(c.startTime))
      r.fail("start time", "not finite");
    if (c.frameCount == 0)
      r.fail("frame count", "clip '" + c.name + "' has no frames");
    clips.push_back(c);
  }
  r.expectEnd();
  return clips;
}

std::vector<uint8_t> encode(const AnimationTexture &t) {
  ByteWriter w;
  w.put<uint32_t>(uint32_t(t.encoding));
  w.put<uint32_t>(uint32_t(t.format));
  w.put<uint32_t>(t.width);
  w.put<uint32_t>(t.height);
  w.put<uint32_t>(t.jointCount);
  w.put<uint32_t>(t.framesPerRow);
  w.put<uint32_t>(t.frameCount);
  if (t.encoding == JointEncoding::QtsWithMatrices)
    w.putArray(t.matrixJoints);
  w.putArray(t.texels);
  return w.take();
}

AnimationTexture decodeAnimationTexture(std::span<const uint8_t> bytes,
                                        const std::string &context) {
  ByteReader r(bytes, context);
  AnimationTexture t;
  uint32_t enc = r.get<uint32_t>("encoding");
  if (enc > 2)
    r.fail("encoding", "unknown joint encoding " + std::to_string(enc));
  t.encoding = JointEncoding(enc);
  uint32_t fmt = r.get<uint32_t>("texel format");
  if (fmt > 1)
    r.fail("texel format", "unknown texel format " + std::to_string(fmt));
  t.format = TexelFormat(fmt);
  readSize(r, t.width, t.height, kMaxTextureSide);
  t.jointCount = r.get<uint32_t>("joint count");
  t.framesPerRow = r.get<uint32_t>("frames per row");
  t.frameCount = r.get<uint32_t>("frame count");
  if (t.jointCount == 0 || t.framesPerRow == 0 || t.frameCount == 0)
    r.fail("joint count/frames", "must be non-zero");
  if (t.encoding == JointEncoding::QtsWithMatrices) {
    t.matrixJoints = r.getArray<uint32_t>("matrix joints", t.jointCount);
    if (t.matrixJoints.empty())
      r.fail("matrix joints", "none listed (the encoding is quat_trans_scale then)");
    for (size_t i = 0; i < t.matrixJoints.size(); ++i)
      if (t.matrixJoints[i] >= t.jointCount || (i && t.matrixJoints[i] <= t.matrixJoints[i - 1]))
        r.fail("matrix joints",
               "joint " + std::to_string(t.matrixJoints[i]) + " is out of range or not ascending");
  }
  if (uint64_t(t.framesPerRow) * t.frameTexels() > t.width)
    r.fail("frames per row", "frames do not fit in the texture width");
  if (uint64_t(t.framesPerRow) * t.height < t.frameCount)
    r.fail("frame count", std::to_string(t.frameCount) + " frames do not fit in " +
                              std::to_string(t.height) + " rows");
  uint64_t expected = uint64_t(t.width) * t.height * bytesPerTexel(t.format);
  t.texels = r.getArray<uint8_t>("texels", expected);
  if (t.texels.size() != expected)
    r.fail("texels",
           std::to_string(t.texels.size()) + " bytes, expected " + std::to_string(expected));
  for (uint32_t y = 0; y < t.height; ++y)
    for (uint32_t x = 0; x < t.width; ++x)
      for (float v : t.texel(x, y))
        if (!std::isfinite(v))
          r.fail("texels",
                 "texel (" + std::to_string(x) + ", " + std::to_string(y) + ") is not finite");
  r.expectEnd();
  return t;
}

std::vector<uint8_t> encode(const SkinTexture &t) {
  ByteWriter w;
  w.put<uint32_t>(t.width);
  w.put<uint32_t>(t.height);
  w.put<uint32_t>(t.vertexCount);
  w.putArray(t.texels);
  return w.take();
}

SkinTexture decodeSkinTexture(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  SkinTexture t;
  readSize(r, t.width, t.height, kMaxTextureSide);
  t.vertexCount = r.get<uint32_t>("vertex count");
  if (t.width % 2 != 0)
    r.fail("width", std::to_string(t.width) + " is odd: a vertex's two texels share a row");
  if (uint64_t(t.vertexCount) * 2 > uint64_t(t.width) * t.height)
    r.fail("vertex count", "does not fit in the texture");
  uint64_t expected = uint64_t(t.width) * t.height * 4;
  t.texels = r.getArray<float>("texels", expected);
  if (t.texels.size() != expected)
    r.fail("texels", "size does not match width x height");
  checkFinite(r, t.texels, "texels");
  for (uint32_t v = 0; v < t.vertexCount; ++v) {
    const float *ids = &t.texels[size_t(v) * 8];
    const float *w = ids + 4;
    for (int k = 0; k < 4; ++k) {
      if (ids[k] < 0 || ids[k] != std::floor(ids[k]))
        r.fail("texels", "vertex " + std::to_string(v) + " has joint id " + std::to_string(ids[k]));
      if (w[k] < 0 || w[k] > 1)
        r.fail("texels", "vertex " + std::to_string(v) + " has weight " + std::to_string(w[k]));
    }
  }
  r.expectEnd();
  return t;
}

std::vector<uint8_t> encode(const Mesh &m) {
  ByteWriter w;
  w.putArray(m.positions);
  w.putArray(m.normals);
  w.putArray(m.uvs);
  w.putArray(m.indices);
  w.put<uint32_t>(uint32_t(m.subMeshes.size()));
  for (const auto &s : m.subMeshes) {
    w.putString(s.name);
    w.put<uint32_t>(s.firstIndex);
    w.put<uint32_t>(s.indexCount);
  }
  for (float f : m.boundingSphere)
    w.put<float>(f);
  return w.take();
}

Mesh decodeMesh(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Mesh m;
  m.positions = r.getArray<float>("positions", kMaxElements);
  m.normals = r.getArray<float>("normals", kMaxElements);
  m.uvs = r.getArray<float>("uvs", kMaxElements);
  m.indices = r.getArray<uint32_t>("indices", kMaxElements);
  size_t vc = m.positions.size() / 3;
  if (m.positions.size() % 3 != 0 || vc == 0)
    r.fail("positions", "not a non-empty xyz array");
  if (m.normals.size() != m.positions.size())
    r.fail("normals", "count differs from positions");
  if (!m.uvs.empty() && m.uvs.size() != vc * 2)
    r.fail("uvs", "count differs from vertices");
  if (m.indices.empty() || m.indices.size() % 3 != 0)
    r.fail("indices", "not a non-empty triangle list");
  for (size_t i = 0; i < m.indices.size(); ++i)
    if (m.indices[i] >= vc)
      r.fail("indices", "index " + std::to_string(i) + " = " + std::to_string(m.indices[i]) +
                            " >= vertex count " + std::to_string(vc));
  checkFinite(r, m.positions, "positions");
  checkFinite(r, m.normals, "normals");
  checkFinite(r, m.uvs, "uvs");
  uint32_t n = r.get<uint32_t>("sub-mesh count");
  if (n == 0 || n > 65535)
    r.fail("sub-mesh count", std::to_string(n) + " is out of range");
  for (uint32_t i = 0; i < n; ++i) {
    SubMesh s;
    s.name = r.getString("sub-mesh name");
    s.firstIndex = r.get<uint32_t>("sub-mesh first index");
    s.indexCount = r.get<uint32_t>("sub-mesh index count");
    if (s.firstIndex % 3 != 0 || s.indexCount % 3 != 0 ||
        uint64_t(s.firstIndex) + s.indexCount > m.indices.size())
      r.fail("sub-mesh range", "sub-mesh '" + s.name + "' has a bad index range");
    m.subMeshes.push_back(s);
  }
  for (float &f : m.boundingSphere)
    f = r.get<float>("bounding sphere");
  if (!(m.boundingSphere[3] >= 0) || !std::isfinite(m.boundingSphere[0] + m.boundingSphere[1] +
                                                    m.boundingSphere[2] + m.boundingSphere[3]))
    r.fail("bounding sphere", "not finite or negative radius");
  r.expectEnd();
  return m;
}

std::vector<uint8_t> encode(const Texture &t) {
  ByteWriter w;
  w.put<uint32_t>(t.width);
  w.put<uint32_t>(t.height);
  w.putArray(t.rgba);
  return w.take();
}

Texture decodeTexture(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Texture t;
  readSize(r, t.width, t.height, 16384);
  uint64_t expected = uint64_t(t.width) * t.height * 4;
  t.rgba = r.getArray<uint8_t>("texels", expected);
  if (t.rgba.size() != expected)
    r.fail("texels", "size does not match width x height x 4");
  r.expectEnd();
  return t;
}

std::vector<uint8_t> encode(const Lod &l) {
  ByteWriter w;
  w.put<uint32_t>(l.floorVertices);
  w.putArray(l.collapse);
  w.putArray(l.error);
  w.putArray(l.triangleCounts);
  return w.take();
}

Lod decodeLod(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  Lod l;
  l.floorVertices = r.get<uint32_t>("floor vertices");
  l.collapse = r.getArray<uint32_t>("collapse", kMaxElements);
  l.error = r.getArray<float>("error", kMaxElements);
  l.triangleCounts = r.getArray<uint32_t>("triangle counts", kMaxElements);
  const size_t n = l.collapse.size();
  if (n == 0 || l.floorVertices == 0 || l.floorVertices > n)
    r.fail("floor vertices", std::to_string(l.floorVertices) + " of " + std::to_string(n));
  for (size_t k = 0; k < n; ++k)
    if (k < l.floorVertices ? l.collapse[k] != k : l.collapse[k] >= k)
      r.fail("collapse",
             "vertex " + std::to_string(k) + " collapses into " + std::to_string(l.collapse[k]));
  if (l.error.size() != n)
    r.fail("error", "count differs from the collapse map");
  checkFinite(r, l.error, "error");
  if (l.triangleCounts.empty() || l.triangleCounts.size() % (n + 1) != 0)
    r.fail("triangle counts", "not whole rows of vertex count + 1");
  for (size_t i = 0; i < l.triangleCounts.size(); ++i)
    if (i % (n + 1) != 0 && l.triangleCounts[i] < l.triangleCounts[i - 1])
      r.fail("triangle counts", "decrease at entry " + std::to_string(i));
  r.expectEnd();
  return l;
}

AnimationPack loadAnimationPack(const Reader &reader) {
  auto ctx = [&](uint32_t type) {
    return "pack '" + reader.name() + "', chunk " + fourccName(type);
  };
  auto get = [&](uint32_t type) { return reader.payload(reader.require(type)); };
  // Chunk types this build does not know are left to `verify`: the player skips them.
  for (size_t i = 0; i < reader.chunks().size(); ++i)
    if (findCodec(reader.chunks()[i].type))
      codecOf(reader.chunks()[i], chunkContext(reader, i));
  AnimationPack p;
  p.provenance = decodeProvenance(get(kProvenance), ctx(kProvenance));
  p.skeleton = decodeSkeleton(get(kSkeleton), ctx(kSkeleton));
  p.clips = decodeClips(get(kClips), ctx(kClips));
  const ChunkEntry *tracks = reader.find(kJointTracks);
  if (reader.find(kAnimationTexture) || !tracks) {
    p.animation = decodeAnimationTexture(get(kAnimationTexture), ctx(kAnimationTexture));
  } else { // joint tracks alone: the clip table's frames stand for the texture's
    p.animation.jointCount = p.skeleton.jointCount();
    for (const auto &c : p.clips)
      p.animation.frameCount = uint32_t(std::min<uint64_t>(
          std::max<uint64_t>(p.animation.frameCount, uint64_t(c.firstFrame) + c.frameCount),
          UINT32_MAX));
  }
  p.skin = decodeSkinTexture(get(kSkinTexture), ctx(kSkinTexture));
  p.mesh = decodeMesh(get(kMesh), ctx(kMesh));
  if (const ChunkEntry *texture = reader.find(kDiffuseTexture)) {
    p.diffuse = decodeTexture(reader.payload(*texture), ctx(kDiffuseTexture));
    if (p.mesh.uvs.empty())
      throw Error(ctx(kDiffuseTexture) + ": the mesh has no UVs to map the texture with");
  }
  if (const ChunkEntry *lod = reader.find(kLod)) {
    p.lod = decodeLod(reader.payload(*lod), ctx(kLod));
    const size_t n = p.mesh.vertexCount();
    if (p.lod->collapse.size() != n ||
        p.lod->triangleCounts.size() != p.mesh.subMeshes.size() * (n + 1))
      throw Error(ctx(kLod) + ": sized for another mesh (" +
                  std::to_string(p.lod->collapse.size()) + " vertices, the mesh has " +
                  std::to_string(n) + ")");
    for (size_t s = 0; s < p.mesh.subMeshes.size(); ++s)
      if (p.lod->triangleCount(s, uint32_t(n)) != p.mesh.subMeshes[s].indexCount / 3)
        throw Error(ctx(kLod) + ", field 'triangle counts': sub-mesh '" + p.mesh.subMeshes[s].name +
                    "' does not end at its triangle count");
  }
  if (const ChunkEntry *outfits = reader.find(kOutfits)) {
    p.outfits = decodeOutfits(reader.payload(*outfits), ctx(kOutfits));
    checkOutfits(*p.outfits, p.mesh, ctx(kOutfits));
  }
  if (const ChunkEntry *sources = reader.find(kSourceMap)) {
    p.sources = decodeSourceMap(reader.payload(*sources), ctx(kSourceMap));
    if (p.sources->vertexCount() != p.mesh.vertexCount())
      throw Error(ctx(kSourceMap) + ": sized for another mesh (" +
                  std::to_string(p.sources->vertexCount()) + " vertices, the mesh has " +
                  std::to_string(p.mesh.vertexCount()) + ")");
  }
  if (const ChunkEntry *looks = reader.find(kLooks)) {
    p.looks = decodeLooks(reader.payload(*looks), ctx(kLooks));
    if (p.looks->textured.size() != p.mesh.subMeshes.size())
      throw Error(ctx(kLooks) + ": " + std::to_string(p.looks->textured.size()) +
                  " sub-meshes described, the mesh has " + std::to_string(p.mesh.subMeshes.size()));
  }
  if (const ChunkEntry *morphs = reader.find(kMorphs)) {
    p.morphs = decodeMorphs(reader.payload(*morphs), ctx(kMorphs));
    if (p.morphs->vertexCount != p.mesh.vertexCount() ||
        p.morphs->frameCount() != p.animation.frameCount)
      throw Error(ctx(kMorphs) + ": sized for another mesh or animation (" +
                  std::to_string(p.morphs->vertexCount) + " vertices and " +
                  std::to_string(p.morphs->frameCount()) + " frames; the mesh has " +
                  std::to_string(p.mesh.vertexCount()) +
                  (p.hasTexture() ? ", the animation texture " : ", the clip table ") +
                  std::to_string(p.animation.frameCount) + ")");
  }
  if (tracks) {
    p.tracks = decodeJointTracks(reader.payload(*tracks), ctx(kJointTracks));
    if (p.tracks->skeleton.jointNodes.size() != p.skeleton.jointCount())
      throw Error(ctx(kJointTracks) +
                  ", field 'joint count': " + std::to_string(p.tracks->skeleton.jointNodes.size()) +
                  " but the skeleton has " + std::to_string(p.skeleton.jointCount()));
    if (p.tracks->clips.size() != p.clips.size())
      throw Error(ctx(kJointTracks) +
                  ", field 'clip count': " + std::to_string(p.tracks->clips.size()) +
                  " but the clip table has " + std::to_string(p.clips.size()));
    for (size_t i = 0; i < p.clips.size(); ++i)
      if (p.tracks->clips[i].name != p.clips[i].name)
        throw Error(ctx(kJointTracks) + ", field 'clip name': clip " + std::to_string(i) + " is '" +
                    p.tracks->clips[i].name + "', the clip table's '" + p.clips[i].name + "'");
  }
  if (p.animation.jointCount != p.skeleton.jointCount())
    throw Error(ctx(kAnimationTexture) +
                ", field 'joint count': " + std::to_string(p.animation.jointCount) +
                " but the skeleton has " + std::to_string(p.skeleton.jointCount()));
  for (const auto &c : p.clips)
    if (uint64_t(c.firstFrame) + c.frameCount > p.animation.frameCount)
      throw Error(ctx(kClips) + ", field 'first frame': clip '" + c.name +
                  "' runs past the texture's " + std::to_string(p.animation.frameCount) +
                  " frames");
  // Every frame belongs to a clip (a pack without clips has nothing a consumer may play, and
  // export, pose and the player index its first clip).
  std::vector<std::pair<uint64_t, uint64_t>> spans; // [first, end) of each clip's frames
  for (const auto &c : p.clips)
    spans.push_back({c.firstFrame, uint64_t(c.firstFrame) + c.frameCount});
  std::sort(spans.begin(), spans.end());
  uint64_t covered = 0;
  for (const auto &[first, end] : spans) {
    if (first > covered)
      break;
    covered = std::max(covered, end);
  }
  if (covered < p.animation.frameCount)
    throw Error(ctx(kClips) + ", field 'clip count': " +
                (p.clips.empty() ? std::string("no clips, ")
                                 : std::to_string(p.clips.size()) + " clips, ") +
                "and frame " + std::to_string(covered) + " of the texture's " +
                std::to_string(p.animation.frameCount) + " belongs to none");
  if (p.skin.vertexCount != p.mesh.vertexCount())
    throw Error(ctx(kSkinTexture) +
                ", field 'vertex count': " + std::to_string(p.skin.vertexCount) +
                " but the mesh has " + std::to_string(p.mesh.vertexCount()));
  for (uint32_t v = 0; v < p.skin.vertexCount; ++v)
    for (int k = 0; k < 4; ++k) {
      const float id = p.skin.texels[size_t(v) * 8 + k]; // a whole joint index, as a float
      if (!(id >= 0 && id < float(p.skeleton.jointCount()) && id == std::floor(id))) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", double(id));
        throw Error(ctx(kSkinTexture) + ", field 'texels': vertex " + std::to_string(v) +
                    " uses joint " + text + " of " + std::to_string(p.skeleton.jointCount()));
      }
    }
  return p;
}

std::vector<uint8_t> packBytes(const AnimationPack &p) {
  Writer w;
  w.add(kProvenance, kChunkVersion, encode(p.provenance));
  w.add(kSkeleton, kChunkVersion, encode(p.skeleton));
  w.add(kClips, kChunkVersion, encode(p.clips));
  if (!p.hasTexture() && !p.tracks)
    throw Error("the pack stores neither an animation texture nor joint tracks");
  if (p.hasTexture())
    w.add(kAnimationTexture, kChunkVersion, encode(p.animation));
  w.add(kSkinTexture, kChunkVersion, encode(p.skin));
  w.add(kMesh, kChunkVersion, encode(p.mesh));
  if (p.diffuse)
    w.add(kDiffuseTexture, kChunkVersion, encode(*p.diffuse));
  if (p.lod)
    w.add(kLod, kChunkVersion, encode(*p.lod));
  if (p.outfits)
    w.add(kOutfits, kChunkVersion, encode(*p.outfits));
  if (p.sources)
    w.add(kSourceMap, kChunkVersion, encode(*p.sources));
  if (p.morphs)
    w.add(kMorphs, kChunkVersion, encode(*p.morphs));
  if (p.looks)
    w.add(kLooks, kChunkVersion, encode(*p.looks));
  if (p.tracks)
    w.add(kJointTracks, kChunkVersion, encode(*p.tracks));
  return w.bytes();
}

void writePack(const AnimationPack &p, const std::string &path) {
  writeFileAtomic(path, packBytes(p));
}

uint16_t floatToHalf(float f) {
  uint32_t x;
  std::memcpy(&x, &f, 4);
  uint32_t sign = (x >> 16) & 0x8000u;
  uint32_t mag = x & 0x7fffffffu;
  if (mag >= 0x7f800000u)
    return uint16_t(sign | 0x7c00u | (mag > 0x7f800000u ? 0x200u : 0));
  if (mag >= 0x477ff000u)
    return uint16_t(sign | 0x7c00u);    // rounds to >= 65520: infinity
  if (mag < 0x38800000u) {              // subnormal half (or zero)
    uint32_t shift = 126 - (mag >> 23); // the 24-bit mantissa's shift to half subnormal units
    if (shift > 24)
      return uint16_t(sign); // below half the smallest subnormal: zero
    uint32_t mant = (mag & 0x7fffffu) | 0x800000u;
    uint32_t half = mant >> shift;
    uint32_t rem = mant & ((1u << shift) - 1);
    uint32_t mid = 1u << (shift - 1);
    if (rem > mid || (rem == mid && (half & 1)))
      ++half;
    return uint16_t(sign | half);
  }
  uint32_t half = ((mag - 0x38000000u) >> 13);
  uint32_t rem = mag & 0x1fffu;
  if (rem > 0x1000u || (rem == 0x1000u && (half & 1)))
    ++half;
  return uint16_t(sign | half);
}

float halfToFloat(uint16_t h) {
  uint32_t sign = uint32_t(h & 0x8000u) << 16;
  uint32_t exp = (h >> 10) & 0x1fu;
  uint32_t mant = h & 0x3ffu;
  uint32_t x;
  if (exp == 0) {
    if (mant == 0) {
      x = sign;
    } else { // subnormal: normalise
      int e = -1;
      do {
        ++e;
        mant <<= 1;
      } while (!(mant & 0x400u));
      x = sign | uint32_t(127 - 15 - e) << 23 | (mant & 0x3ffu) << 13;
    }
  } else if (exp == 31) {
    x = sign | 0x7f800000u | mant << 13;
  } else {
    x = sign | (exp + 112) << 23 | mant << 13;
  }
  float f;
  std::memcpy(&f, &x, 4);
  return f;
}

} // namespace crowd::pack
