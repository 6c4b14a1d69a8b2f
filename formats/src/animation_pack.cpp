// A whole animation pack: every chunk decoded and cross-checked, and written.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/limits.h"
#include "crowd/formats/registry.h"

namespace crowd::pack {

using namespace checks;

namespace {

// The animation texture, the clip table and the skin texture against each other and the
// skeleton: joint counts, every clip inside the texture and every frame in a clip, one skin
// entry per mesh vertex naming real joints.
void checkFramesAndSkin(const AnimationPack &p, const std::string &pack) {
  auto ctx = [&](uint32_t type) { return "pack '" + pack + "', chunk " + fourccName(type); };
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
}

} // namespace

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
    p.tracks = decodeJointTracks(reader.payload(*tracks), ctx(kJointTracks), tracks->version);
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
  checkFramesAndSkin(p, reader.name());
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
    w.add(kJointTracks, kJointTracksVersion, encode(*p.tracks));
  return w.bytes();
}

void writePack(const AnimationPack &p, const std::string &path) {
  writeFileAtomic(path, packBytes(p));
}

} // namespace crowd::pack
